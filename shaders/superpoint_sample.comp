#version 450
// Final SuperPoint outputs for the top-k keypoints (one workgroup per output slot): keypoint (x, y) in pixels,
// score, and the descriptor sampled bilinearly from the L2-normalised dense map with SuperGlue's convention
// (grid_sample, align_corners, zero padding, keypoint shifted by s/2 - 0.5 and scaled by W8 - s/2 - 0.5), then
// L2-normalised again.
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Candidates { uvec2 candidates[]; };
layout(std430, binding = 1) readonly buffer Counter { uint candidate_count; };
layout(std430, binding = 2) readonly buffer Order { uint order[]; };
layout(std430, binding = 3) readonly buffer Dense { float dense[]; };  // D x Hc x Wc
layout(std430, binding = 4) writeonly buffer Keypoints { vec2 keypoints[]; };
layout(std430, binding = 5) writeonly buffer Scores { float out_scores[]; };
layout(std430, binding = 6) writeonly buffer Descriptors { float descriptors[]; };  // k x D

#include "push/sample.h"

shared float partial[64];

// One bilinear tap with zero padding outside the map.
float tap(uint c, int y, int x) {
  if (x < 0 || y < 0 || x >= int(p.cells_w) || y >= int(p.cells_h)) return 0.0;
  return dense[(c * p.cells_h + uint(y)) * p.cells_w + uint(x)];
}

void main() {
  const uint k = gl_WorkGroupID.x;
  if (k >= min(min(candidate_count, p.capacity), p.max_keypoints)) return;  // uniform across the workgroup
  const uvec2 cand = candidates[order[k]];
  const uint width = p.cells_w * 8u;
  const vec2 kp = vec2(float(cand.x % width), float(cand.x / width));
  // grid coordinate in [-1, 1], then align_corners un-normalisation to cell units
  const vec2 scale = vec2(float(p.cells_w) * 8.0 - 4.0 - 0.5, float(p.cells_h) * 8.0 - 4.0 - 0.5);
  const vec2 g = (kp - 4.0 + 0.5) / scale * 2.0 - 1.0;
  const vec2 pos = (g + 1.0) * 0.5 * vec2(float(p.cells_w) - 1.0, float(p.cells_h) - 1.0);
  const vec2 f0 = floor(pos);
  const vec2 t = pos - f0;
  const int x0 = int(f0.x), y0 = int(f0.y);

  const uint lid = gl_LocalInvocationID.x;
  float sq = 0.0;
  for (uint c = lid; c < p.dim; c += 64u) {
    const float v = (tap(c, y0, x0) * (1.0 - t.x) + tap(c, y0, x0 + 1) * t.x) * (1.0 - t.y) +
                    (tap(c, y0 + 1, x0) * (1.0 - t.x) + tap(c, y0 + 1, x0 + 1) * t.x) * t.y;
    sq += v * v;
  }
  partial[lid] = sq;
  barrier();
  for (uint stride = 32u; stride > 0u; stride >>= 1u) {
    if (lid < stride) partial[lid] += partial[lid + stride];
    barrier();
  }
  const float inv = 1.0 / max(sqrt(partial[0]), 1e-12);
  // The taps are read again rather than kept: dim / 64 values per invocation is too few to matter.
  for (uint c = lid; c < p.dim; c += 64u) {
    const float v = (tap(c, y0, x0) * (1.0 - t.x) + tap(c, y0, x0 + 1) * t.x) * (1.0 - t.y) +
                    (tap(c, y0 + 1, x0) * (1.0 - t.x) + tap(c, y0 + 1, x0 + 1) * t.x) * t.y;
    descriptors[k * p.dim + c] = v * inv;
  }
  if (lid == 0u) {
    keypoints[k] = kp;
    out_scores[k] = uintBitsToFloat(cand.y);
  }
}
