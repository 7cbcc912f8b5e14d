#version 450
// C = alpha * A * op(B) + bias (+ C when accumulating) (+ ReLU), gemm.comp's operation and push constants (bias
// and accumulation chosen by specialization constants here), for operands the host has checked to be aligned to
// whole texels (kPerTexel elements) along K (A, and B when transposed) or along N (B when not transposed).
// ROWS x COLS blocks of C per invocation (the shader table: gemm_tiled 4 x 8 for GPUs, gemm_tiled_wide 8 x 16 for
// CPU drivers); per step of kPerTexel along K an invocation fetches its ROWS texels of A and the COLS texels of the
// kPerTexel x COLS slice of op(B), which are the same for every lane of a workgroup.
//
// Operands are read through uniform texel buffers: lavapipe gathers texels with vector loads where it loads storage
// buffers one lane at a time, and a uniform buffer is read as a broadcast only at offsets it can prove uniform (not
// a loop counter). On lavapipe the texel fetches take most of the time, A's more than op(B)'s (every lane reads
// other rows); a texel of A serves one column, so only a wider tile fetches A less per multiply-add: hence the wide
// tile on CPUs. GPUs keep 4 x 8: 8 x 16 accumulators and operands would crowd their register files. Figures:
// docs/performance-history.md, "Tiled GEMM".
#include "packed_texel.glsl"
#extension GL_EXT_control_flow_attributes : require

layout(local_size_x_id = 0, local_size_y = 1, local_size_z = 1) in;
// C stored a whole vec4 at a time: the host sets it where N, ldc, the offsets and batch stride are multiples of
// 4. A specialization constant, not a flag: lavapipe runs both sides of a branch under lane masks, so the scalar
// epilogue's per-lane store loops would run (masked off) beside the vec4 one.
layout(constant_id = 1) const bool kVec4Store = false;
// The rest of the epilogue is specialised the same way, for the same reason: with the bias and accumulation
// chosen by push-constant flags, their loads (each a scalar loop over the lanes) ran masked off in every call
// that used neither, SuperPoint's Winograd GEMMs (K = 64) among them.
layout(constant_id = 2) const bool kAccumulateC = false;  // C += result (the ReLU, if any, applies to the sum)
layout(constant_id = 3) const uint kBiasPer = 0;          // 0: no bias; 1: one per column of C (N); 2: per row (M)

// Operands packed 4 (fp32) or 8 (16-bit storage) per texel, see packed_texel.glsl. The host checks that K, the
// leading dimensions, offsets and batch strides (and N when B is not transposed) are multiples of kPerTexel.
PACKED_TEXELS(0, a_texels);  // A
PACKED_TEXELS(1, b_texels);  // B
layout(std430, binding = 2) readonly buffer Bias { float bias[]; };
layout(std430, binding = 3) buffer MatC { sfloat c[]; };
layout(std430, binding = 3) buffer MatC4 { svec4 c4[]; };


#include "push/gemm.h"

const uint kRows = ROWS;  // rows of C per invocation
const uint kCols = COLS;  // columns of C per invocation and per workgroup
const uint kColVecs = kCols / 4u;

