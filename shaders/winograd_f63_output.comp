#version 450
// Winograd F(6x6, 3x3) output transform + bias (+ ReLU): winograd_output_body.glsl.
#define WINOGRAD_TILE 6
#include "winograd_output_body.glsl"
