#version 450
// Every iteration of log-space Sinkhorn (formulas in superglue_sinkhorn.comp) in one workgroup, always fp32: the
// potentials live in shared memory and a workgroup barrier separates the half-iterations. For small problems:
// one dispatch instead of two per iteration. On lavapipe each dispatch costs a wake-up of its worker threads, while
// one workgroup runs on one thread, so this pays only while a half-iteration's work is small (the host chooses by
// the size of Z: DeviceProfile::fused_sinkhorn_max_cells; docs/performance-history.md, "SuperGlue").
// The couplings come as superglue_sinkhorn_tiled.comp takes them: Z's rows and Z^T's rows, padded to texels.
#include "texel_buffer.glsl"
layout(local_size_x = 128) in;

layout(binding = 0) uniform textureBuffer by_row;     // rows x row_texels texels: Z's rows
layout(binding = 1) uniform textureBuffer by_column;  // cols x column_texels texels: Z's columns
// The final potentials, padded as the tiled kernel leaves them: u (rows, column_texels texels), v (cols,
// row_texels texels).
layout(std430, binding = 2) writeonly buffer RowPotential { vec4 u4[]; };
layout(std430, binding = 3) writeonly buffer ColumnPotential { vec4 v4[]; };

#include "push/sinkhorn_fused.h"

// Potentials padded to whole texels with zeros: kMaxTexels * 4 lines per axis (the host checks).
const uint kMaxTexels = 256;
shared vec4 potential[2][kMaxTexels];  // [0]: rows (u), [1]: columns (v)
uint other_axis = 1u;                 // the axis whose potential the current half reads
#define SINKHORN_OTHER(e) potential[other_axis][e]
#include "sinkhorn_line.glsl"

// Potential of `lines` lines of `couplings` into potential[axis], reading potential[1 - axis].
void half_iteration(textureBuffer couplings, uint axis, uint lines, uint texels, uint others) {
  other_axis = 1u - axis;
  for (uint t = gl_LocalInvocationID.x; t < lines; t += gl_WorkGroupSize.x) {
    const bool dustbin = t == lines - 1u;
    potential[axis][t / 4u][t % 4u] = sinkhorn_potential(couplings, t * texels, texels, dustbin, others, p.norm);
  }
  barrier();
}

void main() {
  for (uint t = gl_LocalInvocationID.x; t < kMaxTexels; t += gl_WorkGroupSize.x) {
    potential[0][t] = vec4(0);
    potential[1][t] = vec4(0);
  }
  barrier();
  for (uint it = 0; it < p.iterations; ++it) {
    half_iteration(by_row, 0u, p.rows, p.row_texels, p.cols - 1u);
    half_iteration(by_column, 1u, p.cols, p.column_texels, p.rows - 1u);
  }
  for (uint t = gl_LocalInvocationID.x; t < p.column_texels; t += gl_WorkGroupSize.x) u4[t] = potential[0][t];
  for (uint t = gl_LocalInvocationID.x; t < p.row_texels; t += gl_WorkGroupSize.x) v4[t] = potential[1][t];
}
