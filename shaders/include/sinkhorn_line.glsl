// One line of a log-space Sinkhorn half-iteration (formulas in superglue_sinkhorn.comp): the new potential of
// line t is marginal - logsumexp_j (Z[t][j] + other[j]). Shared by superglue_sinkhorn_tiled.comp (one dispatch
// per half-iteration) and superglue_sinkhorn_fused.comp (all iterations in one workgroup);
// superglue_sinkhorn_lines.comp takes the marginal.
//
// Define before inclusion: SINKHORN_OTHER(e), texel e (4 entries) of the other axis' potential.
//
// Lines are padded to whole texels with -1e30 (exp gives 0, the maximum ignores them) and the potentials with
// zeros. One pass over the line: a running maximum and the sum of exponentials relative to it, rescaled once per
// block of 4 texels when the maximum grows. Two passes (maximum, then sum) would fetch every texel twice, and on
// lavapipe each fetch of the line is a gather of 8 lanes' rows that misses the cache.
#include "texel_buffer.glsl"
#extension GL_EXT_control_flow_attributes : require

const uint kSinkhornBlock = 4;  // texels per step of the running maximum

// log of line t's marginal: the normalisation `norm` (-log(N + M)), plus log(others) for the dustbin line.
float sinkhorn_log_marginal(bool dustbin, uint others, float norm) { return dustbin ? log(float(others)) + norm : norm; }

// couplings: the padded lines of this axis, `texels` texels each, line t's first at `base`. `others`: real
// points of the other set, the mass of this set's dustbin (the last line).
float sinkhorn_potential(textureBuffer couplings, uint base, uint texels, bool dustbin, uint others, float norm) {
  float peak = -3.0e38, total = 0.0;
  for (uint e0 = 0; e0 < texels; e0 += kSinkhornBlock) {
    vec4 x[kSinkhornBlock];
    [[unroll]] for (uint b = 0; b < kSinkhornBlock; ++b) {
      const uint e = min(e0 + b, texels - 1u);  // past the end: clamped, and given no weight below
      const vec4 value = texelFetch(couplings, int(base + e)) + SINKHORN_OTHER(e);
      x[b] = e0 + b < texels ? value : vec4(-1.0e30);
    }
    const vec4 peak4 = max(max(x[0], x[1]), max(x[2], x[3]));
    const float block_peak = max(max(peak4.x, peak4.y), max(peak4.z, peak4.w));
    const float new_peak = max(peak, block_peak);
    vec4 sum4 = exp(x[0] - new_peak);
    [[unroll]] for (uint b = 1; b < kSinkhornBlock; ++b) sum4 += exp(x[b] - new_peak);
    total = total * exp(peak - new_peak) + ((sum4.x + sum4.y) + (sum4.z + sum4.w));
    peak = new_peak;
  }
  return sinkhorn_log_marginal(dustbin, others, norm) - (peak + log(total));
}
