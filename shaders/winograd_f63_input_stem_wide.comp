#version 450
// Winograd F(6x6, 3x3) input transform whose window is a 1-channel 3x3 convolution of an image computed on the
// fly, 8 channels per invocation in 32-byte stores (needs shaderInt64): winograd_input_stem.glsl.
#define WINOGRAD_WIDE 1
#define WINOGRAD_TILE 6
#include "winograd_input_stem.glsl"
