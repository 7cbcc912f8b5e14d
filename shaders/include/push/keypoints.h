// Push constants: SuperGlue keypoint normalisation (superglue_keypoints.comp): set sizes and image sizes.
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_KEYPOINTS_H
#define VKVO_PUSH_KEYPOINTS_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(KeypointsPush) {
  uint n0, n1;
  float width0, height0, width1, height1;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
