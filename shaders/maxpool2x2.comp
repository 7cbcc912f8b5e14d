#version 450
// 2x2 max-pool, stride 2 (PyTorch floor semantics: an odd last row/column is dropped).
#include "precision.glsl"
#include "tensor.glsl"

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Input { sfloat src[]; };
layout(std430, binding = 1) writeonly buffer Output { sfloat dst[]; };

#include "push/maxpool2x2.h"

void main() {
  const uint out_h = p.in_height / 2u, out_w = p.in_width / 2u;
  // x: pixel of one output plane, y: channel (a 1-D grid would exceed the 65535-group limit on large images)
  const uint i = gl_GlobalInvocationID.x;
  const uint c = gl_GlobalInvocationID.y;
  if (i >= out_h * out_w || c >= p.channels) return;
  const uint y = i / out_w;
  const uint x = i % out_w;
  const uint r = chw_index(c, 2u * y, 2u * x, p.in_height, p.in_width, p.in_pad);
  const uint row = row_stride(p.in_width, p.in_pad);
  const float m = max(max(float(src[r]), float(src[r + 1u])), max(float(src[r + row]), float(src[r + row + 1u])));
  dst[chw_index(c, y, x, out_h, out_w, p.out_pad)] = sfloat(m);
}
