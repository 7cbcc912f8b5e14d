#version 450
// Winograd F(6x6, 3x3) input transform of a bordered activation, 8 channels per invocation in 32-byte stores (needs
// shaderInt64): winograd_input_activation.glsl, winograd_input_body.glsl.
#define WINOGRAD_WIDE 1
#define WINOGRAD_TILE 6
#include "winograd_input_activation.glsl"
