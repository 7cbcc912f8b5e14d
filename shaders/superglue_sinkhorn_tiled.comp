#version 450
// One half-iteration of log-space Sinkhorn (formulas in superglue_sinkhorn.comp), always fp32, for devices that
// read RGBA32F texel buffers: the couplings of this axis' lines (Z for the rows, Z^T for the columns, so both
// halves walk rows in memory order) and the other axis' potential are fetched 4 entries at a time.
// superglue_sinkhorn.comp read both through storage buffers, which lavapipe loads one lane at a time, and walked
// the columns with a stride of a whole row: 0.2-3.7 s of SuperGlue's 1.1-12 s at N = 200-1000 on lavapipe.
// Lines are padded to whole texels with -1e30 (exp gives 0, the maximum ignores them) and the potentials with
// zeros.
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = 64) in;

layout(binding = 0) uniform samplerBuffer couplings;  // lines x (texels * 4): row t holds Z's line t of this axis
layout(binding = 1) uniform samplerBuffer other;      // the other axis' potential, texels * 4 entries
layout(std430, binding = 2) writeonly buffer Potential { float potential[]; };

layout(push_constant) uniform Params {
  uint lines;        // rows of Z (row half) or columns (column half), dustbin included
  uint line_length;  // entries per line, dustbin included
  uint texels;       // texels per padded line
  float norm;
} p;

const uint kBlock = 4;  // texels per step of the running maximum

void main() {
  const uint t = gl_GlobalInvocationID.x;
  if (t >= p.lines) return;
  const uint base = t * p.texels;
  // One pass over the line: a running maximum and the sum of exponentials relative to it, rescaled once per
  // block when the maximum grows. Two passes (maximum, then sum) fetched every texel twice, and on lavapipe each
  // fetch of the line is a gather of 8 lanes' rows that misses the cache (N = 1000: 0.2-0.4 s of SuperGlue).
  float peak = -3.0e38, total = 0.0;
  for (uint e0 = 0; e0 < p.texels; e0 += kBlock) {
    vec4 x[kBlock];
    [[unroll]] for (uint b = 0; b < kBlock; ++b) {
      const uint e = min(e0 + b, p.texels - 1u);  // past the end: clamped, and given no weight below
      const vec4 value = texelFetch(couplings, int(base + e)) + texelFetch(other, int(e));
      x[b] = e0 + b < p.texels ? value : vec4(-1.0e30);
    }
    const vec4 peak4 = max(max(x[0], x[1]), max(x[2], x[3]));
    const float block_peak = max(max(peak4.x, peak4.y), max(peak4.z, peak4.w));
    const float new_peak = max(peak, block_peak);
    vec4 sum4 = exp(x[0] - new_peak);
    [[unroll]] for (uint b = 1; b < kBlock; ++b) sum4 += exp(x[b] - new_peak);
    total = total * exp(peak - new_peak) + ((sum4.x + sum4.y) + (sum4.z + sum4.w));
    peak = new_peak;
  }
  const uint others = p.line_length - 1u;  // real points of the other set: mass of this set's dustbin
  const float marginal = t == p.lines - 1u ? log(float(others)) + p.norm : p.norm;
  potential[t] = marginal - (peak + log(total));
}
