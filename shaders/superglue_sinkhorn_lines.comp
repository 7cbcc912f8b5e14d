#version 450
// One half-iteration of log-space Sinkhorn (formulas in superglue_sinkhorn.comp), always fp32, the GPU form of
// superglue_sinkhorn_tiled.comp (same bindings and push constants): a workgroup per line rather than an
// invocation. Each invocation keeps a running maximum and sum of exponentials over every 64th texel of the line,
// and the workgroup merges the 64 pairs in shared memory. One invocation walking a whole line suits a CPU's few
// threads; on a GPU it leaves most of the chip idle with long chains of dependent fetches (docs/performance-history.md, "SuperGlue").
#include "texel_buffer.glsl"
layout(local_size_x = 64) in;

layout(binding = 0) uniform textureBuffer couplings;  // lines x (texels * 4): row t holds Z's line t of this axis
layout(binding = 1) uniform textureBuffer other;      // the other axis' potential, texels * 4 entries
layout(std430, binding = 2) writeonly buffer Potential { float potential[]; };

#include "push/sinkhorn_half.h"

#define SINKHORN_OTHER(e) texelFetch(other, int(e))
#include "sinkhorn_line.glsl"

shared float peak_of[64], total_of[64];

// (peak, total) of two parts of a line: total relative to the larger peak. An empty part is (-3e38, 0).
void merge(inout float peak, inout float total, float other_peak, float other_total) {
  const float new_peak = max(peak, other_peak);
  total = total * exp(peak - new_peak) + other_total * exp(other_peak - new_peak);
  peak = new_peak;
}

void main() {
  const uint t = gl_WorkGroupID.x, lane = gl_LocalInvocationID.x;  // the host dispatches one group per line
  const uint base = t * p.texels;
  // Padding entries hold -1e30 (exp gives 0, the maximum ignores them).
  float peak = -3.0e38, total = 0.0;
  for (uint e = lane; e < p.texels; e += gl_WorkGroupSize.x) {
    const vec4 x = texelFetch(couplings, int(base + e)) + SINKHORN_OTHER(e);
    const float x_peak = max(max(x.x, x.y), max(x.z, x.w));
    const vec4 weights = exp(x - x_peak);
    merge(peak, total, x_peak, (weights.x + weights.y) + (weights.z + weights.w));
  }
  peak_of[lane] = peak;
  total_of[lane] = total;
  barrier();
  for (uint half_width = gl_WorkGroupSize.x / 2u; half_width > 0u; half_width /= 2u) {
    if (lane < half_width) {
      merge(peak, total, peak_of[lane + half_width], total_of[lane + half_width]);
      peak_of[lane] = peak;
      total_of[lane] = total;
    }
    barrier();
  }
  if (lane == 0u)
    potential[t] = sinkhorn_log_marginal(t == p.lines - 1u, p.line_length - 1u, p.norm) - (peak + log(total));
}
