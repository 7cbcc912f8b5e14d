#version 450
// 3x3 convolution, stride 1, pad 1, + bias (+ ReLU): 8 output channels x 4 pixels x 3 rows per invocation,
// input and weights read through uniform texel buffers. The kernel and why it is shaped so: conv3x3_tiled_body.glsl.
#include "conv3x3_tiled_body.glsl"
