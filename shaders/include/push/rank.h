// Push constants: top-k ranking of SuperPoint's NMS candidates (superpoint_rank.comp).
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_RANK_H
#define VKVO_PUSH_RANK_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(RankPush) {
  uint capacity;
  uint max_keypoints;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
