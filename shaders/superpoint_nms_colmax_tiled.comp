#version 450
// Vertical half of SuperPoint's NMS max-pool and the suppression steps, the row maxima and the scores read
// through RGBA32F texel views; used where the map fits maxTexelBufferElements. The kernel:
// superpoint_nms_colmax_body.glsl.
#include "texel_buffer.glsl"
#extension GL_EXT_control_flow_attributes : require
layout(binding = 0) uniform textureBuffer rows;
layout(binding = 1) uniform textureBuffer scores;
#define LOAD_ROWS(index) texelFetch(rows, int(index))
#define LOAD_SCORES(index) texelFetch(scores, int(index))
#include "superpoint_nms_colmax_body.glsl"
