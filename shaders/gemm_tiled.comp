#version 450
// C = alpha * A * op(B) + bias (+ C) (+ ReLU) on texel-aligned operands, 4 rows x 8 columns of C per invocation:
// the tile for GPUs. The kernel and why it is shaped so: gemm_tiled_body.glsl.
#define ROWS 4
#define COLS 8
#include "gemm_tiled_body.glsl"
