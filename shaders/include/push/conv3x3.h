// Push constants: 3x3 convolution (conv3x3.comp, conv3x3_tiled.comp and its pooled form): the input shape (1-pixel
// border), the output border and ReLU.
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_CONV3X3_H
#define VKVO_PUSH_CONV3X3_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(Conv3x3Push) {
  uint in_channels;
  uint out_channels;
  uint height;
  uint width;
  uint out_pad;
  uint relu;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
