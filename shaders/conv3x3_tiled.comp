#version 450
// 3x3 convolution, stride 1, pad 1, + bias (+ ReLU). Same weight layout ("o4": [O/4][I][9] vec4) and
// activation layout as conv3x3.comp.
//
// Each invocation computes 8 output channels x 4 adjacent pixels x ROWS rows. Per input channel it fetches the
// 18 weight vectors of its 2 blocks of 4 output channels (the same texels in every lane of the workgroup) and
// the (ROWS + 2) x 6 input window. They used to be fetched 3 per lane and handed out with subgroupBroadcast;
// lavapipe runs each broadcast component as a scalar loop over the lanes, and the direct fetches measured 18-22 %
// faster there (conv 64->64 @376x240: 173 -> 142 ms). On GPUs a fetch at a workgroup-uniform index is served
// once from the cache.
//
// The input and the weights are read through uniform texel buffers (R32F/R16F and RGBA32F/RGBA16F views
// chosen by the host for the storage precision): lavapipe fetches texels with vector gathers, where it loads
// storage buffers one lane at a time behind a branch, which made the loads, not the FMAs, the bottleneck.
//
// Three rows per invocation and every loop unrolled ([[unroll]]; the accumulators must be registers, not an
// indexed array): measured on lavapipe (Mesa 22.3, 2 Zen 4 cores) 10-17 % faster than two rows. Without the
// unrolling, three rows ran 10x slower; four rows spill the 128 accumulators and lose. A Winograd F(2x2,3x3)
// variant (2.25x fewer multiply-adds) measured 1.1-2.4x slower there: its 16 transformed weights per filter
// cost more fetches per output and its transformed-domain accumulators spill.
//
// Out-of-range pixels read clamped addresses and skip the store.
#extension GL_EXT_control_flow_attributes : require
#include "precision.glsl"
#include "tensor.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z = 1) in;

layout(binding = 0) uniform samplerBuffer src;      // activations, one channel value per texel
layout(binding = 1) uniform samplerBuffer weights;  // one vec4 (4 output channels) per texel
layout(std430, binding = 2) readonly buffer Bias { vec4 bias[]; };
layout(std430, binding = 3) writeonly buffer Output { sfloat dst[]; };

layout(push_constant) uniform Params {
  uint in_channels;
  uint out_channels;
  uint height;
  uint width;
  uint out_pad;
  uint relu;
} p;

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

// PART[b][r][i] += weight(b, ky * 3 + kx) * input(r + ky, i + kx) for both blocks, every row and pixel.
#define TAP(ky, kx)                                                  \
  {                                                                  \
    const avec4 w0 = WEIGHT((ky) * 3 + (kx)), w1 = WEIGHT(9 + (ky) * 3 + (kx)); \
    [[unroll]] for (uint r = 0; r < kRows; ++r)                                 \
      [[unroll]] for (uint i = 0; i < kPixels; ++i) {                           \
        const afloat v = window[r + (ky)][i + (kx)];                 \
        PART[ACC(0, r, i)] += w0 * v;                                \
        PART[ACC(1, r, i)] += w1 * v;                                \
      }                                                              \
  }

void main() {
  // Grid: (output-channel groups, column tiles, row tiles). The channel group varies fastest so that the
  // workgroups that read one input tile run back to back and find it in cache.
  const uint ob = gl_WorkGroupID.x;  // block of 8 output channels
  const uint x0 = (gl_WorkGroupID.y * gl_WorkGroupSize.x + gl_LocalInvocationID.x) * kPixels;
  const uint y0 = (gl_WorkGroupID.z * gl_WorkGroupSize.y + gl_LocalInvocationID.y) * kRows;
  const uint blocks4 = (p.out_channels + 3u) / 4u;

  const uint row_len = p.width + 2u;
  const uint plane = plane_size(p.height, p.width, 1u);
  // Padded columns x0 .. x0 + 5 hold input columns x0 - 1 .. x0 + 4, padded rows y0 .. y0 + kRows + 1 hold
  // input rows y0 - 1 .. y0 + kRows; past the end they are clamped (those outputs are not stored).
  uint col[kPixels + 2], row[kRows + 2];
  [[unroll]] for (uint i = 0; i < kPixels + 2; ++i) col[i] = min(x0 + i, p.width + 1u);
  [[unroll]] for (uint r = 0; r < kRows + 2; ++r) row[r] = min(y0 + r, p.height + 1u) * row_len;

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
    [[unroll]] for (uint r = 0; r < kRows + 2; ++r)
      [[unroll]] for (uint i = 0; i < kPixels + 2; ++i) window[r][i] = afloat(texelFetch(src, int(base + row[r] + col[i])).x);
#ifdef VKVO_FP16_MATH
    avec4 part[kAcc];  // fp16 products of one input channel, added to the fp32 accumulators below
    [[unroll]] for (uint k = 0; k < kAcc; ++k) part[k] = avec4(0);
#define PART part
#else
#define PART acc
#endif
    TAP(0, 0) TAP(0, 1) TAP(0, 2)
    TAP(1, 0) TAP(1, 1) TAP(1, 2)
    TAP(2, 0) TAP(2, 1) TAP(2, 2)
#ifdef VKVO_FP16_MATH
    [[unroll]] for (uint k = 0; k < kAcc; ++k) acc[k] += vec4(part[k]);
#endif
  }

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
}
