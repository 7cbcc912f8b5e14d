#version 450
// Winograd F(4x4, 3x3) input transform of a bordered activation: winograd_input_activation.glsl.
#define WINOGRAD_TILE 4
#include "winograd_input_activation.glsl"
