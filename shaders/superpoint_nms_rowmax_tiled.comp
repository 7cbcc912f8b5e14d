#version 450
// Horizontal half of SuperPoint's NMS max-pool, the map read through an RGBA32F texel view (a gather per vec4 on
// lavapipe); used where the map fits maxTexelBufferElements. The kernel: superpoint_nms_rowmax_body.glsl.
#include "texel_buffer.glsl"
#extension GL_EXT_control_flow_attributes : require
layout(binding = 0) uniform textureBuffer src;
#define LOAD_SRC(index) texelFetch(src, int(index))
#include "superpoint_nms_rowmax_body.glsl"
