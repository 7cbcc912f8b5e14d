#version 450
// One half-iteration of log-space Sinkhorn (formulas in superglue_sinkhorn.comp), always fp32, for devices that
// read RGBA32F texel buffers: the couplings of this axis' lines (Z for the rows, Z^T for the columns, so both
// halves walk rows in memory order) and the other axis' potential are fetched 4 entries at a time.
// superglue_sinkhorn.comp reads both through storage buffers, which lavapipe loads one lane at a time, and walks
// the columns with a stride of a whole row (docs/performance-history.md, "SuperGlue").
#include "texel_buffer.glsl"
layout(local_size_x = 64) in;

layout(binding = 0) uniform textureBuffer couplings;  // lines x (texels * 4): row t holds Z's line t of this axis
layout(binding = 1) uniform textureBuffer other;      // the other axis' potential, texels * 4 entries
layout(std430, binding = 2) writeonly buffer Potential { float potential[]; };

#include "push/sinkhorn_half.h"

#define SINKHORN_OTHER(e) texelFetch(other, int(e))
#include "sinkhorn_line.glsl"

void main() {
  const uint t = gl_GlobalInvocationID.x;
  if (t >= p.lines) return;
  potential[t] = sinkhorn_potential(couplings, t * p.texels, p.texels, t == p.lines - 1u, p.line_length - 1u, p.norm);
}
