#version 450
// Horizontal half of SuperPoint's (2r+1)x(2r+1) max-pool (stride 1, -inf padding): dst(y, x) = max of the map
// over columns x-r..x+r that lie inside it. The colmax kernels finish the pool.
//
// Four adjacent pixels per invocation, read and written as vec4: the map's width is a multiple of 8 (whole
// cells), so rows are whole vec4s. Per invocation that is 2*ceil(r/4)+1 vec4 loads (3 at the default r = 4) for
// 4 outputs, where one pixel per invocation loaded 2r+1 floats for 1: lavapipe loads storage buffers one lane at
// a time, and fetches a texel with one gather call whatever its width.
//
// TEXEL_INPUTS (the shader table): 1 reads the map through an RGBA32F texel view (a gather per vec4 on lavapipe;
// the _tiled op, where the map fits maxTexelBufferElements), 0 through a storage buffer (any device).
#if TEXEL_INPUTS
#include "texel_buffer.glsl"
#endif
#extension GL_EXT_control_flow_attributes : require
#if TEXEL_INPUTS
layout(binding = 0) uniform textureBuffer src;
#define LOAD_SRC(index) texelFetch(src, int(index))
#else
layout(std430, binding = 0) readonly buffer Source { vec4 src[]; };
#define LOAD_SRC(index) src[index]
#endif
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 1) writeonly buffer Rows { vec4 dst[]; };

#include "push/nms_rows.h"

void main() {
  const uint row_vec4s = p.width / 4u;
  const uint t = gl_GlobalInvocationID.x;
  if (t >= row_vec4s * p.height) return;
  const int column = int(t % row_vec4s);
  const int row_start = int(t) - column;
  const int span = int((p.radius + 3u) / 4u);
  const int radius = int(p.radius);
  // Each output includes its own pixel (k = 0, j = i), so nothing stays at -inf.
  vec4 m = vec4(uintBitsToFloat(0xff800000u));
  for (int k = max(-span, -column); k <= min(span, int(row_vec4s) - 1 - column); ++k) {
    const vec4 v = LOAD_SRC(row_start + column + k);
    // Pixel j of vec4 k lies 4k + j - i columns from output i.
    [[unroll]] for (int j = 0; j < 4; ++j)
      [[unroll]] for (int i = 0; i < 4; ++i)
        if (abs(4 * k + j - i) <= radius) m[i] = max(m[i], v[j]);
  }
  dst[t] = m;
}
