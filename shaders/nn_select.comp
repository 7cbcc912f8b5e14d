#version 450
// Mutual nearest neighbours with a cosine-distance gate and an optional ratio test on the L2 distances of the
// (unit) descriptors, d = sqrt(2 - 2 s): keypoint i of image 0 matches its best j when i is j's best, 1 - s <=
// max_cosine_distance and (ratio <= 0, or only one candidate, or d_best < ratio * d_second).
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Best { int best[]; };
layout(std430, binding = 1) readonly buffer BestValue { float best_value[]; };
layout(std430, binding = 2) readonly buffer Second { float second_value[]; };
layout(std430, binding = 3) writeonly buffer Matches { int matches0[]; };
layout(std430, binding = 4) writeonly buffer MatchScores { float scores0[]; };

#include "push/nn_select.h"

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= p.n0) return;
  const int j = best[i];
  const float similarity = best_value[i];
  bool keep = best[p.n0 + uint(j)] == int(i) && 1.0 - similarity <= p.max_cosine_distance;
  if (keep && p.ratio > 0.0 && p.n1 > 1u) {
    const float d_best = sqrt(max(2.0 - 2.0 * similarity, 0.0));
    const float d_second = sqrt(max(2.0 - 2.0 * second_value[i], 0.0));
    keep = d_best < p.ratio * d_second;
  }
  matches0[i] = keep ? j : -1;
  scores0[i] = keep ? similarity : 0.0;
}
