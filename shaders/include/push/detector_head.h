// Push constants: SuperPoint's detector head (superpoint_detector_head.comp and its tiled form).
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_DETECTOR_HEAD_H
#define VKVO_PUSH_DETECTOR_HEAD_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(DetectorHeadPush) {
  uint in_channels;
  uint cells_h;
  uint cells_w;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
