// C = alpha * A * op(B) + bias (+ C when accumulating) (+ ReLU): the operation and push constants of gemm.comp
// (bias and accumulation chosen by specialization constants here, not by its flags), for operands the host has
// checked to be aligned to whole texels (kPerTexel elements, below) along K (A, and B when transposed) or along N
// (B when not transposed). The body of gemm_tiled.comp (4 x 8 tiles) and gemm_tiled_wide.comp (8 x 16 tiles).
//
// Each invocation computes ROWS rows x COLS columns of C; per step of kPerTexel along K it fetches its ROWS rows
// of A (one texel each) and the kPerTexel x COLS slice of op(B) (COLS texels, the same for every lane of a
// workgroup): at 4 x 8, 12 texel fetches for 128 multiply-adds in fp32 (256 in 16-bit storage), where gemm.comp
// makes 7 storage-buffer loads for 48; at 8 x 16, 24 fetches for 512. Operands are read through uniform texel
// buffers: lavapipe gathers texels with vector loads, where it loads storage buffers one lane at a time. A
// uniform-buffer load is one bounds-checked scalar load broadcast to the lanes, but only where Mesa 22.3 can prove
// the offset uniform: constants and push constants, not a loop counter (there it gathers lane by lane). So op(B)
// from a uniform buffer needs the K loop unrolled, and that straight-line body measured 2x slower than the same
// body reading texels, and 5x slower than this kernel: LLVM schedules its thousands of loads early and spills
// nearly everything (half the JIT code is stack moves).
//
// The wide tile is for CPU drivers. On lavapipe the texel fetches take most of the time (perf on the JIT code:
// 60 % in the two fetch functions at 4 x 8), and A's cost more than op(B)'s, since every lane reads other rows
// (cache misses) where op(B)'s texels are the same for all. A texel of A is used once per column, so only wider
// tiles fetch A less per multiply-add: 4 x 8 -> 8 x 8 measured no faster, 4 x 8 -> 8 x 16 made SuperGlue's
// GEMMs at N = 1000 about 20 % faster (mlp0 + qkv + mlp1 2.2 -> 1.8 s, alternating runs); 4 x 16, 2 x 16,
// 12 x 16, 16 x 16, 8 x 24 and 8 x 32 measured no better than 8 x 16 (Mesa 22.3, 2 Zen 3 cores). GPUs keep the
// 4 x 8 tile: 128 accumulators plus 24 operand texels per invocation would crowd their register files (on an H200
// the 4 x 8 tile ran gemm 1000x512x512 B^T in 0.079 ms, 6.6 TFLOP/s fp32; the 8 x 16 one was not timed there).
//
// Earlier measurements at 4 x 8, 1000x512x512 B^T fp32: 32 ms when op(B) was fetched once per subgroup and
// handed out with subgroupBroadcast, 20 ms with these direct fetches (see below) and the epilogue's loops
// unrolled (see there); fp16s: 24 ms with RGBA16F texels, 16.6 ms with 8 halves per texel.
//
// Defines before inclusion: ROWS and COLS (a multiple of 8).
#include "packed_texel.glsl"
#extension GL_EXT_control_flow_attributes : require

layout(local_size_x_id = 0, local_size_y = 1, local_size_z = 1) in;
// C stored a whole vec4 at a time: the host sets it where N, ldc, the offsets and batch stride are multiples of
// 4. A specialization constant, not a flag: lavapipe runs both sides of a branch under lane masks, and the
// per-lane store loops of the scalar epilogue cost the vec4 one a third of its time at K = 64 when they ran
// (masked off) beside it (400x400x64 B^T fp32 2.2 -> 1.6 ms).
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

const uint kTransposedB = 1u, kRelu = 4u;  // the flags read here (gemm.comp's others are specialised here)

layout(push_constant) uniform Params {
  uint m, n, k;
  uint lda, ldb, ldc;
  uint a_offset, b_offset, c_offset;
  uint a_batch, b_batch, c_batch;  // element strides between consecutive batches (gl_WorkGroupID.z)
  uint flags;
  float alpha;
} p;

const uint kRows = ROWS;  // rows of C per invocation
const uint kCols = COLS;  // columns of C per invocation and per workgroup
const uint kColVecs = kCols / 4u;

void main() {
  // Grid: (column blocks of kCols, row groups, batch); rows vary within a workgroup, columns are uniform.
  const uint n0 = gl_WorkGroupID.x * kCols;
  const uint m0 = (gl_WorkGroupID.y * gl_WorkGroupSize.x + gl_LocalInvocationID.x) * kRows;
  const uint batch = gl_WorkGroupID.z;
  const bool transposed = (p.flags & kTransposedB) != 0u;
  // Lanes past the last row leave at once: a subgroup with no row to compute then skips the K loop, where it
  // used to run it on clamped rows (SuperGlue at N = M = 8, 16 rows: mlp0 5.3 -> 1.2-2.1 ms per dispatch).
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
  // reloaded around every one (fetching first: 1000x512x512 B^T fp32 10-15 % faster, alternating runs on 2 Zen 3
  // cores). One loop per form of op(B), the branch outside: a CPU driver runs both sides of a branch with lane
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
  // (lavapipe then stores it lane by lane under the execution mask, which made this kernel 2-3x slower).
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
            if ((p.flags & kRelu) != 0u) v = max(v, 0.0);
            c4[at / 4u] = svec4(v);
          } else {
            [[unroll]] for (uint j = 0; j < 4u; ++j) {
              if (col + j < p.n) {
                float x = v[j];
                if (kAccumulateC) x += float(c[at + j]);
                if ((p.flags & kRelu) != 0u) x = max(x, 0.0);
                c[at + j] = sfloat(x);
              }
            }
          }
        }
      }
    }
  }
}
