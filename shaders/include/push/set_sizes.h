// Push constants: the sizes of the two keypoint sets (nn_best.comp, superglue_argmax.comp).
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_SET_SIZES_H
#define VKVO_PUSH_SET_SIZES_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(SetSizesPush) {
  uint n0, n1;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
