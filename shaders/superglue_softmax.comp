#version 450
// Row-wise softmax in place over `rows` rows of `cols` attention scores (all heads of one keypoint set), fp32
// math whatever the storage. Rows start `stride` scores apart, a multiple of 4 (the host pads them), and the
// padding columns are set to zero probability: the p.v GEMM reads them, and the buffer is shared by layers
// whose strides differ, so they may hold another layer's scores. One invocation per row: rows are many (heads x
// points), and the passes over a row stay in the invocation's cache.
//
// Scores are read and written 4 at a time, and the exponentials are recomputed in the last pass instead of
// being stored and read back: lavapipe loads and stores storage buffers in a scalar loop over the lanes per
// access, so 3 vec4 loads and 1 vec4 store per 4 scores cost a fifth of 3 scalar loads and 2 scalar stores per
// score (docs/performance-history.md, "SuperGlue").
#include "precision.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) buffer Scores { sfloat s[]; };
layout(std430, binding = 0) buffer Scores4 { svec4 s4[]; };

#include "push/softmax.h"

void main() {
  const uint r = gl_GlobalInvocationID.x;
  if (r >= p.rows) return;
  const uint base = r * p.stride;
  const uint base4 = base / 4u, whole4 = p.cols / 4u, tail = 4u * whole4;  // scores past `tail`: one by one

  vec4 peak4 = vec4(-3.0e38);
  for (uint j = 0; j < whole4; ++j) peak4 = max(peak4, vec4(s4[base4 + j]));
  float peak = max(max(peak4.x, peak4.y), max(peak4.z, peak4.w));
  for (uint j = tail; j < p.cols; ++j) peak = max(peak, float(s[base + j]));

  vec4 total4 = vec4(0.0);
  for (uint j = 0; j < whole4; ++j) total4 += exp(vec4(s4[base4 + j]) - peak);
  float total = (total4.x + total4.y) + (total4.z + total4.w);
  for (uint j = tail; j < p.cols; ++j) total += exp(float(s[base + j]) - peak);

  const float inv = 1.0 / total;
  for (uint j = 0; j < whole4; ++j) s4[base4 + j] = svec4(exp(vec4(s4[base4 + j]) - peak) * inv);
  for (uint j = tail; j < p.cols; ++j) s[base + j] = sfloat(exp(float(s[base + j]) - peak) * inv);
  for (uint j = p.cols; j < p.stride; ++j) s[base + j] = sfloat(0.0);
}
