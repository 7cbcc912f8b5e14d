// Push constants: SuperPoint's input plane from an 8-bit image (superpoint_input.comp).
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_IMAGE_INPUT_H
#define VKVO_PUSH_IMAGE_INPUT_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(ImageInputPush) {
  uint width;
  uint height;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
