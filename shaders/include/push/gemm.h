// Push constants: C = alpha * A * op(B) + bias (+ C) (+ ReLU) (gemm.comp, gemm_tiled.comp): shapes, leading
// dimensions, element offsets, batch strides and flags.
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_GEMM_H
#define VKVO_PUSH_GEMM_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(GemmPush) {
  uint m, n, k;
  uint lda, ldb, ldc;
  uint a_offset, b_offset, c_offset;
  uint a_batch, b_batch, c_batch;  // element strides between consecutive batches (gl_WorkGroupID.z)
  uint flags;
  float alpha;
} VKVO_PUSH_INSTANCE;

// Bits of GemmPush::flags. gemm_tiled.comp reads only kGemmTransposedB and kGemmRelu (its bias and accumulation are
// specialization constants); the vec4 paths are gemm.comp's.
const uint kGemmTransposedB = 1u, kGemmBias = 2u, kGemmRelu = 4u, kGemmAccumulate = 8u, kGemmVec4K = 16u;
const uint kGemmVec4N = 32u;
const uint kGemmRowBias = 64u;  // with kGemmBias: one bias per row of C (M values) instead of per column

VKVO_SHADER_NAMESPACE_END
#endif
