#version 450
// Top-k of the NMS candidates by exact ranking: the rank of candidate i is the number of candidates that beat
// it (higher score, or equal score and lower pixel index: a deterministic order for ties, independent of the
// arbitrary order the atomic compaction produced). Candidates ranked below `max_keypoints` write their list
// slot to order[rank], so order[0..min(count, k)) is score-descending. Candidates are compared in shared-memory
// tiles of 64; the cost is count^2 comparisons, a few ms for the few thousand candidates NMS leaves.
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Candidates { uvec2 candidates[]; };  // (pixel index, score bits)
layout(std430, binding = 1) readonly buffer Counter { uint candidate_count; };
layout(std430, binding = 2) writeonly buffer Order { uint order[]; };

#include "push/rank.h"

shared uvec2 tile[64];

// Scores are non-negative, so their bit patterns order like the floats.
bool beats(uvec2 a, uvec2 b) { return a.y > b.y || (a.y == b.y && a.x < b.x); }

void main() {
  const uint count = min(candidate_count, p.capacity);
  const uint first = gl_WorkGroupID.x * 64u;
  if (first >= count) return;  // uniform across the workgroup
  const uint i = gl_GlobalInvocationID.x;
  const uvec2 mine = i < count ? candidates[i] : uvec2(0xffffffffu, 0u);
  uint rank = 0;
  for (uint base = 0; base < count; base += 64u) {
    const uint j = base + gl_LocalInvocationID.x;
    tile[gl_LocalInvocationID.x] = j < count ? candidates[j] : uvec2(0xffffffffu, 0u);
    barrier();
    const uint n = min(64u, count - base);
    for (uint t = 0; t < n; ++t) rank += beats(tile[t], mine) ? 1u : 0u;
    barrier();
  }
  if (i < count && rank < p.max_keypoints) order[rank] = i;
}
