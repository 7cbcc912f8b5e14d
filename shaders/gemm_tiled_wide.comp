#version 450
// C = alpha * A * op(B) + bias (+ C) (+ ReLU) on texel-aligned operands, 8 rows x 16 columns of C per
// invocation: the tile for CPU drivers, which fetch A's texels fewer times per multiply-add this way. The kernel
// and why it is shaped so: gemm_tiled_body.glsl.
#define ROWS 8
#define COLS 16
#include "gemm_tiled_body.glsl"
