#version 450
// Horizontal half of SuperPoint's NMS max-pool, the map read as a storage buffer (any device). The kernel:
// superpoint_nms_rowmax_body.glsl; superpoint_nms_rowmax_tiled.comp reads through a texel view instead.
#extension GL_EXT_control_flow_attributes : require
layout(std430, binding = 0) readonly buffer Source { vec4 src[]; };
#define LOAD_SRC(index) src[index]
#include "superpoint_nms_rowmax_body.glsl"
