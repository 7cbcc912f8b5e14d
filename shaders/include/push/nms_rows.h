// Push constants: horizontal half of SuperPoint's NMS max-pool (superpoint_nms_rowmax*.comp).
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_NMS_ROWS_H
#define VKVO_PUSH_NMS_ROWS_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(NmsRowsPush) {
  uint width;  // a multiple of 4
  uint height;
  uint radius;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
