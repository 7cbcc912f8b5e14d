#version 450
// Winograd F(4x4, 3x3) input transform of a bordered activation, 4 channels per invocation (the form for devices
// without shaderInt64 and 4 mod 8 channels; winograd_f43_input_wide.comp otherwise): winograd_input_activation.glsl.
#define WINOGRAD_WIDE 0
#define WINOGRAD_TILE 4
#include "winograd_input_activation.glsl"
