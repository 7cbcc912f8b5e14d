#version 450
// C = alpha * A * op(B) + bias (+ C when accumulating) (+ ReLU): the operation and push constants of gemm.comp,
// for operands the host has checked to be vec4-aligned along K (A, and B when transposed) or along N (B when
// not transposed), on devices with subgroups of at least 8 invocations.
//
// Each invocation computes 4 rows x 8 columns of C. The lanes of a subgroup work on different rows of the same
// 8 columns, so op(B)'s 4 x 8 slice for each step of 4 along K is fetched once per subgroup (one vec4 texel per
// lane) and handed out with subgroupBroadcast; A is read 4 values of K per texel. Per 4 steps of K a lane makes
// 5 texel fetches for 128 FMAs, where gemm.comp makes 7 storage-buffer loads for 48. Operands are read through
// uniform texel buffers (vector gathers on lavapipe, see conv3x3_subgroup.comp). All lanes stay active until
// the stores (subgroupBroadcast from an inactive lane is undefined).
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_EXT_control_flow_attributes : require
#include "precision.glsl"

layout(local_size_x_id = 0, local_size_y = 1, local_size_z = 1) in;

layout(binding = 0) uniform samplerBuffer a_texels;  // A, four consecutive elements per texel
layout(binding = 1) uniform samplerBuffer b_texels;  // B, four consecutive elements per texel
layout(std430, binding = 2) readonly buffer Bias { float bias[]; };
layout(std430, binding = 3) buffer MatC { sfloat c[]; };
layout(std430, binding = 3) buffer MatC4 { svec4 c4[]; };

const uint kTransposedB = 1u, kBias = 2u, kRelu = 4u, kAccumulate = 8u, kVec4C = 64u;

layout(push_constant) uniform Params {
  uint m, n, k;
  uint lda, ldb, ldc;
  uint a_offset, b_offset, c_offset;
  uint a_batch, b_batch, c_batch;  // element strides between consecutive batches (gl_WorkGroupID.z)
  uint flags;
  float alpha;
} p;

const uint kRows = 4;  // 8 measured slower on lavapipe (the 64 accumulators spill)

