// Horizontal half of SuperPoint's (2r+1)x(2r+1) max-pool (stride 1, -inf padding): dst(y, x) = max of the map
// over columns x-r..x+r that lie inside it. The colmax kernels finish the pool.
//
// Four adjacent pixels per invocation, read and written as vec4: the map's width is a multiple of 8 (whole
// cells), so rows are whole vec4s. Per invocation that is 2*ceil(r/4)+1 vec4 loads (3 at the default r = 4) for
// 4 outputs, where one pixel per invocation loaded 2r+1 floats for 1: lavapipe loads storage buffers one lane at
// a time, and fetches a texel with one gather call whatever its width.
//
// The including file enables GL_EXT_control_flow_attributes and defines LOAD_SRC(index) (the map's vec4 at
// vec4 index `index`) and its binding 0; binding 1 is the output.
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 1) writeonly buffer Rows { vec4 dst[]; };

layout(push_constant) uniform Params {
  uint width;  // a multiple of 4
  uint height;
  uint radius;
} p;

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
