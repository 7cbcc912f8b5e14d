// Push constants: vertical half of SuperPoint's NMS and its suppression stages (superpoint_nms_colmax*.comp).
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_NMS_COLUMNS_H
#define VKVO_PUSH_NMS_COLUMNS_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(NmsColumnsPush) {
  uint width;  // a multiple of 4
  uint height;
  uint radius;
  uint border;
  float threshold;
  uint capacity;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
