// Push constants: Winograd input transforms (winograd_input*.comp): one band of tiles.
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_WINOGRAD_INPUT_H
#define VKVO_PUSH_WINOGRAD_INPUT_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(WinogradInputPush) {
  uint channels;  // of the transformed tensor, a multiple of kChannels
  uint height;    // of the image
  uint width;
  uint tiles_x;
  uint tiles;           // of this band
  uint first_tile_row;  // of this band
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
