#version 450
// Final SuperPoint outputs for the top-k keypoints (one workgroup per output slot): keypoint (x, y) in pixels,
// score, and the descriptor sampled bilinearly from the L2-normalised dense map with SuperGlue's convention
// (grid_sample, align_corners, zero padding, keypoint shifted by s/2 - 0.5 and scaled by W8 - s/2 - 0.5), then
// L2-normalised again. With p.subpixel the keypoint moves to the peak of the parabola through the log of its score and
// its two neighbours' (a Gaussian peak, as the softmax's logits suggest; it follows a known shift more closely than
// a parabola through the scores: docs/accuracy.md), in x and in y, at most half a pixel. The descriptor stays
// sampled at the pixel NMS chose.
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Candidates { uvec2 candidates[]; };
layout(std430, binding = 1) readonly buffer Counter { uint candidate_count; };
layout(std430, binding = 2) readonly buffer Order { uint order[]; };
layout(std430, binding = 3) readonly buffer ScoreMap { float score_map[]; };  // (Hc*8) x (Wc*8), before NMS
layout(std430, binding = 4) readonly buffer Dense { float dense[]; };          // D x Hc x Wc
layout(std430, binding = 5) writeonly buffer Keypoints { vec2 keypoints[]; };
layout(std430, binding = 6) writeonly buffer Scores { float out_scores[]; };
layout(std430, binding = 7) writeonly buffer Descriptors { float descriptors[]; };  // k x D

#include "push/sample.h"

shared float partial[64];

// One bilinear tap with zero padding outside the map.
float tap(uint c, int y, int x) {
  if (x < 0 || y < 0 || x >= int(p.cells_w) || y >= int(p.cells_h)) return 0.0;
  return dense[(c * p.cells_h + uint(y)) * p.cells_w + uint(x)];
}

// Offset of the vertex of the parabola through (-1, s.x), (0, s.y), (1, s.z); 0 where the three are not concave.
float parabola_peak(vec3 s) {
  const float curvature = s.x - 2.0 * s.y + s.z;
  return curvature < 0.0 ? clamp(0.5 * (s.x - s.z) / curvature, -0.5, 0.5) : 0.0;
}

vec2 subpixel_offset(uint x, uint y, uint width, uint height) {
  if (x == 0u || y == 0u || x + 1u >= width || y + 1u >= height) return vec2(0.0);
  const uint i = y * width + x;
  const float floor_score = 1e-30;  // a softmax that underflowed to 0 would make the log infinite
  const vec3 across = max(vec3(score_map[i - 1u], score_map[i], score_map[i + 1u]), floor_score);
  const vec3 down = max(vec3(score_map[i - width], score_map[i], score_map[i + width]), floor_score);
  return vec2(parabola_peak(log(across)), parabola_peak(log(down)));
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
    keypoints[k] = p.subpixel != 0u ? kp + subpixel_offset(cand.x % width, cand.x / width, width, p.cells_h * 8u) : kp;
    out_scores[k] = uintBitsToFloat(cand.y);
  }
}
