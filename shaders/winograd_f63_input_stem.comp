#version 450
// Winograd F(6x6, 3x3) input transform whose window is a 1-channel 3x3 convolution of an image computed on the
// fly (SuperPoint's conv1a before conv1b), 4 channels per invocation (winograd_f63_input_stem_wide.comp: 8):
// winograd_input_stem.glsl.
#define WINOGRAD_WIDE 0
#define WINOGRAD_TILE 6
#include "winograd_input_stem.glsl"
