#version 450
// Attention softmax, scores read through a storage buffer (any device). The kernel: superglue_softmax_body.glsl;
// superglue_softmax_tiled.comp reads through a texel view instead.
#include "precision.glsl"
layout(std430, binding = 0) readonly buffer ScoresIn { svec4 scores_in[]; };
#define LOAD4(index) vec4(scores_in[index])
#include "superglue_softmax_body.glsl"
