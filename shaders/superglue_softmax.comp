#version 450
// Row-wise softmax in place over `rows` rows of `cols` attention scores (all heads of one keypoint set), fp32
// math whatever the storage. One invocation per row: rows are many (heads x points), and the passes over a
// row stay in the invocation's cache.
//
// Rows whose length is a multiple of 4 are read and written 4 scores at a time, and the exponentials are
// recomputed in the last pass instead of being stored and read back: lavapipe loads and stores storage
// buffers in a scalar loop over the lanes per access, so 3 vec4 loads and 1 vec4 store per 4 scores cost a
// fifth of the 3 scalar loads and 2 scalar stores per score of the general path below.
#include "precision.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) buffer Scores { sfloat s[]; };
layout(std430, binding = 0) buffer Scores4 { svec4 s4[]; };

layout(push_constant) uniform Params {
  uint rows, cols;
} p;

void main() {
  const uint r = gl_GlobalInvocationID.x;
  if (r >= p.rows) return;
  const uint base = r * p.cols;
  if (p.cols % 4u == 0u) {  // the same for every invocation of the dispatch
    const uint base4 = base / 4u, cols4 = p.cols / 4u;
    vec4 peak4 = vec4(-3.0e38);
    for (uint j = 0; j < cols4; ++j) peak4 = max(peak4, vec4(s4[base4 + j]));
    const float peak = max(max(peak4.x, peak4.y), max(peak4.z, peak4.w));
    vec4 total4 = vec4(0.0);
    for (uint j = 0; j < cols4; ++j) total4 += exp(vec4(s4[base4 + j]) - peak);
    const float inv = 1.0 / (total4.x + total4.y + total4.z + total4.w);
    for (uint j = 0; j < cols4; ++j) s4[base4 + j] = svec4(exp(vec4(s4[base4 + j]) - peak) * inv);
    return;
  }
  float peak = -3.0e38;
  for (uint j = 0; j < p.cols; ++j) peak = max(peak, float(s[base + j]));
  float total = 0.0;
  for (uint j = 0; j < p.cols; ++j) {
    const float e = exp(float(s[base + j]) - peak);
    total += e;
    s[base + j] = sfloat(e);
  }
  const float inv = 1.0 / total;
  for (uint j = 0; j < p.cols; ++j) s[base + j] = sfloat(float(s[base + j]) * inv);
}