void main() {
  // Grid: (column blocks of 8, row groups, batch); rows vary within a workgroup, columns are uniform.
  const uint n0 = gl_WorkGroupID.x * 8u;
  const uint m0 = (gl_WorkGroupID.y * gl_WorkGroupSize.x + gl_LocalInvocationID.x) * kRows;
  const uint batch = gl_WorkGroupID.z;
  const bool transposed = (p.flags & kTransposedB) != 0u;
  const uint lane = gl_SubgroupInvocationID & 7u;

  // Texel index of A's row i at k = 0 (rows past the end are clamped and not stored).
  uint a_row[kRows];
  [[unroll]] for (uint i = 0; i < kRows; ++i)
    a_row[i] = (p.a_offset + batch * p.a_batch + min(m0 + i, p.m - 1u) * p.lda) / 4u;
  // The texel this lane fetches per step of 4 along K, and how far it moves per step:
  //  B^T: row n0 + lane of the stored B (= column n0 + lane of op(B)), k .. k + 3;
  //  B:   row k + lane / 2, columns n0 + 4 * (lane % 2) .. + 3.
  const uint b_base = p.b_offset + batch * p.b_batch;
  uint b_texel, b_step;
  if (transposed) {
    b_texel = (b_base + min(n0 + lane, p.n - 1u) * p.ldb) / 4u;
    b_step = 1u;
  } else {
    b_texel = (b_base + (lane / 2u) * p.ldb + min(n0 + 4u * (lane % 2u), (p.n - 1u) & ~3u)) / 4u;
    b_step = p.ldb;  // 4 rows of B = ldb texels
  }

  vec4 acc[kRows][2];  // [row][columns n0..n0+3 | n0+4..n0+7]
  [[unroll]] for (uint i = 0; i < kRows; ++i) acc[i][0] = acc[i][1] = vec4(0);

  // One loop per form of op(B), the branch outside: a CPU driver runs both sides of a branch with lane masks
  // (lavapipe does), so a branch inside the loop would cost every step both bodies.
  const uint steps = p.k / 4u;
  if (transposed) {
    for (uint s = 0; s < steps; ++s) {
      const vec4 held = texelFetch(b_texels, int(b_texel + s));
      // Column j's 4 values along K come from lane j (broadcast lanes must be compile-time constants).
      const avec4 b0 = avec4(subgroupBroadcast(held, 0)), b1 = avec4(subgroupBroadcast(held, 1));
      const avec4 b2 = avec4(subgroupBroadcast(held, 2)), b3 = avec4(subgroupBroadcast(held, 3));
      const avec4 b4 = avec4(subgroupBroadcast(held, 4)), b5 = avec4(subgroupBroadcast(held, 5));
      const avec4 b6 = avec4(subgroupBroadcast(held, 6)), b7 = avec4(subgroupBroadcast(held, 7));
      [[unroll]] for (uint i = 0; i < kRows; ++i) {
        const avec4 a = avec4(texelFetch(a_texels, int(a_row[i] + s)));
        acc[i][0] += vec4(dot(a, b0), dot(a, b1), dot(a, b2), dot(a, b3));
        acc[i][1] += vec4(dot(a, b4), dot(a, b5), dot(a, b6), dot(a, b7));
      }
    }
  } else {
    for (uint s = 0; s < steps; ++s) {
      const vec4 held = texelFetch(b_texels, int(b_texel + s * b_step));
      // Row k + r of the 4 x 8 slice: columns 0-3 from lane 2r, 4-7 from lane 2r + 1.
      const avec4 r0l = avec4(subgroupBroadcast(held, 0)), r0h = avec4(subgroupBroadcast(held, 1));
      const avec4 r1l = avec4(subgroupBroadcast(held, 2)), r1h = avec4(subgroupBroadcast(held, 3));
      const avec4 r2l = avec4(subgroupBroadcast(held, 4)), r2h = avec4(subgroupBroadcast(held, 5));
      const avec4 r3l = avec4(subgroupBroadcast(held, 6)), r3h = avec4(subgroupBroadcast(held, 7));
      [[unroll]] for (uint i = 0; i < kRows; ++i) {
        const avec4 a = avec4(texelFetch(a_texels, int(a_row[i] + s)));
        acc[i][0] += vec4(a.x * r0l + a.y * r1l + a.z * r2l + a.w * r3l);
        acc[i][1] += vec4(a.x * r0h + a.y * r1h + a.z * r2h + a.w * r3h);
      }
    }
  }

  const uint c_base = p.c_offset + batch * p.c_batch;
  for (uint h = 0; h < 2u; ++h) {
    const uint col = n0 + 4u * h;
    if (col >= p.n) break;
    vec4 bias4 = vec4(0);
    if ((p.flags & kBias) != 0u)
      for (uint j = 0; j < 4u; ++j) bias4[j] = bias[min(col + j, p.n - 1u)];
    for (uint i = 0; i < kRows; ++i) {
      if (m0 + i >= p.m) break;
      const uint at = c_base + (m0 + i) * p.ldc + col;
      vec4 v = p.alpha * acc[i][h] + bias4;
      if ((p.flags & kVec4C) != 0u && col + 4u <= p.n) {  // whole aligned vec4: one store
        if ((p.flags & kAccumulate) != 0u) v += vec4(c4[at / 4u]);
        if ((p.flags & kRelu) != 0u) v = max(v, 0.0);
        c4[at / 4u] = svec4(v);
      } else {
        for (uint j = 0; j < 4u && col + j < p.n; ++j) {
          float x = v[j];
          if ((p.flags & kAccumulate) != 0u) x += float(c[at + j]);
          if ((p.flags & kRelu) != 0u) x = max(x, 0.0);
          c[at + j] = sfloat(x);
        }
      }
    }
  }
}
