// Push constants: Z's padded row and column copies (superglue_couplings_pad.comp).
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_COUPLINGS_PAD_H
#define VKVO_PUSH_COUPLINGS_PAD_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(CouplingsPadPush) {
  uint rows, cols, rows_padded, cols_padded;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
