#version 450
// C = alpha * A * op(B) + bias (+ C when accumulating) (+ ReLU) on tensor cores: gemm.comp's contract (push/gemm.h:
// leading dimensions, offsets, batch strides, flags) with the products in fp16 x fp16 -> fp32 cooperative matrices
// (include/coopmat_tile.glsl). The batch is gl_WorkGroupID.z. Runs where DeviceProfile::cooperative_matrix.
#include "precision.glsl"
#include "push/gemm.h"

layout(std430, binding = 0) readonly buffer MatA { sfloat a[]; };
layout(std430, binding = 1) readonly buffer MatB { sfloat b[]; };
layout(std430, binding = 2) readonly buffer Bias { float bias[]; };
layout(std430, binding = 3) buffer MatC { sfloat c[]; };

float16_t tile_a(uint row, uint k) { return float16_t(a[p.a_offset + gl_WorkGroupID.z * p.a_batch + row * p.lda + k]); }

float16_t tile_b(uint k, uint col) {
  const uint base = p.b_offset + gl_WorkGroupID.z * p.b_batch;
  return float16_t((p.flags & kGemmTransposedB) != 0u ? b[base + col * p.ldb + k] : b[base + k * p.ldb + col]);
}

void tile_store(uint row, uint col, float value) {
  const uint index = p.c_offset + gl_WorkGroupID.z * p.c_batch + row * p.ldc + col;
  float x = p.alpha * value;
  if ((p.flags & kGemmBias) != 0u) x += bias[(p.flags & kGemmRowBias) != 0u ? row : col];
  if ((p.flags & kGemmAccumulate) != 0u) x += float(c[index]);
  if ((p.flags & kGemmRelu) != 0u) x = max(x, 0.0);
  c[index] = sfloat(x);
}

#include "coopmat_tile.glsl"

void main() { coopmat_tile(p.m, p.n, p.k); }
