#version 450
// Row and column maxima of the inner n0 x n1 block of the log-assignment (dustbins excluded): invocations
// [0, n0) scan rows, [n0, n0 + n1) scan columns. The first maximum wins ties (as torch.max).
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Assignment { float z[]; };  // (n0 + 1) x (n1 + 1)
layout(std430, binding = 1) writeonly buffer Best { int best[]; };      // n0 + n1 indices
layout(std430, binding = 2) writeonly buffer BestValue { float best_value[]; };

#include "push/set_sizes.h"

void main() {
  const uint t = gl_GlobalInvocationID.x;
  if (t >= p.n0 + p.n1) return;
  const bool by_row = t < p.n0;
  const uint line = by_row ? t : t - p.n0;
  const uint length = by_row ? p.n1 : p.n0;
  const uint cols = p.n1 + 1u;
  const uint base = by_row ? line * cols : line;
  const uint stride = by_row ? 1u : cols;
  float peak = z[base];
  int arg = 0;
  for (uint e = 1; e < length; ++e) {
    const float value = z[base + e * stride];
    if (value > peak) {
      peak = value;
      arg = int(e);
    }
  }
  best[t] = arg;
  best_value[t] = peak;
}
