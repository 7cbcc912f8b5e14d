// Winograd F(m x m, 3x3) input transform (m = WINOGRAD_TILE: winograd_tiles.glsl), shared by the transform of an
// activation (winograd_input_activation.glsl) and the one whose window is computed from an image by a 1-channel
// 3x3 convolution (winograd_input_stem.glsl). Each invocation takes the (m + 2) x (m + 2) window of one tile in 4
// channels and writes its (m + 2)^2 transformed values, V[point][tile][channel], so that the GEMM of each point
// reads a tile's channels as whole texels (A, M = tiles x K = channels). Consecutive invocations take consecutive
// channel blocks of a tile, so that neighbouring lanes store neighbouring addresses: with lanes walking tiles
// instead (256 bytes apart at 64 channels) SuperPoint 640x480 took 1.42 s instead of 1.14 s on lavapipe (F(4x4,
// 3x3), one run each; storing a quarter of the components measured no faster, so it is the scattered addresses,
// not the number of stores).
//
// Tile (ty, tx) covers output rows m ty .. m ty + m - 1 and columns m tx .. m tx + m - 1; its window is rows
// m ty - 1 .. m ty + m and columns m tx - 1 .. m tx + m of the convolution's input (padded rows and columns
// m ty .. m ty + m + 1 and m tx .. m tx + m + 1 of a 1-pixel bordered tensor). Window values outside the image
// are zero: the convolution's padding, and whatever lies past the bordered tensor is no pixel (the transforms
// would carry it into every output of the tile, a NaN poisoning them all).
//
// Define before inclusion: WINOGRAD_TILE, and TRANSFORMED_BINDING, the binding of the output buffer. The including
// header defines main() with a window of its own and calls store_transformed().
#extension GL_EXT_control_flow_attributes : require
#include "precision.glsl"
#include "tensor.glsl"
#include "winograd_tiles.glsl"

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = TRANSFORMED_BINDING) writeonly buffer Transformed { svec4 transformed[]; };

layout(push_constant) uniform Params {
  uint channels;  // of the transformed tensor, a multiple of 4
  uint height;    // of the image
  uint width;
  uint tiles_x;
  uint tiles;           // of this band
  uint first_tile_row;  // of this band
} p;

#define TileBlock WinogradTileBlock

// This invocation's tile and channel block; false past the band.
bool tile_block(out TileBlock t) {
  t = winograd_tile_block(gl_GlobalInvocationID.x, p.channels / 4u, p.tiles_x, p.first_tile_row);
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

// B^T d B of the window d[r][x] (one component per channel), stored at V[point][tile][channel block].
void store_transformed(const TileBlock t, const vec4 d[kWinogradInput][kWinogradInput]) {
  vec4 columns[kWinogradInput][kWinogradInput];  // columns[i][x] = (B^T d)[i][x]
  [[unroll]] for (uint x = 0; x < kWinogradInput; ++x) {
    vec4 column[kWinogradInput];
    [[unroll]] for (uint r = 0; r < kWinogradInput; ++r) column[r] = d[r][x];
    const vec4 c[kWinogradInput] = winograd_input_1d(column);
    [[unroll]] for (uint i = 0; i < kWinogradInput; ++i) columns[i][x] = c[i];
  }
  const uint blocks = p.channels / 4u;
  [[unroll]] for (uint i = 0; i < kWinogradInput; ++i) {
    const vec4 c[kWinogradInput] = winograd_input_1d(columns[i]);
    [[unroll]] for (uint j = 0; j < kWinogradInput; ++j)
      transformed[((i * kWinogradInput + j) * p.tiles + t.tile) * blocks + t.block] = svec4(c[j]);
  }
}
