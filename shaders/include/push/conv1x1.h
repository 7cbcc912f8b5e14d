// Push constants: 1x1 convolution (conv1x1.comp, conv1x1_tiled.comp): activation shapes, borders and ReLU.
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_CONV1X1_H
#define VKVO_PUSH_CONV1X1_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(Conv1x1Push) {
  uint in_channels;
  uint out_channels;
  uint height;
  uint width;
  uint in_pad;
  uint out_pad;
  uint relu;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
