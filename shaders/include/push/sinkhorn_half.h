// Push constants: one half-iteration of the texel-buffer Sinkhorn (superglue_sinkhorn_tiled.comp,
// superglue_sinkhorn_lines.comp).
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_SINKHORN_HALF_H
#define VKVO_PUSH_SINKHORN_HALF_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(SinkhornHalfPush) {
  uint lines;        // rows of Z (row half) or columns (column half), dustbin included
  uint line_length;  // entries per line, dustbin included
  uint texels;       // texels per padded line
  float norm;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
