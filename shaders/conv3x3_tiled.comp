#version 450
// 3x3 convolution, stride 1, pad 1, + bias (+ ReLU), the input and the weights read through uniform texel buffers.
// Weights "o4" ([O/4][I][9] vec4) and activations (tensor.glsl) as conv3x3.comp. Each invocation computes 8 output
// channels x 4 adjacent pixels x ROWS rows; with VKVO_CONV3X3_MAXPOOL it stores the 2x2 max-pool of its block
// instead (the shader table: conv3x3_tiled, 3 rows; conv3x3_maxpool_tiled, 4 rows).
//
// Why so: lavapipe fetches texels with vector gathers where it loads storage buffers one lane at a time, and a
// fetch costs the same whatever the format, so the input is read 4 pixels per texel (rows padded to whole texels)
// and the weights, the same texels in every lane, are fetched directly (a subgroup broadcast is a scalar loop over
// the lanes there; on GPUs a workgroup-uniform fetch is served once from the cache). Each fetch is a call that
// clobbers the vector registers, so per input channel every fetch comes first and then the arithmetic, each
// output's 9 taps summed before its accumulator (on the stack) is touched. Loops are unrolled: an accumulator array
// indexed by a variable becomes memory with masked stores. Figures: docs/performance-history.md, "Tiled 3x3
// convolution".
//
// Out-of-range pixels read clamped addresses and skip the store.
#include "texel_buffer.glsl"
#extension GL_EXT_control_flow_attributes : require
#include "precision.glsl"
#include "tensor.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z = 1) in;

layout(binding = 0) uniform textureBuffer src;      // activations, 4 consecutive values of a row per texel
layout(binding = 1) uniform textureBuffer weights;  // one vec4 (4 output channels) per texel
layout(std430, binding = 2) readonly buffer Bias { vec4 bias[]; };
layout(std430, binding = 3) writeonly buffer Output { sfloat dst[]; };

#include "push/conv3x3.h"

#ifndef ROWS
#define ROWS 3
#endif
const uint kPixels = 4;   // adjacent output pixels per invocation
const uint kRows = ROWS;  // output rows per invocation
const uint kAcc = 2 * kRows * kPixels;

// Weight vector `item` (= block * 9 + tap) of the current input channel: the same texel in every lane.
#define WEIGHT(item) avec4(texelFetch(weights, int(weight_channel[(item) / 9] + (item) % 9)))

// Accumulator of block b, output row r, pixel i.
#define ACC(b, r, i) (((b) * kRows + (r)) * kPixels + (i))

