#version 450
// SuperGlue score matrix with dustbins, fp32 output for the optimal transport: for i < n0, j < n1
// Z[i][j] = <mdesc0_i, mdesc1_j> * scale (scale = 1 / sqrt(D)); row n0 and column n1 hold the learned bin score.
// Z is (n0 + 1) x (n1 + 1), row-major. Each invocation computes a 3 x 4 block (12 accumulation chains).
// superglue_scores_tiled.comp is the same through a texel view, where the device has one large enough.
#include "precision.glsl"

layout(local_size_x = 16, local_size_y = 4) in;

layout(std430, binding = 0) readonly buffer Desc { sfloat desc[]; };  // (n0 + n1) x dim: image 0 rows, then image 1
layout(std430, binding = 1) writeonly buffer Couplings { float z[]; };

#include "push/scores.h"

void main() {
  const uint j0 = gl_GlobalInvocationID.x * 4u;
  const uint i0 = gl_GlobalInvocationID.y * 3u;
  const uint cols = p.n1 + 1u;
  if (i0 > p.n0 || j0 > p.n1) return;
  uint a_rows[3], b_rows[4];
  for (uint i = 0; i < 3u; ++i) a_rows[i] = min(i0 + i, p.n0 - 1u) * p.dim;
  for (uint j = 0; j < 4u; ++j) b_rows[j] = (p.n0 + min(j0 + j, p.n1 - 1u)) * p.dim;
  vec4 acc[3] = vec4[3](vec4(0), vec4(0), vec4(0));
  for (uint d = 0; d < p.dim; ++d) {
    const avec4 bv = avec4(desc[b_rows[0] + d], desc[b_rows[1] + d], desc[b_rows[2] + d], desc[b_rows[3] + d]);
    for (uint i = 0; i < 3u; ++i) acc[i] += vec4(afloat(desc[a_rows[i] + d]) * bv);
  }
  for (uint i = 0; i < 3u && i0 + i <= p.n0; ++i)
    for (uint j = 0; j < 4u && j0 + j <= p.n1; ++j)
      z[(i0 + i) * cols + j0 + j] = (i0 + i == p.n0 || j0 + j == p.n1) ? p.bin_score : p.scale * acc[i][j];
}
