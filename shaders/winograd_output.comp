#version 450
// Winograd F(m x m, 3x3) output transform (m = WINOGRAD_TILE: winograd_tiles.glsl) + bias (+ ReLU) (+ 2x2
// max-pool) (the ops winograd_f*_output and winograd_f*_output_maxpool). Each invocation reads the
// (m + 2)^2 transformed-domain sums of one tile in 4 output channels (the GEMMs' C, [point][tile][channel], through
// a texel view: one texel per point), computes A^T M A and stores the tile's m x m pixels, or their 2 x 2
// max-pool, into a bordered (or dense) activation. Pixels past the image are not stored.
//
// Defines (the shader table): WINOGRAD_TILE, and VKVO_WINOGRAD_MAXPOOL to store the pooled tile (floor semantics, as
// maxpool2x2.comp; m is even).
#include "texel_buffer.glsl"
#extension GL_EXT_control_flow_attributes : require
#include "precision.glsl"
#include "tensor.glsl"
#include "winograd_tiles.glsl"

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(binding = 0) uniform textureBuffer products;  // [(m + 2)^2][tiles][ceil(channels / 4)] vec4s
layout(std430, binding = 1) readonly buffer Bias { vec4 bias[]; };
layout(std430, binding = 2) writeonly buffer Output { sfloat dst[]; };

#include "push/winograd_output.h"

void main() {
  const uint blocks = (p.channels + 3u) / 4u;
  const WinogradTileBlock at = winograd_tile_block(gl_GlobalInvocationID.x, blocks, p.tiles_x, p.first_tile_row);
  if (at.tile >= p.tiles) return;
  const uint tile = at.tile, block = at.block, ty = at.ty, tx = at.tx;

  // A^T M A: the columns, then the rows.
  vec4 rows[kWinogradTile][kWinogradInput];  // rows[a][j] = (A^T M)[a][j]
  [[unroll]] for (uint j = 0; j < kWinogradInput; ++j) {
    vec4 m[kWinogradInput];
    [[unroll]] for (uint i = 0; i < kWinogradInput; ++i)
      m[i] = texelFetch(products, int(((i * kWinogradInput + j) * p.tiles + tile) * blocks + block));
    const vec4 t[kWinogradTile] = winograd_output_1d(m);
    [[unroll]] for (uint a = 0; a < kWinogradTile; ++a) rows[a][j] = t[a];
  }
  const vec4 b = bias[block];
  vec4 y[kWinogradTile][kWinogradTile];
  [[unroll]] for (uint a = 0; a < kWinogradTile; ++a) {
    const vec4 t[kWinogradTile] = winograd_output_1d(rows[a]);
    [[unroll]] for (uint x = 0; x < kWinogradTile; ++x) y[a][x] = p.relu != 0u ? max(t[x] + b, 0.0) : t[x] + b;
  }

#ifdef VKVO_WINOGRAD_MAXPOOL
  // ReLU commutes with the max, so pooling after it stores what conv + maxpool2x2.comp would.
  const uint out_h = p.height / 2u, out_w = p.width / 2u, out_tile = kWinogradTile / 2u;
  vec4 out_values[kWinogradTile / 2u][kWinogradTile / 2u];
  [[unroll]] for (uint a = 0; a < out_tile; ++a)
    [[unroll]] for (uint x = 0; x < out_tile; ++x)
      out_values[a][x] = max(max(y[2u * a][2u * x], y[2u * a][2u * x + 1u]),
                             max(y[2u * a + 1u][2u * x], y[2u * a + 1u][2u * x + 1u]));
#else
  const uint out_h = p.height, out_w = p.width, out_tile = kWinogradTile;
#define out_values y
#endif
  [[unroll]] for (uint a = 0; a < out_tile; ++a) {
    const uint oy = ty * out_tile + a;
    [[unroll]] for (uint x = 0; x < out_tile; ++x) {
      const uint ox = tx * out_tile + x;
      if (oy >= out_h || ox >= out_w) continue;
      [[unroll]] for (uint c = 0; c < 4u; ++c) {
        const uint channel = block * 4u + c;
        if (channel < p.channels) dst[chw_index(channel, oy, ox, out_h, out_w, p.out_pad)] = sfloat(out_values[a][x][c]);
      }
    }
  }
}
