#version 450
// C = alpha * A * op(B) + bias (+ C when accumulating) (+ ReLU): the operation and push constants of gemm.comp,
// for operands the host has checked to be aligned to whole texels (kPerTexel elements, below) along K (A, and B
// when transposed) or along N (B when not transposed).
//
// Each invocation computes 4 rows x 8 columns of C; per step of kPerTexel along K it fetches its 4 rows of A
// (one texel each) and the kPerTexel x 8 slice of op(B) (8 texels, the same for every lane of a workgroup):
// 12 texel fetches for 128 multiply-adds in fp32, 256 in 16-bit storage, where gemm.comp makes 7 storage-buffer
// loads for 48. Operands are read through uniform texel buffers: lavapipe gathers texels with vector loads,
// where it loads storage buffers one lane at a time.
//
// Measured on lavapipe (Mesa 22.3, 2 Zen 4 cores), 1000x512x512 B^T fp32: 32 ms when op(B) was fetched once
// per subgroup and handed out with subgroupBroadcast, 20 ms with these direct fetches (see below) and the
// epilogue's loops unrolled (see there); fp16s: 24 ms with RGBA16F texels, 16.6 ms with 8 halves per texel.
#extension GL_EXT_control_flow_attributes : require
#include "precision.glsl"

layout(local_size_x_id = 0, local_size_y = 1, local_size_z = 1) in;
// C stored a whole vec4 at a time: the host sets it where N, ldc, the offsets and batch stride are multiples of
// 4. A specialization constant, not a flag: lavapipe runs both sides of a branch under lane masks, and the
// per-lane store loops of the scalar epilogue cost the vec4 one a third of its time at K = 64 when they ran
// (masked off) beside it (400x400x64 B^T fp32 2.2 -> 1.6 ms).
layout(constant_id = 1) const bool kVec4Store = false;

// fp32: four elements per RGBA32F texel. 16-bit storage: eight halves per RGBA32UI texel, unpacked here: a
// texel fetch costs lavapipe about the same whatever the format, so packing 8 halves halves the fetches per
// multiply-add (an RGBA16F view held 4). The host checks that K, the leading dimensions, offsets and batch
// strides (and N when B is not transposed) are multiples of kPerTexel.
#if defined(VKVO_VARIANT_fp32)
layout(binding = 0) uniform samplerBuffer a_texels;  // A
layout(binding = 1) uniform samplerBuffer b_texels;  // B
const uint kPerTexel = 4;
#define FETCH(texels, index, dst) dst[0] = avec4(texelFetch(texels, int(index)))
#else
layout(binding = 0) uniform usamplerBuffer a_texels;  // A
layout(binding = 1) uniform usamplerBuffer b_texels;  // B
const uint kPerTexel = 8;
#define FETCH(texels, index, dst)                                                   \
  {                                                                                 \
    const uvec4 halves = texelFetch(texels, int(index));                            \
    dst[0] = avec4(unpackHalf2x16(halves.x), unpackHalf2x16(halves.y));             \
    dst[1] = avec4(unpackHalf2x16(halves.z), unpackHalf2x16(halves.w));             \
  }
#endif
const uint kVecs = kPerTexel / 4;  // vec4s per texel
layout(std430, binding = 2) readonly buffer Bias { float bias[]; };
layout(std430, binding = 3) buffer MatC { sfloat c[]; };
layout(std430, binding = 3) buffer MatC4 { svec4 c4[]; };

