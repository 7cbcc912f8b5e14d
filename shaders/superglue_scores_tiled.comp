#version 450
// SuperGlue score matrix with dustbins, as superglue_scores.comp, the descriptors read through a texel view of the
// storage precision, 4 dimensions per fetch (descriptor_dim a multiple of 4): per 4 dimensions an invocation
// makes 7 fetches for its 3 x 4 block where the storage-buffer kernel makes 28 loads, each a scalar loop over the
// lanes on lavapipe. Used where the descriptors fit maxTexelBufferElements.
#include "texel_buffer.glsl"

layout(local_size_x = 16, local_size_y = 4) in;

layout(binding = 0) uniform textureBuffer desc;  // (n0 + n1) x dim: image 0 rows, then image 1; 4 per texel
layout(std430, binding = 1) writeonly buffer Couplings { float z[]; };

#include "push/scores.h"

void main() {
  const uint j0 = gl_GlobalInvocationID.x * 4u;
  const uint i0 = gl_GlobalInvocationID.y * 3u;
  const uint cols = p.n1 + 1u;
  if (i0 > p.n0 || j0 > p.n1) return;
  const uint texels = p.dim / 4u;
  // Rows past the last keypoint are clamped (their results land in the dustbin row / column or are not stored).
  uint a_rows[3], b_rows[4];
  for (uint i = 0; i < 3u; ++i) a_rows[i] = min(i0 + i, p.n0 - 1u) * texels;
  for (uint j = 0; j < 4u; ++j) b_rows[j] = (p.n0 + min(j0 + j, p.n1 - 1u)) * texels;
  vec4 acc[3] = vec4[3](vec4(0), vec4(0), vec4(0));
  for (uint t = 0; t < texels; ++t) {
    vec4 a[3], b[4];
    for (uint i = 0; i < 3u; ++i) a[i] = texelFetch(desc, int(a_rows[i] + t));
    for (uint j = 0; j < 4u; ++j) b[j] = texelFetch(desc, int(b_rows[j] + t));
    for (uint i = 0; i < 3u; ++i) acc[i] += vec4(dot(a[i], b[0]), dot(a[i], b[1]), dot(a[i], b[2]), dot(a[i], b[3]));
  }
  for (uint i = 0; i < 3u && i0 + i <= p.n0; ++i)
    for (uint j = 0; j < 4u && j0 + j <= p.n1; ++j)
      z[(i0 + i) * cols + j0 + j] = (i0 + i == p.n0 || j0 + j == p.n1) ? p.bin_score : p.scale * acc[i][j];
}
