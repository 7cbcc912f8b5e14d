// Push constants: every Sinkhorn iteration in one workgroup (superglue_sinkhorn_fused.comp).
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_SINKHORN_FUSED_H
#define VKVO_PUSH_SINKHORN_FUSED_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(SinkhornFusedPush) {
  uint rows, cols;                  // of Z, dustbins included
  uint row_texels, column_texels;   // texels per padded row (cols / 4 rounded up) and per padded column
  uint iterations;
  float norm;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
