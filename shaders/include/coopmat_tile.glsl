// The tensor-core tile loop shared by gemm_coopmat.comp and conv3x3_coopmat.comp (GL_NV_cooperative_matrix):
// a workgroup of four subgroups computes a 64 x 64 block of D = A (M x K) * B (K x N) in fp32 from fp16 operands,
// each subgroup a 32 x 32 quarter as 2 x 2 accumulators of 16 x 16. Per step of 32 along K the workgroup stages
// A's and B's tiles in shared memory as fp16 (zero outside the matrices), which is also where the including
// shader's layout is resolved: it defines, before including this file,
//   float16_t tile_a(uint row, uint k)   element (row, k) of A, rows and k in range
//   float16_t tile_b(uint k, uint col)   element (k, col) of B, k and col in range
//   void tile_store(uint row, uint col, float value)   the epilogue for one element of D in range
// and calls coopmat_tile(m, n, k) with the problem's sizes; the block is (gl_WorkGroupID.y, gl_WorkGroupID.x).
// The workgroup has 4 * subgroup size invocations (specialization constant 0; the host sets it from the device).
#ifndef VKVO_COOPMAT_TILE_GLSL
#define VKVO_COOPMAT_TILE_GLSL

#extension GL_NV_cooperative_matrix : require
#extension GL_KHR_memory_scope_semantics : require
#extension GL_KHR_shader_subgroup_basic : require

layout(local_size_x_id = 0, local_size_y = 1, local_size_z = 1) in;

const uint kTileM = 64, kTileN = 64, kTileK = 32, kFragment = 16;
// Row strides of the staged tiles, padded by 16 bytes so that the rows of a fragment fall in different banks;
// cooperative loads and stores need strides of whole 16-byte units.
const uint kStrideA = kTileK + 8u, kStrideB = kTileN + 8u, kStrideD = kTileN + 4u;

shared float16_t staged_a[kTileM * kStrideA];
shared float16_t staged_b[kTileK * kStrideB];
shared float staged_d[kTileM * kStrideD];

#define VKVO_FRAGMENT_F16 fcoopmatNV<16, gl_ScopeSubgroup, kFragment, kFragment>
#define VKVO_FRAGMENT_F32 fcoopmatNV<32, gl_ScopeSubgroup, kFragment, kFragment>

void coopmat_tile(uint m, uint n, uint k) {
  const uint threads = gl_WorkGroupSize.x;
  const uint local = gl_LocalInvocationIndex;
  const uint row0 = gl_WorkGroupID.y * kTileM, col0 = gl_WorkGroupID.x * kTileN;
  // This subgroup's 32 x 32 quarter of the block.
  const uint sub_row = (gl_SubgroupID / 2u) * 32u, sub_col = (gl_SubgroupID % 2u) * 32u;

  VKVO_FRAGMENT_F32 acc[2][2];
  for (uint i = 0; i < 2u; ++i)
    for (uint j = 0; j < 2u; ++j) acc[i][j] = VKVO_FRAGMENT_F32(0.0);

  for (uint k0 = 0; k0 < k; k0 += kTileK) {
    barrier();  // the previous step's fragments are loaded
    for (uint e = local; e < kTileM * kTileK; e += threads) {
      const uint r = e / kTileK, kk = e % kTileK;
      const uint row = row0 + r, kg = k0 + kk;
      staged_a[r * kStrideA + kk] = row < m && kg < k ? tile_a(row, kg) : float16_t(0.0);
    }
    for (uint e = local; e < kTileK * kTileN; e += threads) {
      const uint kk = e / kTileN, c = e % kTileN;
      const uint col = col0 + c, kg = k0 + kk;
      staged_b[kk * kStrideB + c] = col < n && kg < k ? tile_b(kg, col) : float16_t(0.0);
    }
    barrier();
    for (uint kk = 0; kk < kTileK; kk += kFragment) {
      VKVO_FRAGMENT_F16 a[2], b[2];
      for (uint i = 0; i < 2u; ++i)
        coopMatLoadNV(a[i], staged_a, (sub_row + i * kFragment) * kStrideA + kk, kStrideA, false);
      for (uint j = 0; j < 2u; ++j)
        coopMatLoadNV(b[j], staged_b, kk * kStrideB + sub_col + j * kFragment, kStrideB, false);
      for (uint i = 0; i < 2u; ++i)
        for (uint j = 0; j < 2u; ++j) acc[i][j] = coopMatMulAddNV(a[i], b[j], acc[i][j]);
    }
  }

  for (uint i = 0; i < 2u; ++i)
    for (uint j = 0; j < 2u; ++j)
      coopMatStoreNV(acc[i][j], staged_d, (sub_row + i * kFragment) * kStrideD + sub_col + j * kFragment, kStrideD,
                     false);
  barrier();
  for (uint e = local; e < kTileM * kTileN; e += threads) {
    const uint r = e / kTileN, c = e % kTileN;
    const uint row = row0 + r, col = col0 + c;
    if (row < m && col < n) tile_store(row, col, staged_d[r * kStrideD + c]);
  }
}

#endif
