#version 450
// Winograd F(4x4, 3x3) output transform + bias (+ ReLU): winograd_output_body.glsl.
#define WINOGRAD_TILE 4
#include "winograd_output_body.glsl"
