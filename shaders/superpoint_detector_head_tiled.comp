#version 450
// superpoint_detector_head.comp (1x1 convolution 256 -> 65 + softmax + dustbin drop + depth-to-space, logits fp32
// in every variant) for devices that read the input and the weights through uniform texel buffers (R32F/R16F
// input, RGBA32F/RGBA16F weights as the host chooses, as conv1x1_tiled.comp). Each invocation computes kCells
// adjacent cells, so the 17 weight vectors of an input channel serve kCells cells; per step of 4 input channels
// all operands are fetched first and then every logit takes its 4 products at once (on lavapipe each fetch is a
// call that clobbers the vector registers, so the 4 x 68 logits live on the stack: updating them once per step,
// not once per channel, is what keeps the stores from binding the kernel; docs/performance-history.md,
// "SuperPoint"). The host guarantees in_channels % 4 == 0.
#include "texel_buffer.glsl"
#extension GL_EXT_control_flow_attributes : require
#include "precision.glsl"

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(binding = 0) uniform textureBuffer src;      // I x cells (Hc x Wc, no border), one value per texel
layout(binding = 1) uniform textureBuffer weights;  // "o4" [17][I]: one vec4 (4 output channels) per texel
layout(std430, binding = 2) readonly buffer Bias { vec4 bias[]; };
layout(std430, binding = 3) writeonly buffer Scores { float dense[]; };  // (Hc*8) x (Wc*8)

#include "push/detector_head.h"

const uint kBlocks = 17;  // 65 channels padded to 68
const uint kCells = 4;    // adjacent cells per invocation
const uint kStep = 4;     // input channels per step

void main() {
  const uint cells = p.cells_h * p.cells_w;
  const uint first = gl_GlobalInvocationID.x * kCells;
  if (first >= cells) return;
  uint cell[kCells];  // clamped past the end (those are not stored)
  [[unroll]] for (uint c = 0; c < kCells; ++c) cell[c] = min(first + c, cells - 1u);

  vec4 logits[kCells][kBlocks];
  [[unroll]] for (uint b = 0; b < kBlocks; ++b) {
    const vec4 bias_b = bias[b];
    [[unroll]] for (uint c = 0; c < kCells; ++c) logits[c][b] = bias_b;
  }
  for (uint ic = 0; ic < p.in_channels; ic += kStep) {
    afloat v[kStep][kCells];
    [[unroll]] for (uint s = 0; s < kStep; ++s)
      [[unroll]] for (uint c = 0; c < kCells; ++c) v[s][c] = afloat(texelFetch(src, int((ic + s) * cells + cell[c])).x);
    avec4 w[kStep][kBlocks];
    [[unroll]] for (uint s = 0; s < kStep; ++s)
      [[unroll]] for (uint b = 0; b < kBlocks; ++b) w[s][b] = avec4(texelFetch(weights, int(b * p.in_channels + ic + s)));
    [[unroll]] for (uint c = 0; c < kCells; ++c)
      [[unroll]] for (uint b = 0; b < kBlocks; ++b)
        logits[c][b] += vec4(w[0][b] * v[0][c] + w[1][b] * v[1][c] + w[2][b] * v[2][c] + w[3][b] * v[3][c]);
  }

  const uint row = p.cells_w * 8u;
  [[unroll]] for (uint c = 0; c < kCells; ++c) {
    if (first + c < cells) {  // an if, not a break: a break would turn the logits into an indexed array
      float top = logits[c][0].x;
      [[unroll]] for (uint b = 0; b < kBlocks; ++b)
        [[unroll]] for (uint k = 0; k < 4u; ++k)
          if (b * 4u + k < 65u) top = max(top, logits[c][b][k]);
      float sum = 0.0;
      [[unroll]] for (uint b = 0; b < kBlocks; ++b) {
        logits[c][b] = exp(logits[c][b] - top);
        [[unroll]] for (uint k = 0; k < 4u; ++k)
          if (b * 4u + k < 65u) sum += logits[c][b][k];
      }
      const float inv = 1.0 / sum;
      const uint cy = (first + c) / p.cells_w, cx = (first + c) % p.cells_w;
      [[unroll]] for (uint k = 0; k < 64u; ++k)
        dense[(cy * 8u + k / 8u) * row + cx * 8u + k % 8u] = logits[c][k / 4u][k % 4u] * inv;
    }
  }
}
