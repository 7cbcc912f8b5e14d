#version 450
// Winograd F(4x4, 3x3) input transform of a bordered activation (tensor.glsl, 1-pixel border) read 4 values of a
// row per texel, as conv3x3_tiled reads it: the window's padded columns 4tx .. 4tx + 5 are texel tx and the first
// half of texel tx + 1. The transform and its layout: winograd_f43_input_body.glsl.
#define TRANSFORMED_BINDING 1
#include "texel_buffer.glsl"
#include "winograd_f43_input_body.glsl"

layout(binding = 0) uniform textureBuffer src;  // 4 consecutive values of a padded row per texel

void main() {
  TileBlock t;
  if (!tile_block(t)) return;
  const uint row_texels = row_stride(p.width, 1u) / 4u;
  const uint plane = plane_size(p.height, p.width, 1u) / 4u;
  const uint col[2] = {min(t.tx, row_texels - 1u), min(t.tx + 1u, row_texels - 1u)};

  vec4 d[6][6];  // d[r][x]: padded row 4ty + r, column 4tx + x, one component per channel
  [[unroll]] for (uint r = 0; r < kWinogradInput; ++r) {
    const uint row = min(t.ty * kWinogradTile + r, p.height + 1u) * row_texels;
    [[unroll]] for (uint c = 0; c < 4u; ++c) {
      const uint base = (t.block * 4u + c) * plane + row;
      const vec4 head = texelFetch(src, int(base + col[0]));
      const vec4 tail = texelFetch(src, int(base + col[1]));
      const float values[6] = {head.x, head.y, head.z, head.w, tail.x, tail.y};
      [[unroll]] for (uint x = 0; x < kWinogradInput; ++x) d[r][x][c] = on_image(t, r, x) ? values[x] : 0.0;
    }
  }
  store_transformed(t, d);
}
