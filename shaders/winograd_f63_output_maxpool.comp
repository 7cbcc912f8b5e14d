#version 450
// Winograd F(6x6, 3x3) output transform + bias (+ ReLU) + 2x2 max-pool: winograd_output_body.glsl. SuperPoint
// pools after conv1b, conv2b and conv3b; fused here, the full-resolution activation is never stored.
#define WINOGRAD_TILE 6
#define VKVO_WINOGRAD_MAXPOOL 1
#include "winograd_output_body.glsl"
