#version 450
// C = alpha * A * op(B) + bias (+ C when accumulating) (+ ReLU), row-major with leading dimensions, element
// offsets and a batch index (gl_WorkGroupID.z) that advances each operand by a fixed stride. A is M x K; op(B) is
// B (K x N) or B^T with B stored N x K (the form of a linear layer's weight, and of Q K^T). Strided views let one
// GEMM read a column block of a wider matrix (one attention head, the first half of [x | message]) and write
// into one.
// Each invocation computes a ROWS x 4 block of C: ROWS * 4 independent accumulators (lavapipe runs fastest with
// about 12 per invocation, method-notes). Edges are clamped on load and masked on store. Where the host has checked
// alignment, operands are read as vec4s (one bounds-checked access per 4 elements on lavapipe): along K for both
// operands when B is transposed (kGemmVec4K), along N for B otherwise (kGemmVec4N).
#include "precision.glsl"

#define ROWS 3

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer MatA { sfloat a[]; };
layout(std430, binding = 0) readonly buffer MatA4 { svec4 a4[]; };
layout(std430, binding = 1) readonly buffer MatB { sfloat b[]; };
layout(std430, binding = 1) readonly buffer MatB4 { svec4 b4[]; };
layout(std430, binding = 2) readonly buffer Bias { float bias[]; };
layout(std430, binding = 3) buffer MatC { sfloat c[]; };


#include "push/gemm.h"

void main() {
  const uint n0 = gl_GlobalInvocationID.x * 4u;
  const uint m0 = gl_GlobalInvocationID.y * ROWS;
  if (m0 >= p.m || n0 >= p.n) return;
  const uint batch = gl_WorkGroupID.z;
  const bool transposed = (p.flags & kGemmTransposedB) != 0u;
  uint rows[ROWS];
  for (uint i = 0; i < ROWS; ++i) rows[i] = p.a_offset + batch * p.a_batch + min(m0 + i, p.m - 1u) * p.lda;
  uint cols[4];
  for (uint j = 0; j < 4u; ++j) cols[j] = min(n0 + j, p.n - 1u);
  // Element (kk, col) of op(B) is at col_base + kk * k_stride.
  const uint k_stride = transposed ? 1u : p.ldb;
  const uint b_base = p.b_offset + batch * p.b_batch;
  uint col_base[4];
  for (uint j = 0; j < 4u; ++j) col_base[j] = b_base + (transposed ? cols[j] * p.ldb : cols[j]);

  vec4 acc[ROWS];
  for (uint i = 0; i < ROWS; ++i) acc[i] = vec4(0);
  if ((p.flags & kGemmVec4K) != 0u) {
    // acc[i][j] = sum over k of A[row i] . B[col j], four k at a time.
    for (uint i = 0; i < ROWS; ++i) rows[i] /= 4u;
    for (uint j = 0; j < 4u; ++j) col_base[j] /= 4u;
    const uint k4 = p.k / 4u;
    for (uint kk = 0; kk < k4; ++kk) {
      const avec4 b0 = avec4(b4[col_base[0] + kk]), b1 = avec4(b4[col_base[1] + kk]);
      const avec4 b2 = avec4(b4[col_base[2] + kk]), b3 = avec4(b4[col_base[3] + kk]);
      for (uint i = 0; i < ROWS; ++i) {
        const avec4 av = avec4(a4[rows[i] + kk]);
        acc[i] += vec4(float(dot(av, b0)), float(dot(av, b1)), float(dot(av, b2)), float(dot(av, b3)));
      }
    }
  } else if ((p.flags & kGemmVec4N) != 0u) {
    // One vec4 of B's row kk covers the block's four columns (n is a multiple of 4).
    const uint b4_base = (b_base + n0) / 4u, ldb4 = p.ldb / 4u;
    for (uint kk = 0; kk < p.k; ++kk) {
      const avec4 bv = avec4(b4[b4_base + kk * ldb4]);
      for (uint i = 0; i < ROWS; ++i) acc[i] += vec4(afloat(a[rows[i] + kk]) * bv);
    }
  } else {
    for (uint kk = 0; kk < p.k; ++kk) {
      const uint off = kk * k_stride;
      const avec4 bv = avec4(b[col_base[0] + off], b[col_base[1] + off], b[col_base[2] + off], b[col_base[3] + off]);
      for (uint i = 0; i < ROWS; ++i) acc[i] += vec4(afloat(a[rows[i] + kk]) * bv);
    }
  }
  const bool row_bias = (p.flags & (kGemmBias | kGemmRowBias)) == (kGemmBias | kGemmRowBias);
  vec4 bias4 = vec4(0);
  if ((p.flags & kGemmBias) != 0u && !row_bias) bias4 = vec4(bias[cols[0]], bias[cols[1]], bias[cols[2]], bias[cols[3]]);
  const uint c_base = p.c_offset + batch * p.c_batch;
  for (uint i = 0; i < ROWS && m0 + i < p.m; ++i) {
    const uint row = c_base + (m0 + i) * p.ldc;
    vec4 v = p.alpha * acc[i] + bias4;
    if (row_bias) v += bias[m0 + i];
    for (uint j = 0; j < 4u && n0 + j < p.n; ++j) {
      float x = v[j];
      if ((p.flags & kGemmAccumulate) != 0u) x += float(c[row + n0 + j]);
      if ((p.flags & kGemmRelu) != 0u) x = max(x, 0.0);
      c[row + n0 + j] = sfloat(x);
    }
  }
}