void main() {
  // Grid: (output-channel groups, column tiles, row tiles). The channel group varies fastest so that the
  // workgroups that read one input tile run back to back and find it in cache.
  const uint ob = gl_WorkGroupID.x;  // block of 8 output channels
  const uint x0 = (gl_WorkGroupID.y * gl_WorkGroupSize.x + gl_LocalInvocationID.x) * kPixels;
  const uint y0 = (gl_WorkGroupID.z * gl_WorkGroupSize.y + gl_LocalInvocationID.y) * kRows;
  // Lanes with no pixel of the image leave at once, so that a subgroup past the right or bottom edge skips the
  // input-channel loop rather than running it on clamped addresses: at 1/8 of 640x480 (80 x 60) a quarter of the
  // subgroups lie past the edge.
  if (x0 >= p.width || y0 >= p.height) return;
  const uint blocks4 = (p.out_channels + 3u) / 4u;

  // In texels of 4 values: rows and planes of the bordered input are whole texels.
  const uint row_texels = row_stride(p.width, 1u) / 4u;
  const uint plane = plane_size(p.height, p.width, 1u) / 4u;
  // Padded columns x0 .. x0 + 5 hold input columns x0 - 1 .. x0 + 4: texel x0 / 4 and the first half of the next
  // one. Padded rows y0 .. y0 + kRows + 1 hold input rows y0 - 1 .. y0 + kRows. Past the end both are clamped
  // (those outputs are not stored).
  const uint col[2] = {min(x0 / 4u, row_texels - 1u), min(x0 / 4u + 1u, row_texels - 1u)};
  uint row[kRows + 2];
  [[unroll]] for (uint r = 0; r < kRows + 2; ++r) row[r] = min(y0 + r, p.height + 1u) * row_texels;

  // Texel of block b's weights for input channel 0, tap 0 (blocks past the end are clamped, not stored).
  uint weight_row[2];
  [[unroll]] for (uint b = 0; b < 2u; ++b) weight_row[b] = min(2u * ob + b, blocks4 - 1u) * p.in_channels * 9u;

  vec4 acc[kAcc];
  [[unroll]] for (uint b = 0; b < 2u; ++b) {
    const vec4 bias_b = bias[min(2u * ob + b, blocks4 - 1u)];
    [[unroll]] for (uint k = 0; k < kRows * kPixels; ++k) acc[b * kRows * kPixels + k] = bias_b;
  }

  for (uint ic = 0, base = 0; ic < p.in_channels; ++ic, base += plane) {
    const uint weight_channel[2] = {weight_row[0] + ic * 9u, weight_row[1] + ic * 9u};
    afloat window[kRows + 2][kPixels + 2];
    [[unroll]] for (uint r = 0; r < kRows + 2; ++r) {
      const avec4 head = avec4(texelFetch(src, int(base + row[r] + col[0])));
      const avec4 tail = avec4(texelFetch(src, int(base + row[r] + col[1])));
      window[r] = afloat[kPixels + 2](head.x, head.y, head.z, head.w, tail.x, tail.y);
    }
    avec4 w[2][9];
    [[unroll]] for (uint b = 0; b < 2u; ++b)
      [[unroll]] for (uint t = 0; t < 9u; ++t) w[b][t] = WEIGHT(b * 9u + t);
    // One output at a time, its 9 taps summed before the accumulator is touched: lavapipe keeps the 96
    // accumulators on the stack (every texel fetch is a call that clobbers the vector registers), and updating
    // them tap by tap stored each of them 9 times per input channel. In the fp16 variant the 9-tap sum is fp16,
    // the accumulator fp32.
    [[unroll]] for (uint b = 0; b < 2u; ++b)
      [[unroll]] for (uint r = 0; r < kRows; ++r)
        [[unroll]] for (uint i = 0; i < kPixels; ++i) {
          avec4 sum = w[b][0] * window[r][i];
          [[unroll]] for (uint t = 1; t < 9u; ++t) sum += w[b][t] * window[r + t / 3u][i + t % 3u];
          acc[ACC(b, r, i)] += vec4(sum);
        }
  }

#ifdef VKVO_CONV3X3_MAXPOOL
  // 2x2 max-pool of each 4-pixel x kRows block (kRows even; floor semantics: an odd last row or column is
  // dropped). ReLU commutes with the max and rounding to the storage type is monotonic, so this stores exactly
  // what the convolution followed by maxpool2x2.comp would.
  const uint pooled_h = p.height / 2u, pooled_w = p.width / 2u;
  const uint out_plane = plane_size(pooled_h, pooled_w, p.out_pad);
  [[unroll]] for (uint b = 0; b < 2u; ++b) {
    const uint channel = (2u * ob + b) * 4u;
    [[unroll]] for (uint r = 0; r < kRows / 2u; ++r) {
      const uint y = y0 / 2u + r;
      [[unroll]] for (uint i = 0; i < kPixels / 2u; ++i) {
        const uint x = x0 / 2u + i;
        if (x >= pooled_w || y >= pooled_h) continue;
        const vec4 top = max(acc[ACC(b, 2u * r, 2u * i)], acc[ACC(b, 2u * r, 2u * i + 1u)]);
        const vec4 bottom = max(acc[ACC(b, 2u * r + 1u, 2u * i)], acc[ACC(b, 2u * r + 1u, 2u * i + 1u)]);
        const vec4 pooled = max(top, bottom);
        const vec4 value = p.relu != 0u ? max(pooled, 0.0) : pooled;
        const uint o = chw_index(channel, y, x, pooled_h, pooled_w, p.out_pad);
        [[unroll]] for (uint k = 0; k < 4u; ++k)
          if (channel + k < p.out_channels) dst[o + k * out_plane] = sfloat(value[k]);
      }
    }
  }
#else
  const uint out_plane = plane_size(p.height, p.width, p.out_pad);
  [[unroll]] for (uint b = 0; b < 2u; ++b) {
    const uint channel = (2u * ob + b) * 4u;
    [[unroll]] for (uint r = 0; r < kRows; ++r) {
      const uint y = y0 + r;
      [[unroll]] for (uint i = 0; i < kPixels; ++i) {
        const uint x = x0 + i;
        if (x >= p.width || y >= p.height) continue;
        const vec4 value = p.relu != 0u ? max(acc[ACC(b, r, i)], 0.0) : acc[ACC(b, r, i)];
        const uint o = chw_index(channel, y, x, p.height, p.width, p.out_pad);
        [[unroll]] for (uint k = 0; k < 4u; ++k)
          if (channel + k < p.out_channels) dst[o + k * out_plane] = sfloat(value[k]);
      }
    }
  }
#endif
}
