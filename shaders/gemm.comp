#version 450
// C = alpha * A * op(B) + bias (+ ReLU), row-major. A is M x K; op(B) is B (K x N) or B^T with B stored N x K
// (the form of a linear layer's weight, and of Q K^T). Each invocation computes a 4 x 4 block of C: 16
// independent accumulation chains. Edges are clamped on load and masked on store.
#include "precision.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer MatA { sfloat a[]; };
layout(std430, binding = 1) readonly buffer MatB { sfloat b[]; };
layout(std430, binding = 2) readonly buffer Bias { float bias[]; };
layout(std430, binding = 3) writeonly buffer MatC { sfloat c[]; };

layout(push_constant) uniform Params {
  uint m;
  uint n;
  uint k;
  uint b_transposed;  // 1: B is stored N x K
  uint has_bias;
  uint relu;
  float alpha;
} p;

void main() {
  const uint n0 = gl_GlobalInvocationID.x * 4u;
  const uint m0 = gl_GlobalInvocationID.y * 4u;
  if (m0 >= p.m || n0 >= p.n) return;
  uint rows[4], cols[4];
  for (uint i = 0; i < 4u; ++i) {
    rows[i] = min(m0 + i, p.m - 1u) * p.k;
    cols[i] = min(n0 + i, p.n - 1u);
  }
  // Element (kk, col) of op(B) is at col_base + kk * k_stride.
  const uint k_stride = p.b_transposed != 0u ? 1u : p.n;
  uint col_base[4];
  for (uint j = 0; j < 4u; ++j) col_base[j] = p.b_transposed != 0u ? cols[j] * p.k : cols[j];

  vec4 acc0 = vec4(0), acc1 = vec4(0), acc2 = vec4(0), acc3 = vec4(0);
  for (uint kk = 0; kk < p.k; ++kk) {
    const uint off = kk * k_stride;
    const avec4 bv = avec4(b[col_base[0] + off], b[col_base[1] + off], b[col_base[2] + off], b[col_base[3] + off]);
    acc0 += vec4(afloat(a[rows[0] + kk]) * bv);
    acc1 += vec4(afloat(a[rows[1] + kk]) * bv);
    acc2 += vec4(afloat(a[rows[2] + kk]) * bv);
    acc3 += vec4(afloat(a[rows[3] + kk]) * bv);
  }
  vec4 bias4 = vec4(0);
  if (p.has_bias != 0u) bias4 = vec4(bias[cols[0]], bias[cols[1]], bias[cols[2]], bias[cols[3]]);
  const vec4 results[4] = vec4[4](acc0, acc1, acc2, acc3);
  for (uint i = 0; i < 4u && m0 + i < p.m; ++i) {
    vec4 v = p.alpha * results[i] + bias4;
    if (p.relu != 0u) v = max(v, 0.0);
    for (uint j = 0; j < 4u && n0 + j < p.n; ++j) c[(m0 + i) * p.n + n0 + j] = sfloat(v[j]);
  }
}
