#version 450
// SuperPoint descriptor head after convDb: L2 normalisation over the channels of every cell (PyTorch's
// F.normalize, eps 1e-12), written as fp32 for sampling and for the dense output.
#include "precision.glsl"

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Input { sfloat src[]; };  // C x Hc x Wc, no border
layout(std430, binding = 1) writeonly buffer Output { float dst[]; };

#include "push/l2norm.h"

void main() {
  const uint cell = gl_GlobalInvocationID.x;
  if (cell >= p.cells) return;
  float s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;  // independent chains
  uint c = 0;
  for (; c + 4u <= p.channels; c += 4u) {
    const float a = float(src[c * p.cells + cell]), b = float(src[(c + 1u) * p.cells + cell]);
    const float d = float(src[(c + 2u) * p.cells + cell]), e = float(src[(c + 3u) * p.cells + cell]);
    s0 += a * a;
    s1 += b * b;
    s2 += d * d;
    s3 += e * e;
  }
  for (; c < p.channels; ++c) {
    const float a = float(src[c * p.cells + cell]);
    s0 += a * a;
  }
  const float inv = 1.0 / max(sqrt((s0 + s1) + (s2 + s3)), 1e-12);
  for (c = 0; c < p.channels; ++c) dst[c * p.cells + cell] = float(src[c * p.cells + cell]) * inv;
}
