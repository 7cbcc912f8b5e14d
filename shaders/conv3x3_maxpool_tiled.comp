#version 450
// 3x3 convolution + bias (+ ReLU) followed by a 2x2 max-pool, in one pass: conv3x3_tiled's kernel with 4 output
// rows per invocation, storing the pooled 2 x 2 block of its 4 x 4 pixels. SuperPoint pools after conv1b, conv2b
// and conv3b: fused, the full-resolution activation is never written (a quarter of the stores, which lavapipe
// makes one lane at a time) nor read back by a separate pool pass.
//
// Push constants as conv3x3_tiled: height and width are the convolution's; out_pad is the pooled output's border.
#define ROWS 4
#define VKVO_CONV3X3_MAXPOOL 1
#include "conv3x3_tiled_body.glsl"
