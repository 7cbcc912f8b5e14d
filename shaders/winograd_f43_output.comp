#version 450
// Winograd F(4x4, 3x3) output transform + bias (+ ReLU): winograd_f43_output_body.glsl.
#include "winograd_f43_output_body.glsl"
