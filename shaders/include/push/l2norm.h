// Push constants: SuperPoint's descriptor normalisation (superpoint_l2norm.comp).
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_L2NORM_H
#define VKVO_PUSH_L2NORM_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(L2NormPush) {
  uint channels;
  uint cells;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
