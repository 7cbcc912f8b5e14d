#version 450
// SuperGlue multi-head attention in one pass, the GPU form of superglue_attention_tiled.comp (same formula, same
// bindings and push constants):
//   message[i, head h] = sum_j softmax_j(<q_i, k_j> / sqrt(head_dim)) v_j      (dims of head h only)
// A workgroup takes kRows query rows of one head with kParts invocations per row, and walks the keys a tile of
// kTileKeys at a time: the workgroup loads the tile's key and value rows into shared memory once for all its
// rows; each invocation computes the scores of every kParts-th key of the tile for its row (the whole head's dot
// product, its query row in registers), then, after a barrier, runs the online softmax over the tile's scores and
// updates the accumulators of its quarter of the head's dimensions. The tiled form keeps a few whole rows per
// invocation with all their accumulators, which suits a CPU's few wide threads; on a GPU it leaves most of the
// chip idle (docs/performance-history.md, "SuperGlue").
// fp32 math and fp32 tiles in every variant.
#include "packed_texel.glsl"
#extension GL_EXT_control_flow_attributes : require

const uint kRows = 16;      // query rows per workgroup
const uint kParts = 4;      // invocations per query row
const uint kTileKeys = 32;  // keys per shared tile: a multiple of kParts
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;  // kRows * kParts
layout(constant_id = 0) const uint kHeadVec4 = 16;  // head_dim / 4

PACKED_TEXELS(0, qkv);  // rows of [q | k | v], 3 * dim values, kPerTexel per texel (the host: head_dim a multiple)
layout(std430, binding = 1) writeonly buffer State { sfloat state[]; };  // rows of [descriptor | message]

#include "push/attention.h"

const uint kHeadTexels = kHeadVec4 / kVecs;
const uint kPartVec4 = (kHeadVec4 + kParts - 1u) / kParts;  // accumulator vec4s per invocation

// One spare vec4 per key row: the kParts invocations of a row read kParts different keys at once, and rows of
// kHeadVec4 vec4s would put them all in the same bank.
shared vec4 key_tile[kTileKeys][kHeadVec4 + 1u];
shared vec4 value_tile[kTileKeys][kHeadVec4];
shared float score_tile[kRows][kTileKeys + 1u];

// Copies the head's slice of key rows j0 .. j0 + kTileKeys - 1 (k or v, starting at texel `slice` of a row) into
// `tile`; keys past the end repeat the last one (their scores are masked).
#define LOAD_TILE(tile, slice)                                                                \
  for (uint t = gl_LocalInvocationID.x; t < kTileKeys * kHeadTexels; t += gl_WorkGroupSize.x) { \
    const uint j = t / kHeadTexels, texel = t % kHeadTexels;                                  \
    const uint row = p.key_row0 + min(j0 + j, p.keys - 1u);                                   \
    vec4 fetched[kVecs];                                                                      \
    FETCH_AS(vec4, qkv, row * row_texels + (slice) + texel, fetched);                         \
    [[unroll]] for (uint e = 0; e < kVecs; ++e) tile[j][texel * kVecs + e] = fetched[e];      \
  }

void main() {
  const uint head = gl_WorkGroupID.y;
  const uint local_row = gl_LocalInvocationID.x / kParts, part = gl_LocalInvocationID.x % kParts;
  const uint i = gl_WorkGroupID.x * kRows + local_row;
  const uint row_texels = 3u * p.dim / kPerTexel;
  const uint head_texel = head * kHeadTexels;  // within q, k or v
  const uint k_texel = p.dim / kPerTexel + head_texel, v_texel = 2u * p.dim / kPerTexel + head_texel;

  // The query row, pre-scaled (rows past the end repeat the last one and are not stored; every invocation stays
  // for the barriers).
  vec4 q[kHeadVec4];
  const uint q_base = (p.query_row0 + min(i, p.queries - 1u)) * row_texels + head_texel;
  [[unroll]] for (uint t = 0; t < kHeadTexels; ++t) {
    vec4 fetched[kVecs];
    FETCH_AS(vec4, qkv, q_base + t, fetched);
    [[unroll]] for (uint e = 0; e < kVecs; ++e) q[t * kVecs + e] = fetched[e] * p.scale;
  }

  vec4 acc[kPartVec4];
  [[unroll]] for (uint d = 0; d < kPartVec4; ++d) acc[d] = vec4(0.0);
  float peak = -3.0e38, total = 0.0;

  for (uint j0 = 0; j0 < p.keys; j0 += kTileKeys) {
    barrier();  // the previous tile's readers are done
    LOAD_TILE(key_tile, k_texel);
    LOAD_TILE(value_tile, v_texel);
    barrier();
    [[unroll]] for (uint jj = 0; jj < kTileKeys / kParts; ++jj) {
      const uint j = jj * kParts + part;
      vec4 partial = q[0] * key_tile[j][0];
      [[unroll]] for (uint d = 1; d < kHeadVec4; ++d) partial += q[d] * key_tile[j][d];
      score_tile[local_row][j] = j0 + j < p.keys ? (partial.x + partial.y) + (partial.z + partial.w) : -3.0e38;
    }
    barrier();
    // Online softmax: the new running maximum rescales what was accumulated under the old one.
    float m = peak;
    [[unroll]] for (uint j = 0; j < kTileKeys; ++j) m = max(m, score_tile[local_row][j]);
    const float rescale = exp(peak - m);
    peak = m;
    total *= rescale;
    [[unroll]] for (uint d = 0; d < kPartVec4; ++d) acc[d] *= rescale;
    [[unroll]] for (uint j = 0; j < kTileKeys; ++j) {
      const float weight = exp(score_tile[local_row][j] - m);
      total += weight;
      [[unroll]] for (uint d = 0; d < kPartVec4; ++d) {
        const uint dim4 = part * kPartVec4 + d;
        if (dim4 < kHeadVec4) acc[d] += weight * value_tile[j][dim4];
      }
    }
  }

  if (i < p.queries) {
    const float inv = 1.0 / total;
    const uint base = (p.query_row0 + i) * 2u * p.dim + p.dim + head * 4u * kHeadVec4;
    [[unroll]] for (uint d = 0; d < kPartVec4; ++d) {
      const uint dim4 = part * kPartVec4 + d;
      if (dim4 < kHeadVec4)
        [[unroll]] for (uint c = 0; c < 4u; ++c) state[base + 4u * dim4 + c] = sfloat(acc[d][c] * inv);
    }
  }
}
