#version 450
// Winograd F(6x6, 3x3) input transform whose window is a 1-channel 3x3 convolution of an image computed on the
// fly (SuperPoint's conv1a before conv1b): winograd_input_stem.glsl.
#define WINOGRAD_TILE 6
#include "winograd_input_stem.glsl"
