#version 450
// Horizontal half of SuperPoint's (2r+1)x(2r+1) max-pool (stride 1, -inf padding): dst(y, x) = max of src over
// columns x-r..x+r that lie inside the image. superpoint_nms_colmax.comp finishes the pool.
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Source { float src[]; };
layout(std430, binding = 1) writeonly buffer Rows { float dst[]; };

layout(push_constant) uniform Params {
  uint width;
  uint height;
  uint radius;
} p;

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= p.width * p.height) return;
  const uint x = i % p.width;
  const uint row = i - x;
  const uint lo = x >= p.radius ? x - p.radius : 0u;
  const uint hi = min(x + p.radius, p.width - 1u);
  float m = src[row + lo];
  for (uint xx = lo + 1u; xx <= hi; ++xx) m = max(m, src[row + xx]);
  dst[i] = m;
}
