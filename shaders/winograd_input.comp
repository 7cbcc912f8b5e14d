#version 450
// Winograd input transform of a bordered activation (tensor.glsl, 1-pixel border) read 4 values of a row per texel,
// as conv3x3_tiled reads it: the window's padded columns m tx .. m tx + m + 1 start in texel (m tx) / 4 at value
// (m tx) mod 4, which is always 0 for F(4x4, 3x3) (two texels) and 0 or 2 for F(6x6, 3x3) (up to three). The
// transform and its layout: winograd_input_body.glsl. Defines (the shader table): WINOGRAD_TILE, WINOGRAD_WIDE.
#define TRANSFORMED_BINDING 1
#include "texel_buffer.glsl"
#include "winograd_input_body.glsl"

layout(binding = 0) uniform textureBuffer src;  // 4 consecutive values of a padded row per texel

const uint kWindowTexels = (kWinogradInput + 3u + 3u) / 4u;  // enough for any start within a texel

void main() {
  TileBlock t;
  if (!tile_block(t)) return;
  const uint row_texels = row_stride(p.width, 1u) / 4u;
  const uint plane = plane_size(p.height, p.width, 1u) / 4u;
  const uint first_column = t.tx * kWinogradTile, first_texel = first_column / 4u, shift = first_column & 3u;

  // d[h][r][x]: padded row m ty + r, column m tx + x of channel block kBlocks t.block + h, a component per channel
  vec4 d[kBlocks][kWinogradInput][kWinogradInput];
  [[unroll]] for (uint h = 0; h < kBlocks; ++h)
    [[unroll]] for (uint r = 0; r < kWinogradInput; ++r) {
      const uint row = min(t.ty * kWinogradTile + r, p.height + 1u) * row_texels;
      [[unroll]] for (uint c = 0; c < 4u; ++c) {
        const uint base = ((kBlocks * t.block + h) * 4u + c) * plane + row;
        float values[kWindowTexels * 4u];
        [[unroll]] for (uint k = 0; k < kWindowTexels; ++k) {
          const vec4 texel = texelFetch(src, int(base + min(first_texel + k, row_texels - 1u)));
          [[unroll]] for (uint e = 0; e < 4u; ++e) values[k * 4u + e] = texel[e];
        }
        [[unroll]] for (uint x = 0; x < kWinogradInput; ++x)
          d[h][r][x][c] = on_image(t, r, x) ? WINOGRAD_SHIFTED(values, x, shift) : 0.0;
      }
    }
  store_transformed(t, d);
}
