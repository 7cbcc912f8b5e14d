#version 450
// Vertical half of SuperPoint's NMS max-pool and the suppression steps, inputs read as storage buffers (any
// device). The kernel: superpoint_nms_colmax_body.glsl; superpoint_nms_colmax_tiled.comp reads through texel views.
#extension GL_EXT_control_flow_attributes : require
layout(std430, binding = 0) readonly buffer Rows { vec4 rows[]; };
layout(std430, binding = 1) readonly buffer Scores { vec4 scores[]; };
#define LOAD_ROWS(index) rows[index]
#define LOAD_SCORES(index) scores[index]
#include "superpoint_nms_colmax_body.glsl"
