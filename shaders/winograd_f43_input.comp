#version 450
// Winograd F(4x4, 3x3) input transform (winograd_f43.glsl): each invocation reads the 6 x 6 window of one tile
// in 4 input channels and writes its 36 transformed values, V[point][tile][channel], so that the GEMM of each
// point reads a tile's channels as whole texels (A, M = tiles x K = channels).
//
// The input is a bordered activation (tensor.glsl, 1-pixel border) read 4 values of a row per texel, as
// conv3x3_tiled reads it: tile (ty, tx) covers output rows 4ty .. 4ty + 3, whose window is padded rows
// 4ty .. 4ty + 5 and padded columns 4tx .. 4tx + 5: texel tx and the first half of texel tx + 1. Window values
// past the padded tensor (the last tiles of an image whose size is not a multiple of 4) are zero: whatever lies
// there would reach every output of the tile through the transforms.
#extension GL_EXT_control_flow_attributes : require
#include "precision.glsl"
#include "tensor.glsl"
#include "winograd_f43.glsl"

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(binding = 0) uniform samplerBuffer src;  // 4 consecutive values of a padded row per texel
layout(std430, binding = 1) writeonly buffer Transformed { svec4 transformed[]; };

layout(push_constant) uniform Params {
  uint channels;  // a multiple of 4
  uint height;
  uint width;
  uint tiles_x;
  uint tiles;           // of this band
  uint first_tile_row;  // of this band
} p;

void main() {
  const uint blocks = p.channels / 4u;
  const uint tile = gl_GlobalInvocationID.x / blocks, block = gl_GlobalInvocationID.x - tile * blocks;
  const uint c0 = block * 4u;
  if (tile >= p.tiles) return;
  const uint band_row = tile / p.tiles_x, tx = tile - band_row * p.tiles_x;
  const uint ty = p.first_tile_row + band_row;

  const uint row_texels = row_stride(p.width, 1u) / 4u;
  const uint plane = plane_size(p.height, p.width, 1u) / 4u;
  const uint padded_h = p.height + 2u, padded_w = p.width + 2u;
  const uint col[2] = {min(tx, row_texels - 1u), min(tx + 1u, row_texels - 1u)};

  // d[r][x]: padded row 4ty + r, column 4tx + x, one component per channel.
  vec4 d[6][6];
  [[unroll]] for (uint r = 0; r < kWinogradInput; ++r) {
    const uint y = ty * kWinogradTile + r;
    const uint row = min(y, padded_h - 1u) * row_texels;
    [[unroll]] for (uint c = 0; c < 4u; ++c) {
      const uint base = (c0 + c) * plane + row;
      const vec4 head = texelFetch(src, int(base + col[0]));
      const vec4 tail = texelFetch(src, int(base + col[1]));
      const float values[6] = {head.x, head.y, head.z, head.w, tail.x, tail.y};
      [[unroll]] for (uint x = 0; x < kWinogradInput; ++x) {
        const bool inside = y < padded_h && tx * kWinogradTile + x < padded_w;
        d[r][x][c] = inside ? values[x] : 0.0;
      }
    }
  }

  // B^T d B: the columns, then the rows.
  vec4 columns[6][6];  // columns[i][x] = (B^T d)[i][x]
  [[unroll]] for (uint x = 0; x < kWinogradInput; ++x) {
    const vec4 t[6] = winograd_f43_input_1d(vec4[6](d[0][x], d[1][x], d[2][x], d[3][x], d[4][x], d[5][x]));
    [[unroll]] for (uint i = 0; i < kWinogradInput; ++i) columns[i][x] = t[i];
  }
  [[unroll]] for (uint i = 0; i < kWinogradInput; ++i) {
    const vec4 t[6] = winograd_f43_input_1d(columns[i]);
    [[unroll]] for (uint j = 0; j < kWinogradInput; ++j)
      transformed[((i * kWinogradInput + j) * p.tiles + tile) * blocks + block] = svec4(t[j]);
  }
}
