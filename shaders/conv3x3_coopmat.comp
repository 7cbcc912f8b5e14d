#version 450
// 3x3 convolution, stride 1, pad 1, + bias (+ ReLU) on tensor cores, as an implicit GEMM (include/coopmat_tile.glsl):
// out (O x H*W) = W (O x 9I) * patches (9I x H*W), the patch matrix read straight from the bordered input
// (tensor.glsl) as the tiles are staged, never stored. Weights in conv3x3.comp's "o4" layout [O/4][I][9] (vec4 =
// four output channels), bias fp32 padded to 4, push/conv3x3.h: a drop-in for conv3x3.comp where
// DeviceProfile::cooperative_matrix.
#include "precision.glsl"
#include "tensor.glsl"
#include "push/conv3x3.h"

layout(std430, binding = 0) readonly buffer Input { sfloat src[]; };
layout(std430, binding = 1) readonly buffer Weights { wvec4 weights[]; };
layout(std430, binding = 2) readonly buffer Bias { float bias[]; };
layout(std430, binding = 3) writeonly buffer Output { sfloat dst[]; };

// Row o, column k = 9 * input channel + 3 * ky + kx of the weight matrix.
float16_t tile_a(uint o, uint k) { return float16_t(weights[(o / 4u) * p.in_channels * 9u + k][o % 4u]); }

// Row k, column y * W + x of the patch matrix: input (k / 9, y + ky - 1, x + kx - 1), inside the border.
float16_t tile_b(uint k, uint pixel) {
  const uint channel = k / 9u, tap = k % 9u;
  const uint y = pixel / p.width + tap / 3u, x = pixel % p.width + tap % 3u;
  return float16_t(src[channel * plane_size(p.height, p.width, 1u) + y * row_stride(p.width, 1u) + x]);
}

void tile_store(uint o, uint pixel, float value) {
  float x = value + bias[o];
  if (p.relu != 0u) x = max(x, 0.0);
  dst[chw_index(o, pixel / p.width, pixel % p.width, p.height, p.width, p.out_pad)] = sfloat(x);
}

#include "coopmat_tile.glsl"

void main() { coopmat_tile(p.out_channels, p.height * p.width, p.in_channels * 9u); }
