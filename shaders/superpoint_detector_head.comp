#version 450
// SuperPoint detector head after convPa: 1x1 convolution 256 -> 65 + softmax over the 65 channels + dustbin drop
// + depth-to-space by 8, fused so the logits never leave the invocation (they stay fp32 in every precision
// variant: fp16 logits would cost ~1e-3 of score accuracy). One invocation per 8x8 cell.
// Weights "o4" [17][I] (vec4 = four output channels, channel 65..67 zero), bias vec4[17].
#include "precision.glsl"

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Input { sfloat src[]; };   // I x Hc x Wc, no border
layout(std430, binding = 1) readonly buffer Weights { wvec4 weights[]; };
layout(std430, binding = 2) readonly buffer Bias { vec4 bias[]; };
layout(std430, binding = 3) writeonly buffer Scores { float dense[]; };  // (Hc*8) x (Wc*8)

#include "push/detector_head.h"

const uint kBlocks = 17;  // 65 channels padded to 68

void main() {
  const uint cell = gl_GlobalInvocationID.x;
  const uint cells = p.cells_h * p.cells_w;
  if (cell >= cells) return;

  vec4 logits[kBlocks];
  for (uint b = 0; b < kBlocks; ++b) logits[b] = bias[b];
  for (uint ic = 0; ic < p.in_channels; ++ic) {
    const afloat v = afloat(src[ic * cells + cell]);
    for (uint b = 0; b < kBlocks; ++b) logits[b] += vec4(avec4(weights[b * p.in_channels + ic]) * v);
  }
  float top = logits[0].x;
  for (uint b = 0; b < kBlocks; ++b)
    for (uint k = 0; k < 4u; ++k)
      if (b * 4u + k < 65u) top = max(top, logits[b][k]);
  float sum = 0.0;
  for (uint b = 0; b < kBlocks; ++b) {
    logits[b] = exp(logits[b] - top);
    for (uint k = 0; k < 4u; ++k)
      if (b * 4u + k < 65u) sum += logits[b][k];
  }
  const float inv = 1.0 / sum;
  const uint cy = cell / p.cells_w, cx = cell % p.cells_w;
  const uint row = p.cells_w * 8u;
  for (uint c = 0; c < 64u; ++c)
    dense[(cy * 8u + c / 8u) * row + cx * 8u + c % 8u] = logits[c / 4u][c % 4u] * inv;
}
