// Push constants: row-wise softmax of attention scores (superglue_softmax.comp).
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_SOFTMAX_H
#define VKVO_PUSH_SOFTMAX_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(SoftmaxPush) {
  uint rows, cols, stride;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
