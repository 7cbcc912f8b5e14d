// Push constants: SuperGlue's fused attention (superglue_attention_tiled.comp, superglue_attention_shared.comp).
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_ATTENTION_H
#define VKVO_PUSH_ATTENTION_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(AttentionPush) {
  uint queries;     // rows of the query set
  uint keys;        // rows of the key set
  uint query_row0;  // first qkv / state row of the query set
  uint key_row0;    // first qkv row of the key set
  uint dim;         // descriptor dimension (heads x head_dim)
  float scale;      // 1 / sqrt(head_dim)
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