void main() {
  // Grid: (column blocks of kCols, row groups, batch); rows vary within a workgroup, columns are uniform.
  const uint n0 = gl_WorkGroupID.x * kCols;
  const uint m0 = (gl_WorkGroupID.y * gl_WorkGroupSize.x + gl_LocalInvocationID.x) * kRows;
  const uint batch = gl_WorkGroupID.z;
  const bool transposed = (p.flags & kGemmTransposedB) != 0u;
  // Lanes past the last row leave at once: a subgroup with no row to compute then skips the K loop rather than
  // running it on clamped rows (small M, e.g. SuperGlue at a few keypoints).
  if (m0 >= p.m) return;

  // Texel index of A's row i at k = 0 (rows past the end are clamped and not stored).
  uint a_row[kRows];
  [[unroll]] for (uint i = 0; i < kRows; ++i)
    a_row[i] = (p.a_offset + batch * p.a_batch + min(m0 + i, p.m - 1u) * p.lda) / kPerTexel;
  // The kCols texels of op(B) that every lane needs per step of kPerTexel along K, and how far they move per step:
  //  B^T: texel j = row n0 + j of the stored B (= column n0 + j of op(B)), kPerTexel values along K; step 1.
  //  B:   texel j = row k + j / t, columns n0 + kPerTexel * (j % t) .., with t = kCols / kPerTexel texels per
  //       row of the tile; step kPerTexel rows = kPerTexel * ldb elements.
  // Every lane fetches them itself at the same index. Sharing one fetch per lane through subgroupBroadcast
  // reads like less work, but lavapipe implements each broadcast component as a scalar loop over the 8 lanes
  // (seen in its generated code): about four times the instructions of the texel fetch it replaces. On GPUs a
  // fetch at a workgroup-uniform index is served once from the cache.
  const uint b_base = p.b_offset + batch * p.b_batch;
  const uint row_texels = kCols / kPerTexel;
  uint b_texel[kCols];
  [[unroll]] for (uint j = 0; j < kCols; ++j) {
    // Columns past the end are clamped (and not stored); for B they are clamped to the last whole texel (the
    // host checks that N fills whole texels in 16-bit storage).
    if (transposed)
      b_texel[j] = (b_base + min(n0 + j, p.n - 1u) * p.ldb) / kPerTexel;
    else
      b_texel[j] = (b_base + (j / row_texels) * p.ldb +
                    min(n0 + kPerTexel * (j % row_texels), (p.n - 1u) & ~(kPerTexel - 1u))) / kPerTexel;
  }
  const uint b_step = transposed ? 1u : p.ldb;

  vec4 acc[kRows][kColVecs];  // [row][columns n0 + 4h .. n0 + 4h + 3]
  [[unroll]] for (uint i = 0; i < kRows; ++i)
    [[unroll]] for (uint h = 0; h < kColVecs; ++h) acc[i][h] = vec4(0);

  // Per step, every fetch comes before the arithmetic: each texel fetch is a call on lavapipe that clobbers the
  // vector registers, and with A's fetch between the rows' multiply-adds the accumulators were stored and
  // reloaded around every one. One loop per form of op(B), the branch outside: a CPU driver runs both sides of a branch with lane
  // masks (lavapipe does), so a branch inside the loop would cost every step both bodies.
  const uint steps = p.k / kPerTexel;
  if (transposed) {
    for (uint s = 0; s < steps; ++s) {
      avec4 b[kCols][kVecs];  // column j's kPerTexel values along K
      [[unroll]] for (uint j = 0; j < kCols; ++j) FETCH(b_texels, b_texel[j] + s, b[j]);
      avec4 a[kRows][kVecs];
      [[unroll]] for (uint i = 0; i < kRows; ++i) FETCH(a_texels, a_row[i] + s, a[i]);
      [[unroll]] for (uint i = 0; i < kRows; ++i) {
        [[unroll]] for (uint v = 0; v < kVecs; ++v) {
          const avec4 x = a[i][v];
          [[unroll]] for (uint h = 0; h < kColVecs; ++h)
            acc[i][h] += vec4(dot(x, b[4u * h][v]), dot(x, b[4u * h + 1u][v]), dot(x, b[4u * h + 2u][v]),
                              dot(x, b[4u * h + 3u][v]));
        }
      }
    }
  } else {
    for (uint s = 0; s < steps; ++s) {
      avec4 r[kPerTexel][kColVecs];  // row k + kk of op(B): columns n0 + 4h .. n0 + 4h + 3
      [[unroll]] for (uint j = 0; j < kCols; ++j) {
        avec4 texel[kVecs];
        FETCH(b_texels, b_texel[j] + s * b_step, texel);
        [[unroll]] for (uint v = 0; v < kVecs; ++v) r[j / row_texels][(j % row_texels) * kVecs + v] = texel[v];
      }
      avec4 a[kRows][kVecs];
      [[unroll]] for (uint i = 0; i < kRows; ++i) FETCH(a_texels, a_row[i] + s, a[i]);
      [[unroll]] for (uint i = 0; i < kRows; ++i) {
        [[unroll]] for (uint v = 0; v < kVecs; ++v) {
          const uint kk = 4u * v;
          const avec4 x = a[i][v];
          [[unroll]] for (uint h = 0; h < kColVecs; ++h)
            acc[i][h] += vec4(x.x * r[kk][h] + x.y * r[kk + 1u][h] + x.z * r[kk + 2u][h] + x.w * r[kk + 3u][h]);
        }
      }
    }
  }

  // Every loop below is unrolled and guarded by `if` rather than `break`: acc must only ever be indexed by
  // constants, or the compiler turns it into a memory array that every FMA of the K loop reads and writes
  // (lavapipe then stores it lane by lane under the execution mask).
  const uint c_base = p.c_offset + batch * p.c_batch;
  float bias_of_row[kRows];
  [[unroll]] for (uint i = 0; i < kRows; ++i) bias_of_row[i] = 0.0;
  if (kBiasPer == 2u) [[unroll]] for (uint i = 0; i < kRows; ++i) bias_of_row[i] = bias[min(m0 + i, p.m - 1u)];
  [[unroll]] for (uint h = 0; h < kColVecs; ++h) {
    const uint col = n0 + 4u * h;
    if (col < p.n) {
      vec4 bias4 = vec4(0);
      if (kBiasPer == 1u) [[unroll]] for (uint j = 0; j < 4u; ++j) bias4[j] = bias[min(col + j, p.n - 1u)];
      [[unroll]] for (uint i = 0; i < kRows; ++i) {
        if (m0 + i < p.m) {
          const uint at = c_base + (m0 + i) * p.ldc + col;
          vec4 v = p.alpha * acc[i][h] + bias4 + bias_of_row[i];
          if (kVec4Store) {  // whole aligned vec4: one store
            if (kAccumulateC) v += vec4(c4[at / 4u]);
            if ((p.flags & kGemmRelu) != 0u) v = max(v, 0.0);
            c4[at / 4u] = svec4(v);
          } else {
            [[unroll]] for (uint j = 0; j < 4u; ++j) {
              if (col + j < p.n) {
                float x = v[j];
                if (kAccumulateC) x += float(c[at + j]);
                if ((p.flags & kGemmRelu) != 0u) x = max(x, 0.0);
                c[at + j] = sfloat(x);
              }
            }
          }
        }
      }
    }
  }
}
