#version 450
// One half-iteration of log-space Sinkhorn on the (rows x cols) couplings Z with dustbins, always fp32:
//   axis 0: u_i = log_mu_i - logsumexp_j(Z_ij + v_j)      axis 1: v_j = log_nu_j - logsumexp_i(Z_ij + u_i)
// log_mu = norm for the rows < rows - 1 and log(cols - 1) + norm for the dustbin row (log_nu symmetric), with
// norm = -log(rows - 1 + cols - 1). One invocation per row (or column), two passes: max, then sum.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Couplings { float z[]; };
layout(std430, binding = 1) buffer RowPotential { float u[]; };
layout(std430, binding = 2) buffer ColPotential { float v[]; };

#include "push/sinkhorn.h"

void main() {
  const uint t = gl_GlobalInvocationID.x;
  const bool by_row = p.axis == 0u;
  const uint lines = by_row ? p.rows : p.cols;
  if (t >= lines) return;
  const uint length = by_row ? p.cols : p.rows;
  const uint base = by_row ? t * p.cols : t;
  const uint stride = by_row ? 1u : p.cols;
  float peak = -3.0e38;
  for (uint e = 0; e < length; ++e) peak = max(peak, z[base + e * stride] + (by_row ? v[e] : u[e]));
  float total = 0.0;
  for (uint e = 0; e < length; ++e) total += exp(z[base + e * stride] + (by_row ? v[e] : u[e]) - peak);
  const uint others = length - 1u;  // real points of the other set: mass of this set's dustbin
  const float marginal = t == lines - 1u ? log(float(others)) + p.norm : p.norm;
  const float value = marginal - (peak + log(total));
  if (by_row) u[t] = value; else v[t] = value;
}
