// Push constants: SuperPoint's keypoint outputs and descriptor sampling (superpoint_sample.comp).
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_SAMPLE_H
#define VKVO_PUSH_SAMPLE_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(SamplePush) {
  uint cells_h;
  uint cells_w;
  uint dim;
  uint capacity;
  uint max_keypoints;
  uint subpixel;  // 1: keypoints refined to the score map's sub-pixel peak
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
