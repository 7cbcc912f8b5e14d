#version 450
// 1x1 convolution (a per-pixel matrix product) + bias (+ ReLU). Weights in the "o4" layout [O/4][I] (vec4 = four
// output channels). Each invocation computes 4 output channels x 4 pixels (16 accumulation chains); the input
// and output may carry a zero border (tensor.glsl).
#include "precision.glsl"
#include "tensor.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Input { sfloat src[]; };
layout(std430, binding = 1) readonly buffer Weights { wvec4 weights[]; };
layout(std430, binding = 2) readonly buffer Bias { vec4 bias[]; };
layout(std430, binding = 3) writeonly buffer Output { sfloat dst[]; };

#include "push/conv1x1.h"

const uint kPixels = 4;

void main() {
  const uint x0 = gl_GlobalInvocationID.x * kPixels;
  const uint y = gl_GlobalInvocationID.y;
  const uint ob = gl_GlobalInvocationID.z;
  if (x0 >= p.width || y >= p.height) return;

  const uint in_plane = plane_size(p.height, p.width, p.in_pad);
  const uint base = chw_index(0u, y, x0, p.height, p.width, p.in_pad);
  // Pixels past the right edge re-read the last valid pixel: no branch in the loop, results discarded.
  const uint last = p.width - 1u - x0;
  const uint d1 = min(1u, last), d2 = min(2u, last), d3 = min(3u, last);
  vec4 acc0 = bias[ob], acc1 = acc0, acc2 = acc0, acc3 = acc0;
  uint w_index = ob * p.in_channels;
  for (uint ic = 0; ic < p.in_channels; ++ic) {
    const uint r = base + ic * in_plane;
    const avec4 w = avec4(weights[w_index + ic]);
    acc0 += vec4(w * afloat(src[r]));
    acc1 += vec4(w * afloat(src[r + d1]));
    acc2 += vec4(w * afloat(src[r + d2]));
    acc3 += vec4(w * afloat(src[r + d3]));
  }
  if (p.relu != 0u) {
    acc0 = max(acc0, 0.0);
    acc1 = max(acc1, 0.0);
    acc2 = max(acc2, 0.0);
    acc3 = max(acc3, 0.0);
  }
  const vec4 results[4] = vec4[4](acc0, acc1, acc2, acc3);
  const uint out_plane = plane_size(p.height, p.width, p.out_pad);
  for (uint i = 0; i < kPixels; ++i) {
    const uint x = x0 + i;
    if (x >= p.width) break;
    const uint o = chw_index(ob * 4u, y, x, p.height, p.width, p.out_pad);
    for (uint k = 0; k < 4u; ++k)
      if (ob * 4u + k < p.out_channels) dst[o + k * out_plane] = sfloat(results[i][k]);
  }
}
