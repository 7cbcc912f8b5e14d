#version 450
// Winograd F(6x6, 3x3) input transform of a bordered activation: winograd_input_activation.glsl.
#define WINOGRAD_TILE 6
#include "winograd_input_activation.glsl"
