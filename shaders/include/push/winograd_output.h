// Push constants: Winograd output transforms (winograd_output.comp): one band of tiles, the output border and ReLU.
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_WINOGRAD_OUTPUT_H
#define VKVO_PUSH_WINOGRAD_OUTPUT_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(WinogradOutputPush) {
  uint channels;
  uint height;  // of the convolution (before any pooling)
  uint width;
  uint tiles_x;
  uint tiles;           // of this band
  uint first_tile_row;  // of this band
  uint out_pad;
  uint relu;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
