// Push constants: SuperGlue score matrix with dustbins (superglue_scores.comp, superglue_scores_tiled.comp).
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_SCORES_H
#define VKVO_PUSH_SCORES_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(ScoresPush) {
  uint n0, n1, dim;
  float scale, bin_score;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
