#version 450
// SuperGlue keypoint normalisation: row r of the keypoint-encoder input becomes [x', y', score, 0] with
// (x', y') = (kpt - [W/2, H/2]) / (0.7 * max(W, H)), each keypoint set normalised by its own image size. Rows
// [0, n0) are image 0's keypoints, [n0, n0 + n1) image 1's; the zero fourth column pads K to 4.
#include "precision.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Keypoints { float kpts[]; };  // (n0 + n1) x 2, pixels
layout(std430, binding = 1) readonly buffer Scores { float scores[]; };   // n0 + n1
layout(std430, binding = 2) writeonly buffer Encoded { sfloat encoded[]; };  // (n0 + n1) x 4

#include "push/keypoints.h"

void main() {
  const uint r = gl_GlobalInvocationID.x;
  if (r >= p.n0 + p.n1) return;
  const vec2 size = r < p.n0 ? vec2(p.width0, p.height0) : vec2(p.width1, p.height1);
  const vec2 xy = (vec2(kpts[2u * r], kpts[2u * r + 1u]) - 0.5 * size) / (0.7 * max(size.x, size.y));
  encoded[4u * r] = sfloat(xy.x);
  encoded[4u * r + 1u] = sfloat(xy.y);
  encoded[4u * r + 2u] = sfloat(scores[r]);
  encoded[4u * r + 3u] = sfloat(0.0);
}
