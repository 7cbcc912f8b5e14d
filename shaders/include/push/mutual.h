// Push constants: SuperGlue match extraction (superglue_mutual.comp).
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_MUTUAL_H
#define VKVO_PUSH_MUTUAL_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(MutualPush) {
  uint n0, n1;
  float threshold;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
