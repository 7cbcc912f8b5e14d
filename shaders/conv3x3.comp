#version 450
// 3x3 convolution, stride 1, pad 1, + bias (+ ReLU). Weights in the "o4" layout [O/4][I][9] (vec4 = four
// output channels). Each invocation computes 4 output channels x 3 adjacent pixels: 12 independent
// accumulation chains, which is what keeps CPU drivers (lavapipe) near their FMA peak and GPUs busy.
// The input has a 1-pixel zero border (tensor.glsl), so the loop has no bounds checks.
#include "precision.glsl"
#include "tensor.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Input { sfloat src[]; };
layout(std430, binding = 1) readonly buffer Weights { wvec4 weights[]; };
layout(std430, binding = 2) readonly buffer Bias { vec4 bias[]; };
layout(std430, binding = 3) writeonly buffer Output { sfloat dst[]; };

#include "push/conv3x3.h"

const uint kPixels = 3;

void main() {
  const uint x0 = gl_GlobalInvocationID.x * kPixels;
  const uint y = gl_GlobalInvocationID.y;
  const uint ob = gl_GlobalInvocationID.z;  // block of 4 output channels
  if (x0 >= p.width || y >= p.height) return;

  const uint row = row_stride(p.width, 1u);
  const uint plane = plane_size(p.height, p.width, 1u);
  const uint last_x = p.width + 1u;  // rightmost readable column of a padded row
  vec4 acc0 = bias[ob], acc1 = acc0, acc2 = acc0;

  uint w_index = ob * p.in_channels * 9u;
  uint base = y * row + x0;  // padded (y - 1 + 1, x0 - 1 + 1)
  for (uint ic = 0; ic < p.in_channels; ++ic, base += plane) {
#ifdef VKVO_FP16_MATH
    avec4 part0 = avec4(0), part1 = avec4(0), part2 = avec4(0);
#define ACC0 part0
#define ACC1 part1
#define ACC2 part2
#else
#define ACC0 acc0
#define ACC1 acc1
#define ACC2 acc2
#endif
    for (uint ky = 0; ky < 3u; ++ky) {
      const uint r = base + ky * row;
      const uint rx = r - x0;
      const afloat v0 = afloat(src[r]);
      const afloat v1 = afloat(src[r + 1u]);
      const afloat v2 = afloat(src[rx + min(x0 + 2u, last_x)]);
      const afloat v3 = afloat(src[rx + min(x0 + 3u, last_x)]);
      const afloat v4 = afloat(src[rx + min(x0 + 4u, last_x)]);
      const avec4 w0 = avec4(weights[w_index + 0u]);
      const avec4 w1 = avec4(weights[w_index + 1u]);
      const avec4 w2 = avec4(weights[w_index + 2u]);
      w_index += 3u;
      ACC0 += w0 * v0 + w1 * v1 + w2 * v2;
      ACC1 += w0 * v1 + w1 * v2 + w2 * v3;
      ACC2 += w0 * v2 + w1 * v3 + w2 * v4;
    }
#ifdef VKVO_FP16_MATH
    acc0 += vec4(part0);
    acc1 += vec4(part1);
    acc2 += vec4(part2);
#endif
  }
  if (p.relu != 0u) {
    acc0 = max(acc0, 0.0);
    acc1 = max(acc1, 0.0);
    acc2 = max(acc2, 0.0);
  }
  const vec4 results[3] = vec4[3](acc0, acc1, acc2);
  const uint out_plane = plane_size(p.height, p.width, p.out_pad);
  for (uint i = 0; i < kPixels; ++i) {
    const uint x = x0 + i;
    if (x >= p.width) break;
    const uint o = chw_index(ob * 4u, y, x, p.height, p.width, p.out_pad);
    for (uint k = 0; k < 4u; ++k)
      if (ob * 4u + k < p.out_channels) dst[o + k * out_plane] = sfloat(results[i][k]);
  }
}
