#version 450
// Log-assignment from the Sinkhorn potentials, in place: P_ij = Z_ij + u_i + v_j - norm (fp32).
layout(local_size_x = 64) in;

layout(std430, binding = 0) buffer Couplings { float z[]; };
layout(std430, binding = 1) readonly buffer RowPotential { float u[]; };
layout(std430, binding = 2) readonly buffer ColPotential { float v[]; };

#include "push/assignment.h"

void main() {
  const uint e = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u;
  if (e >= p.rows * p.cols) return;
  const uint i = e / p.cols, j = e - i * p.cols;
  z[e] = z[e] + u[i] + v[j] - p.norm;
}
