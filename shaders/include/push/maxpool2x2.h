// Push constants: 2x2 max-pool (maxpool2x2.comp): the input shape and the borders of input and output.
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_MAXPOOL2X2_H
#define VKVO_PUSH_MAXPOOL2X2_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(MaxPoolPush) {
  uint channels;
  uint in_height;
  uint in_width;
  uint in_pad;
  uint out_pad;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
