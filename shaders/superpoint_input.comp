#version 450
// SuperPoint input: an 8-bit grayscale image (four pixels packed per uint, row-major) -> one-channel tensor of
// the pixel values 0-255 (exact in 16 bits, where pixel / 255 is not; the host folds SuperPoint's 1/255 into
// conv1a's weights), with the 1-pixel zero border conv1a reads (never written: it stays zero).
#include "precision.glsl"
#include "tensor.glsl"

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Image { uint pixels[]; };
layout(std430, binding = 1) writeonly buffer Output { sfloat dst[]; };

#include "push/image_input.h"

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= p.width * p.height) return;
  const uint value = (pixels[i >> 2u] >> (8u * (i & 3u))) & 0xffu;
  dst[chw_index(0u, i / p.width, i % p.width, p.height, p.width, 1u)] = sfloat(float(value));
}
