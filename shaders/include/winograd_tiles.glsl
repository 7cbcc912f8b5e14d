// The Winograd tile a shader is built for, and how its invocations walk tiles. Define WINOGRAD_TILE (4 or 6: the
// output pixels per tile side of F(4x4, 3x3) or F(6x6, 3x3)) before inclusion; this includes that transform's
// header, which defines kWinogradTile, kWinogradInput, kWinogradPoints, winograd_input_1d and winograd_output_1d.
#ifndef VKVO_WINOGRAD_TILES_GLSL
#define VKVO_WINOGRAD_TILES_GLSL

#if WINOGRAD_TILE == 4
#include "winograd_f43.glsl"
#elif WINOGRAD_TILE == 6
#include "winograd_f63.glsl"
#else
#error "WINOGRAD_TILE must be 4 or 6"
#endif

// The tile and the block of channels (4, or 8 in the wide input transforms) an invocation of a transform takes:
// consecutive invocations take consecutive channel blocks of one tile (neighbouring lanes then read or write
// neighbouring addresses). Tiles are numbered row by row within a band of tile rows starting at first_tile_row.
struct WinogradTileBlock {
  uint tile;   // in the band
  uint block;  // channels n block .. n block + n - 1 for blocks of n
  uint ty, tx;
};

WinogradTileBlock winograd_tile_block(uint invocation, uint blocks, uint tiles_x, uint first_tile_row) {
  WinogradTileBlock t;
  t.tile = invocation / blocks;
  t.block = invocation - t.tile * blocks;
  const uint band_row = t.tile / tiles_x;
  t.tx = t.tile - band_row * tiles_x;
  t.ty = first_tile_row + band_row;
  return t;
}

#endif
