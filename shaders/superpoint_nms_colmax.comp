#version 450
// Vertical half of SuperPoint's max-pool, fused with the element-wise steps of simple_nms (two suppression
// rounds, exactly as the reference):
//   max_mask = scores == pool(scores)                                    stage 0 (rows: rowmax(scores))
//   repeat 2x: supp = pool(max_mask) > 0; supp_scores = supp ? 0 : scores   stage 1 (rows: rowmax(max_mask))
//              max_mask |= (supp_scores == pool(supp_scores)) & !supp       stage 2 (rows: rowmax(supp_scores))
// Stage 3 is stage 2 followed by selection: a pixel that is a maximum, scores above the threshold and lies at
// least `border` pixels inside the map is appended to the candidate list (pixel index, score bits) through an
// atomic counter; the order of that list is arbitrary, superpoint_rank.comp sorts it.
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;
layout(constant_id = 0) const uint kStage = 0;

layout(std430, binding = 0) readonly buffer Rows { float rows[]; };
layout(std430, binding = 1) readonly buffer Scores { float scores[]; };
layout(std430, binding = 2) buffer Mask { float max_mask[]; };
layout(std430, binding = 3) buffer SuppScores { float supp_scores[]; };
layout(std430, binding = 4) buffer Supp { float supp[]; };
layout(std430, binding = 5) buffer Candidates { uvec2 candidates[]; };
layout(std430, binding = 6) buffer Counter { uint candidate_count; };

layout(push_constant) uniform Params {
  uint width;
  uint height;
  uint radius;
  uint border;
  float threshold;
  uint capacity;
} p;

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= p.width * p.height) return;
  const uint x = i % p.width, y = i / p.width;
  const uint lo = y >= p.radius ? y - p.radius : 0u;
  const uint hi = min(y + p.radius, p.height - 1u);
  float m = rows[lo * p.width + x];
  for (uint yy = lo + 1u; yy <= hi; ++yy) m = max(m, rows[yy * p.width + x]);

  if (kStage == 0u) {
    max_mask[i] = scores[i] == m ? 1.0 : 0.0;
  } else if (kStage == 1u) {
    const bool s = m > 0.0;
    supp[i] = s ? 1.0 : 0.0;
    supp_scores[i] = s ? 0.0 : scores[i];
  } else {
    bool is_max = max_mask[i] != 0.0;
    if (!is_max && supp_scores[i] == m && supp[i] == 0.0) {
      is_max = true;
      max_mask[i] = 1.0;
    }
    if (kStage == 3u && is_max) {
      const float s = scores[i];
      if (s > p.threshold && x >= p.border && y >= p.border && x + p.border < p.width && y + p.border < p.height) {
        const uint slot = atomicAdd(candidate_count, 1u);
        if (slot < p.capacity) candidates[slot] = uvec2(i, floatBitsToUint(s));
      }
    }
  }
}
