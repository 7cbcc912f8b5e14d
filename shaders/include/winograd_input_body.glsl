// Winograd F(m x m, 3x3) input transform (m = WINOGRAD_TILE: winograd_tiles.glsl), shared by the transform of an
// activation (winograd_input.comp) and the one whose window is computed from an image by a 1-channel
// 3x3 convolution (winograd_input_stem.comp). Each invocation takes the (m + 2) x (m + 2) window of one tile in
// kChannels channels (kBlocks blocks of 4) and writes its (m + 2)^2 transformed values, V[point][tile][channel],
// so that the GEMM of each point reads a tile's channels as whole texels (A, M = tiles x K = channels).
// Consecutive invocations take consecutive channel blocks of a tile, so that neighbouring lanes store
// neighbouring addresses (lanes walking tiles store 256 bytes apart at 64 channels).
//
// The wide form (WINOGRAD_WIDE 1, 8 channels, where the device has shaderInt64 and the channels are a multiple of
// 8) stores each point's 8 values as one u64vec4. Stores bound this kernel on lavapipe: it writes a storage buffer
// lane by lane in a loop (about 70 instructions per lane per vec4 store in its JIT code), and a 32-byte store
// costs about what a 16-byte one does (docs/performance-history.md, "SuperPoint").
//
// Tile (ty, tx) covers output rows m ty .. m ty + m - 1 and columns m tx .. m tx + m - 1; its window is rows
// m ty - 1 .. m ty + m and columns m tx - 1 .. m tx + m of the convolution's input (padded rows and columns
// m ty .. m ty + m + 1 and m tx .. m tx + m + 1 of a 1-pixel bordered tensor). Window values outside the image
// are zero: the convolution's padding, and whatever lies past the bordered tensor is no pixel (the transforms
// would carry it into every output of the tile, a NaN poisoning them all).
//
// Define before inclusion: WINOGRAD_TILE, WINOGRAD_WIDE (0 or 1) and TRANSFORMED_BINDING, the binding of the output
// buffer. The including header defines main() with a window of its own and calls store_transformed().
#extension GL_EXT_control_flow_attributes : require
#if WINOGRAD_WIDE
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#endif
#include "precision.glsl"
#include "tensor.glsl"
#include "winograd_tiles.glsl"

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

#if WINOGRAD_WIDE
const uint kBlocks = 2;  // blocks of 4 channels per invocation
layout(std430, binding = TRANSFORMED_BINDING) writeonly buffer Transformed { u64vec4 transformed[]; };
#else
const uint kBlocks = 1;
layout(std430, binding = TRANSFORMED_BINDING) writeonly buffer Transformed { svec4 transformed[]; };
#endif
const uint kChannels = 4 * kBlocks;  // per invocation

#include "push/winograd_input.h"

#define TileBlock WinogradTileBlock

// This invocation's tile and group of kChannels channels (t.block); false past the band.
bool tile_block(out TileBlock t) {
  t = winograd_tile_block(gl_GlobalInvocationID.x, p.channels / kChannels, p.tiles_x, p.first_tile_row);
  return t.tile < p.tiles;
}

// Whether window position (r, x) of tile t lies on the image (else it is the convolution's zero padding).
bool on_image(const TileBlock t, uint r, uint x) {
  const uint y = t.ty * kWinogradTile + r, column = t.tx * kWinogradTile + x;  // padded coordinates
  return y >= 1u && y <= p.height && column >= 1u && column <= p.width;
}

// Value `index` + `shift` of a row read as consecutive texels, for a shift of 0 .. 3 known only at run time: a
// select among constant indices (which stays in registers) instead of a dynamically indexed array (which lavapipe
// would keep in memory). A shift the compiler can prove constant folds the selects away.
#define WINOGRAD_SHIFTED(values, index, shift)                                                    \
  ((shift) == 0u ? values[index] : (shift) == 1u ? values[(index) + 1u]                           \
                                 : (shift) == 2u ? values[(index) + 2u] : values[(index) + 3u])

// B^T d B of the window d[r][x] (one component per channel), in place: d[i][j] becomes transformed point
// (m + 2) i + j.
void winograd_input_2d(inout vec4 d[kWinogradInput][kWinogradInput]) {
  vec4 columns[kWinogradInput][kWinogradInput];  // columns[i][x] = (B^T d)[i][x]
  [[unroll]] for (uint x = 0; x < kWinogradInput; ++x) {
    vec4 column[kWinogradInput];
    [[unroll]] for (uint r = 0; r < kWinogradInput; ++r) column[r] = d[r][x];
    const vec4 c[kWinogradInput] = winograd_input_1d(column);
    [[unroll]] for (uint i = 0; i < kWinogradInput; ++i) columns[i][x] = c[i];
  }
  [[unroll]] for (uint i = 0; i < kWinogradInput; ++i) d[i] = winograd_input_1d(columns[i]);
}

// The transforms of the windows d[h] of channel blocks kBlocks t.block + h, stored at V[point][tile][channel]: one
// store of kChannels values per point.
void store_transformed(const TileBlock t, vec4 d[kBlocks][kWinogradInput][kWinogradInput]) {
  [[unroll]] for (uint h = 0; h < kBlocks; ++h) winograd_input_2d(d[h]);
  const uint groups = p.channels / kChannels;
  [[unroll]] for (uint i = 0; i < kWinogradInput; ++i)
    [[unroll]] for (uint j = 0; j < kWinogradInput; ++j) {
      const uint at = ((i * kWinogradInput + j) * p.tiles + t.tile) * groups + t.block;
#if WINOGRAD_WIDE
      const uvec4 lo = floatBitsToUint(d[0][i][j]), hi = floatBitsToUint(d[1][i][j]);
      transformed[at] = u64vec4(pack64(lo.xy), pack64(lo.zw), pack64(hi.xy), pack64(hi.zw));
#else
      transformed[at] = svec4(d[0][i][j]);
#endif
    }
}
