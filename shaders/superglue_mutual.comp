#version 450
// SuperGlue match extraction: keypoint i of image 0 matches j = argmax_j P_ij when i is also the argmax of
// column j (mutual) and exp(P_ij) > threshold. matching score = exp(P_ij) for mutual pairs (kept even when below
// the threshold, as SuperGlue's matching_scores0), 0 otherwise; match -1 when not valid.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Best { int best[]; };  // row argmax [0, n0), column argmax [n0, n0 + n1)
layout(std430, binding = 1) readonly buffer BestValue { float best_value[]; };
layout(std430, binding = 2) writeonly buffer Matches { int matches0[]; };
layout(std430, binding = 3) writeonly buffer MatchScores { float scores0[]; };

#include "push/mutual.h"

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= p.n0) return;
  const int j = best[i];
  const bool mutual = best[p.n0 + uint(j)] == int(i);
  const float score = mutual ? exp(best_value[i]) : 0.0;
  matches0[i] = mutual && score > p.threshold ? j : -1;
  scores0[i] = score;
}
