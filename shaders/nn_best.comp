#version 450
// Nearest neighbours in a similarity matrix S (n0 x n1, fp32, row-major): invocations [0, n0) scan rows and
// record the best column, its similarity and the second-best similarity (for the ratio test); invocations
// [n0, n0 + n1) scan columns for the best row. The first maximum wins ties.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Similarity { float s[]; };
layout(std430, binding = 1) writeonly buffer Best { int best[]; };            // n0 + n1
layout(std430, binding = 2) writeonly buffer BestValue { float best_value[]; };  // n0 + n1
layout(std430, binding = 3) writeonly buffer Second { float second_value[]; };   // n0 + n1

#include "push/set_sizes.h"

void main() {
  const uint t = gl_GlobalInvocationID.x;
  if (t >= p.n0 + p.n1) return;
  const bool by_row = t < p.n0;
  const uint line = by_row ? t : t - p.n0;
  const uint length = by_row ? p.n1 : p.n0;
  const uint base = by_row ? line * p.n1 : line;
  const uint stride = by_row ? 1u : p.n1;
  float first = -3.0e38, second = -3.0e38;
  int arg = 0;
  for (uint e = 0; e < length; ++e) {
    const float value = s[base + e * stride];
    if (value > first) {
      second = first;
      first = value;
      arg = int(e);
    } else if (value > second) {
      second = value;
    }
  }
  best[t] = arg;
  best_value[t] = first;
  second_value[t] = second;
}
