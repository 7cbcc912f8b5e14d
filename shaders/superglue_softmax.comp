#version 450
// Row-wise softmax in place over `rows` rows of `cols` attention scores (all heads of one keypoint set), fp32
// math whatever the storage. One invocation per row: rows are many (heads x points), and the three passes over a
// row stay in the invocation's cache.
#include "precision.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) buffer Scores { sfloat s[]; };

layout(push_constant) uniform Params {
  uint rows, cols;
} p;

void main() {
  const uint r = gl_GlobalInvocationID.x;
  if (r >= p.rows) return;
  const uint base = r * p.cols;
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
