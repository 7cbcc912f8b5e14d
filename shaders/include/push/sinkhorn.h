// Push constants: one half-iteration of the storage-buffer Sinkhorn (superglue_sinkhorn.comp).
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_SINKHORN_H
#define VKVO_PUSH_SINKHORN_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(SinkhornPush) {
  uint rows, cols, axis;
  float norm;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
