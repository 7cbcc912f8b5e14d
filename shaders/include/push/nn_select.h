// Push constants: mutual nearest-neighbour selection (nn_select.comp).
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_NN_SELECT_H
#define VKVO_PUSH_NN_SELECT_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(NnSelectPush) {
  uint n0, n1;
  float max_cosine_distance, ratio;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
