#version 450
// Vertical half of SuperPoint's max-pool, fused with the element-wise steps of simple_nms (two suppression
// rounds, exactly as the reference):
//   max_mask = scores == pool(scores)                                    stage 0 (rows: rowmax(scores))
//   repeat 2x: supp = pool(max_mask) > 0; supp_scores = supp ? 0 : scores   stage 1 (rows: rowmax(max_mask))
//              max_mask |= (supp_scores == pool(supp_scores)) & !supp       stage 2 (rows: rowmax(supp_scores))
// Stage 3 is stage 2 followed by selection: a pixel that is a maximum, scores above the threshold and lies at
// least `border` pixels inside the map is appended to the candidate list (pixel index, score bits) through an
// atomic counter; the order of that list is arbitrary, superpoint_rank.comp sorts it.
//
// Four adjacent pixels of a row per invocation, as vec4s (see superpoint_nms_rowmax.comp): 2r+1 vec4 loads of the
// row maxima for 4 outputs.
//
// TEXEL_INPUTS (the shader table): 1 reads the row maxima and the scores through RGBA32F texel views (the _tiled
// op, where the map fits maxTexelBufferElements), 0 through storage buffers (any device).
#if TEXEL_INPUTS
#include "texel_buffer.glsl"
#endif
#extension GL_EXT_control_flow_attributes : require
#if TEXEL_INPUTS
layout(binding = 0) uniform textureBuffer rows;
layout(binding = 1) uniform textureBuffer scores;
#define LOAD_ROWS(index) texelFetch(rows, int(index))
#define LOAD_SCORES(index) texelFetch(scores, int(index))
#else
layout(std430, binding = 0) readonly buffer Rows { vec4 rows[]; };
layout(std430, binding = 1) readonly buffer Scores { vec4 scores[]; };
#define LOAD_ROWS(index) rows[index]
#define LOAD_SCORES(index) scores[index]
#endif
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;
layout(constant_id = 0) const uint kStage = 0;

layout(std430, binding = 2) buffer Mask { vec4 max_mask[]; };
layout(std430, binding = 3) buffer SuppScores { vec4 supp_scores[]; };
layout(std430, binding = 4) buffer Supp { vec4 supp[]; };
layout(std430, binding = 5) buffer Candidates { uvec2 candidates[]; };
layout(std430, binding = 6) buffer Counter { uint candidate_count; };

#include "push/nms_columns.h"

void main() {
  const uint row_vec4s = p.width / 4u;
  const uint t = gl_GlobalInvocationID.x;
  if (t >= row_vec4s * p.height) return;
  const uint column = t % row_vec4s, y = t / row_vec4s;
  const uint lo = y >= p.radius ? y - p.radius : 0u;
  const uint hi = min(y + p.radius, p.height - 1u);
  vec4 m = LOAD_ROWS(lo * row_vec4s + column);
  for (uint yy = lo + 1u; yy <= hi; ++yy) m = max(m, LOAD_ROWS(yy * row_vec4s + column));

  if (kStage == 0u) {
    max_mask[t] = vec4(equal(LOAD_SCORES(t), m));
  } else if (kStage == 1u) {
    const bvec4 suppressed = greaterThan(m, vec4(0.0));
    supp[t] = vec4(suppressed);
    supp_scores[t] = mix(LOAD_SCORES(t), vec4(0.0), suppressed);
  } else {
    const bvec4 new_max = bvec4(uvec4(equal(supp_scores[t], m)) & uvec4(equal(supp[t], vec4(0.0))));
    const bvec4 is_max = bvec4(uvec4(notEqual(max_mask[t], vec4(0.0))) | uvec4(new_max));
    max_mask[t] = vec4(is_max);
    if (kStage == 3u) {
      const vec4 s = LOAD_SCORES(t);
      const bool inside_rows = y >= p.border && y + p.border < p.height;
      [[unroll]] for (uint i = 0; i < 4u; ++i) {
        const uint x = column * 4u + i;
        if (is_max[i] && s[i] > p.threshold && inside_rows && x >= p.border && x + p.border < p.width) {
          const uint slot = atomicAdd(candidate_count, 1u);
          if (slot < p.capacity) candidates[slot] = uvec2(y * p.width + x, floatBitsToUint(s[i]));
        }
      }
    }
  }
}
