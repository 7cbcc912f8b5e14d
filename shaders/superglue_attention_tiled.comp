#version 450
// SuperGlue multi-head attention in one pass, for one keypoint set's queries over a set's keys and values:
//   message[i, head h] = sum_j softmax_j(<q_i, k_j> / sqrt(head_dim)) v_j      (dims of head h only)
// written into the message half of the state rows. The scores are never stored (the three-pass form's score
// stores were lavapipe's largest cost): each invocation keeps kRows query rows of one head, walks the keys 8 at a
// time and keeps a running maximum, sum and weighted sum of values per row (the online softmax).
//
// The CPU form: per block of 8 keys an invocation fetches the key rows, computes its kRows x 8 scores, then fetches
// the value rows, every fetch of a phase before its arithmetic (on lavapipe a texel fetch is a call that clobbers
// the vector registers). Keys and values are the same texels in every lane and serve all kRows rows, so more rows
// fetch less per multiply-add (the host: 8 on CPUs). fp32 math in every variant; 16-bit storage reads 8 halves per
// fetch (packed_texel.glsl). GPUs run superglue_attention_shared.comp. Figures: docs/performance-history.md,
// "SuperGlue".
#include "packed_texel.glsl"
#extension GL_EXT_control_flow_attributes : require

layout(local_size_x = 16, local_size_y = 1, local_size_z = 1) in;
layout(constant_id = 0) const uint kHeadVec4 = 16;  // head_dim / 4 (the accumulators are indexed by constants)
layout(constant_id = 1) const uint kRows = 8;       // query rows per invocation (the host: 8 on CPUs, 4 on GPUs)

PACKED_TEXELS(0, qkv);  // rows of [q | k | v], 3 * dim values, kPerTexel per texel (the host: head_dim a multiple)
layout(std430, binding = 1) writeonly buffer State { sfloat state[]; };  // rows of [descriptor | message]

#include "push/attention.h"

const uint kKeys = 8;
const uint kHeadTexels = kHeadVec4 / kVecs;

// dst[0 .. kHeadVec4 - 1] = the head's values of a row, starting at texel `first`.
#define FETCH_HEAD(first, dst)                                      \
  [[unroll]] for (uint t = 0; t < kHeadTexels; ++t) {               \
    vec4 part[kVecs];                                               \
    FETCH_AS(vec4, qkv, (first) + t, part);                         \
    [[unroll]] for (uint e = 0; e < kVecs; ++e) dst[t * kVecs + e] = part[e]; \
  }

void main() {
  const uint head = gl_WorkGroupID.y;
  const uint i0 = gl_GlobalInvocationID.x * kRows;
  if (i0 >= p.queries) return;
  const uint row_texels = 3u * p.dim / kPerTexel;
  const uint head_texel = head * kHeadTexels;  // within q, k or v
  const uint k_texel = p.dim / kPerTexel + head_texel, v_texel = 2u * p.dim / kPerTexel + head_texel;

  // The query rows, pre-scaled (rows past the end repeat the last one and are not stored).
  vec4 q[kRows][kHeadVec4];
  [[unroll]] for (uint r = 0; r < kRows; ++r) {
    const uint base = (p.query_row0 + min(i0 + r, p.queries - 1u)) * row_texels + head_texel;
    FETCH_HEAD(base, q[r]);
    [[unroll]] for (uint d = 0; d < kHeadVec4; ++d) q[r][d] *= p.scale;
  }

  vec4 acc[kRows][kHeadVec4];
  float peak[kRows], total[kRows];
  [[unroll]] for (uint r = 0; r < kRows; ++r) {
    [[unroll]] for (uint d = 0; d < kHeadVec4; ++d) acc[r][d] = vec4(0.0);
    peak[r] = -3.0e38;
    total[r] = 0.0;
  }

  for (uint j0 = 0; j0 < p.keys; j0 += kKeys) {
    // Scores of the block; keys past the end get zero weight.
    float s[kRows][kKeys];
    [[unroll]] for (uint j = 0; j < kKeys; ++j) {
      const uint base = (p.key_row0 + min(j0 + j, p.keys - 1u)) * row_texels + k_texel;
      vec4 k[kHeadVec4];
      FETCH_HEAD(base, k);
      [[unroll]] for (uint r = 0; r < kRows; ++r) {
        vec4 partial = q[r][0] * k[0];
        [[unroll]] for (uint d = 1; d < kHeadVec4; ++d) partial += q[r][d] * k[d];
        s[r][j] = j0 + j < p.keys ? (partial.x + partial.y) + (partial.z + partial.w) : -3.0e38;
      }
    }
    // Online softmax: the new running maximum rescales what was accumulated under the old one.
    float weight[kRows][kKeys], rescale[kRows];
    [[unroll]] for (uint r = 0; r < kRows; ++r) {
      float m = peak[r];
      [[unroll]] for (uint j = 0; j < kKeys; ++j) m = max(m, s[r][j]);
      rescale[r] = exp(peak[r] - m);
      peak[r] = m;
      float block_total = 0.0;
      [[unroll]] for (uint j = 0; j < kKeys; ++j) {
        weight[r][j] = exp(s[r][j] - m);
        block_total += weight[r][j];
      }
      total[r] = total[r] * rescale[r] + block_total;
    }
    // Values of the block, then each accumulator updated once.
    vec4 v[kKeys][kHeadVec4];
    [[unroll]] for (uint j = 0; j < kKeys; ++j) {
      const uint base = (p.key_row0 + min(j0 + j, p.keys - 1u)) * row_texels + v_texel;
      FETCH_HEAD(base, v[j]);
    }
    [[unroll]] for (uint r = 0; r < kRows; ++r)
      [[unroll]] for (uint d = 0; d < kHeadVec4; ++d) {
        vec4 sum = weight[r][0] * v[0][d];
        [[unroll]] for (uint j = 1; j < kKeys; ++j) sum += weight[r][j] * v[j][d];
        acc[r][d] = acc[r][d] * rescale[r] + sum;
      }
  }

  const uint head_dim = 4u * kHeadVec4;
  [[unroll]] for (uint r = 0; r < kRows; ++r) {
    if (i0 + r < p.queries) {
      const float inv = 1.0 / total[r];
      const uint base = (p.query_row0 + i0 + r) * 2u * p.dim + p.dim + head * head_dim;
      [[unroll]] for (uint d = 0; d < kHeadVec4; ++d)
        [[unroll]] for (uint c = 0; c < 4u; ++c) state[base + 4u * d + c] = sfloat(acc[r][d][c] * inv);
    }
  }
}