const uint kTransposedB = 1u, kBias = 2u, kRelu = 4u, kAccumulate = 8u;

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

  // Texel index of A's row i at k = 0 (rows past the end are clamped and not stored).
  uint a_row[kRows];
  [[unroll]] for (uint i = 0; i < kRows; ++i)
    a_row[i] = (p.a_offset + batch * p.a_batch + min(m0 + i, p.m - 1u) * p.lda) / kPerTexel;
  // The 8 texels of op(B) that every lane needs per step of kPerTexel along K, and how far they move per step:
  //  B^T: texel j = row n0 + j of the stored B (= column n0 + j of op(B)), kPerTexel values along K; step 1.
  //  B:   fp32: texel j = row k + j / 2, columns n0 + 4 * (j % 2) .. + 3; 16-bit: texel j = row k + j, columns
  //       n0 .. n0 + 7; step kPerTexel rows = ldb texels.
  // Every lane fetches them itself at the same index. Sharing one fetch per lane through subgroupBroadcast
  // reads like less work, but lavapipe implements each broadcast component as a scalar loop over the 8 lanes
  // (seen in its generated code): about four times the instructions of the texel fetch it replaces. On GPUs a
  // fetch at a workgroup-uniform index is served once from the cache.
  const uint b_base = p.b_offset + batch * p.b_batch;
  uint b_texel[8];
  [[unroll]] for (uint j = 0; j < 8u; ++j) {
    if (transposed)
      b_texel[j] = (b_base + min(n0 + j, p.n - 1u) * p.ldb) / kPerTexel;
    else if (kPerTexel == 4u)
      b_texel[j] = (b_base + (j / 2u) * p.ldb + min(n0 + 4u * (j % 2u), (p.n - 1u) & ~3u)) / 4u;
    else
      b_texel[j] = (b_base + j * p.ldb + n0) / kPerTexel;  // N is a multiple of 8 here
  }
  const uint b_step = transposed ? 1u : p.ldb;

  vec4 acc[kRows][2];  // [row][columns n0..n0+3 | n0+4..n0+7]
  [[unroll]] for (uint i = 0; i < kRows; ++i) acc[i][0] = acc[i][1] = vec4(0);

  // Per step, every fetch comes before the arithmetic: each texel fetch is a call on lavapipe that clobbers the
  // vector registers, and with A's fetch between the rows' multiply-adds the accumulators were stored and
  // reloaded around every one (fetching first: 1000x512x512 B^T fp32 10-15 % faster, alternating runs on 2 Zen 3
  // cores). One loop per form of op(B), the branch outside: a CPU driver runs both sides of a branch with lane
  // masks (lavapipe does), so a branch inside the loop would cost every step both bodies.
  const uint steps = p.k / kPerTexel;
  if (transposed) {
    for (uint s = 0; s < steps; ++s) {
      avec4 b[8][kVecs];  // column j's kPerTexel values along K
      [[unroll]] for (uint j = 0; j < 8u; ++j) FETCH(b_texels, b_texel[j] + s, b[j]);
      avec4 a[kRows][kVecs];
      [[unroll]] for (uint i = 0; i < kRows; ++i) FETCH(a_texels, a_row[i] + s, a[i]);
      [[unroll]] for (uint i = 0; i < kRows; ++i) {
        [[unroll]] for (uint v = 0; v < kVecs; ++v) {
          const avec4 x = a[i][v];
          acc[i][0] += vec4(dot(x, b[0][v]), dot(x, b[1][v]), dot(x, b[2][v]), dot(x, b[3][v]));
          acc[i][1] += vec4(dot(x, b[4][v]), dot(x, b[5][v]), dot(x, b[6][v]), dot(x, b[7][v]));
        }
      }
    }
  } else {
    for (uint s = 0; s < steps; ++s) {
      avec4 r[kPerTexel][2];  // row k + kk of op(B): columns n0..n0+3 | n0+4..n0+7
#if defined(VKVO_VARIANT_fp32)
      [[unroll]] for (uint j = 0; j < 8u; ++j) r[j / 2u][j % 2u] = avec4(texelFetch(b_texels, int(b_texel[j] + s * b_step)));
#else
      [[unroll]] for (uint j = 0; j < 8u; ++j) FETCH(b_texels, b_texel[j] + s * b_step, r[j]);
#endif
      avec4 a[kRows][kVecs];
      [[unroll]] for (uint i = 0; i < kRows; ++i) FETCH(a_texels, a_row[i] + s, a[i]);
      [[unroll]] for (uint i = 0; i < kRows; ++i) {
        [[unroll]] for (uint v = 0; v < kVecs; ++v) {
          const uint kk = 4u * v;
          const avec4 x = a[i][v];
          acc[i][0] += vec4(x.x * r[kk][0] + x.y * r[kk + 1u][0] + x.z * r[kk + 2u][0] + x.w * r[kk + 3u][0]);
          acc[i][1] += vec4(x.x * r[kk][1] + x.y * r[kk + 1u][1] + x.z * r[kk + 2u][1] + x.w * r[kk + 3u][1]);
        }
      }
    }
  }

  // Every loop below is unrolled and guarded by `if` rather than `break`: acc must only ever be indexed by
  // constants, or the compiler turns it into a memory array that every FMA of the K loop reads and writes
  // (lavapipe then stores it lane by lane under the execution mask, which made this kernel 2-3x slower).
  const uint c_base = p.c_offset + batch * p.c_batch;
  [[unroll]] for (uint h = 0; h < 2u; ++h) {
    const uint col = n0 + 4u * h;
    if (col < p.n) {
      vec4 bias4 = vec4(0);
      if ((p.flags & kBias) != 0u)
        [[unroll]] for (uint j = 0; j < 4u; ++j) bias4[j] = bias[min(col + j, p.n - 1u)];
      [[unroll]] for (uint i = 0; i < kRows; ++i) {
        if (m0 + i < p.m) {
          const uint at = c_base + (m0 + i) * p.ldc + col;
          vec4 v = p.alpha * acc[i][h] + bias4;
          if (kVec4Store) {  // whole aligned vec4: one store
            if ((p.flags & kAccumulate) != 0u) v += vec4(c4[at / 4u]);
            if ((p.flags & kRelu) != 0u) v = max(v, 0.0);
            c4[at / 4u] = svec4(v);
          } else {
            [[unroll]] for (uint j = 0; j < 4u; ++j) {
              if (col + j < p.n) {
                float x = v[j];
                if ((p.flags & kAccumulate) != 0u) x += float(c[at + j]);
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
