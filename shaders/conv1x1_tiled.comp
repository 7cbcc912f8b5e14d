#version 450
// 1x1 convolution + bias (+ ReLU), for input channel counts that are multiples of 4. Same weight layout
// ("o4": [O/4][I] vec4), activation layout and push constants as conv1x1.comp.
//
// Each invocation computes 8 output channels x 8 adjacent pixels. Per step of 4 input channels it fetches the
// 8 weight vectors of its 2 blocks (the same texels in every lane) and 4 x 8 input values, through uniform
// texel buffers: conv3x3_tiled.comp's scheme (see there why lavapipe needs texel buffers and why the weights
// are not shared through subgroup broadcasts). conv1x1.comp makes 5 storage-buffer loads per 16 multiply-adds,
// this kernel 40 texel fetches per 256.
//
// Out-of-range pixels read clamped addresses and skip the store.
#include "texel_buffer.glsl"
#extension GL_EXT_control_flow_attributes : require
#include "precision.glsl"
#include "tensor.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z = 1) in;

layout(binding = 0) uniform textureBuffer src;      // activations, one channel value per texel
layout(binding = 1) uniform textureBuffer weights;  // one vec4 (4 output channels) per texel
layout(std430, binding = 2) readonly buffer Bias { vec4 bias[]; };
layout(std430, binding = 3) writeonly buffer Output { sfloat dst[]; };

#include "push/conv1x1.h"

const uint kPixels = 8;

// Weight vector of block b (0, 1) and input channel ic0 + j of the current step: the same texel in every lane.
#define WEIGHT(b, j) avec4(texelFetch(weights, int(weight_row[b] + ic0 + (j))))

// acc[b][i] += weight(b, j) * input(ic0 + j, pixel i) for both blocks and every pixel.
#define CHANNEL(j)                                                              \
  {                                                                             \
    const avec4 w0 = WEIGHT(0, j), w1 = WEIGHT(1, j);                           \
    [[unroll]] for (uint i = 0; i < kPixels; ++i) {                             \
      const afloat v = afloat(texelFetch(src, int(base + (j) * in_plane + col[i])).x); \
      acc[0][i] += vec4(w0 * v);                                                \
      acc[1][i] += vec4(w1 * v);                                                \
    }                                                                           \
  }

void main() {
  // Grid: (output-channel groups of 8, column tiles, rows), as conv3x3_tiled.comp.
  const uint ob = gl_WorkGroupID.x;
  const uint x0 = (gl_WorkGroupID.y * gl_WorkGroupSize.x + gl_LocalInvocationID.x) * kPixels;
  const uint y = min(gl_WorkGroupID.z * gl_WorkGroupSize.y + gl_LocalInvocationID.y, p.height - 1u);
  const bool row_valid = gl_WorkGroupID.z * gl_WorkGroupSize.y + gl_LocalInvocationID.y < p.height;
  if (x0 >= p.width || !row_valid) return;  // no pixel of the image: skip the loop (conv3x3_tiled.comp)
  const uint blocks4 = (p.out_channels + 3u) / 4u;

  const uint in_plane = plane_size(p.height, p.width, p.in_pad);
  const uint row_start = chw_index(0u, y, 0u, p.height, p.width, p.in_pad);
  uint col[kPixels];
  [[unroll]] for (uint i = 0; i < kPixels; ++i) col[i] = row_start + min(x0 + i, p.width - 1u);

  uint weight_row[2];  // texel of block b's weights for input channel 0 (clamped past the end, not stored)
  [[unroll]] for (uint b = 0; b < 2u; ++b) weight_row[b] = min(2u * ob + b, blocks4 - 1u) * p.in_channels;

  vec4 acc[2][kPixels];
  [[unroll]] for (uint b = 0; b < 2u; ++b) {
    const vec4 bias_b = bias[min(2u * ob + b, blocks4 - 1u)];
    [[unroll]] for (uint i = 0; i < kPixels; ++i) acc[b][i] = bias_b;
  }

  for (uint ic0 = 0; ic0 < p.in_channels; ic0 += 4u) {
    const uint base = ic0 * in_plane;
    CHANNEL(0) CHANNEL(1) CHANNEL(2) CHANNEL(3)
  }

  const uint out_plane = plane_size(p.height, p.width, p.out_pad);
  [[unroll]] for (uint b = 0; b < 2u; ++b) {
    const uint channel = (2u * ob + b) * 4u;
    [[unroll]] for (uint i = 0; i < kPixels; ++i) {
      const uint x = x0 + i;
      if (x >= p.width || !row_valid) continue;
      const vec4 value = p.relu != 0u ? max(acc[b][i], 0.0) : acc[b][i];
      const uint o = chw_index(channel, y, x, p.height, p.width, p.out_pad);
      [[unroll]] for (uint k = 0; k < 4u; ++k)
        if (channel + k < p.out_channels) dst[o + k * out_plane] = sfloat(value[k]);
    }
  }
}
