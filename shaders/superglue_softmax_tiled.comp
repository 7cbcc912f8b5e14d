#version 450
// Attention softmax, scores read through a texel view of the storage precision (one gather per vec4 on lavapipe);
// used where the score buffer fits maxTexelBufferElements. The kernel: superglue_softmax_body.glsl.
#include "precision.glsl"
layout(binding = 0) uniform samplerBuffer scores_in;
#define LOAD4(index) texelFetch(scores_in, int(index))
#include "superglue_softmax_body.glsl"
