#version 450
// Winograd input transform of a convolution whose input is itself a 1-channel 3x3 convolution + bias + ReLU of an
// image (SuperPoint's conv1a before conv1b): the window is computed here from the image, so the stem's
// full-resolution, 64-channel output is never stored nor read back. The transform and its layout:
// winograd_input_body.glsl. Defines (the shader table): WINOGRAD_TILE, WINOGRAD_WIDE.
//
// The image is a bordered 1-channel tensor (1-pixel border) read 4 values of a row per texel. Window position
// (r, x) is the stem's output at padded (m ty + r, m tx + x), the sum over its 3 x 3 taps of padded image rows
// m ty + r - 1 .. m ty + r + 1 and columns m tx + x - 1 .. m tx + x + 1: the (m + 4) x (m + 4) image block from
// padded (m ty - 1, m tx - 1). Its columns start in texel (m tx + 3) / 4 - 1 at value (m tx + 3) mod 4. Reads
// outside the tensor are clamped; they only reach positions off the image, which are zero.
#define TRANSFORMED_BINDING 3
#include "texel_buffer.glsl"
#include "winograd_input_body.glsl"

layout(binding = 0) uniform textureBuffer image;         // 4 consecutive values of a padded row per texel
layout(binding = 1) uniform textureBuffer stem_weights;  // "o4": texel block * 9 + tap, 4 output channels
layout(std430, binding = 2) readonly buffer StemBias { vec4 stem_bias[]; };

const uint kImageBlock = kWinogradInput + 2u;                // image rows and columns a window needs
const uint kImageBlockTexels = (kImageBlock + 3u + 3u) / 4u;  // enough for any start within a texel

void main() {
  TileBlock t;
  if (!tile_block(t)) return;
  const uint row_texels = row_stride(p.width, 1u) / 4u;
  const uint after_first = t.tx * kWinogradTile + 3u;  // padded column of the block's start, plus 4
  const int first_texel = int(after_first / 4u) - 1;
  const uint shift = after_first & 3u;

  float image_block[kImageBlock][kImageBlock];  // padded image (m ty - 1 + r, m tx - 1 + c)
  [[unroll]] for (uint r = 0; r < kImageBlock; ++r) {
    const uint row = min(max(t.ty * kWinogradTile + r, 1u) - 1u, p.height + 1u) * row_texels;
    float values[kImageBlockTexels * 4u];
    [[unroll]] for (uint k = 0; k < kImageBlockTexels; ++k) {
      const int column = clamp(first_texel + int(k), 0, int(row_texels) - 1);
      const vec4 texel = texelFetch(image, int(row) + column);
      [[unroll]] for (uint e = 0; e < 4u; ++e) values[k * 4u + e] = texel[e];
    }
    [[unroll]] for (uint c = 0; c < kImageBlock; ++c) image_block[r][c] = WINOGRAD_SHIFTED(values, c, shift);
  }
  vec4 d[kBlocks][kWinogradInput][kWinogradInput];  // the stem's ReLU'd output at window position (r, x)
  [[unroll]] for (uint h = 0; h < kBlocks; ++h) {
    const uint block = kBlocks * t.block + h;  // of 4 stem output channels
    vec4 w[9];
    [[unroll]] for (uint tap = 0; tap < 9u; ++tap) w[tap] = texelFetch(stem_weights, int(block * 9u + tap));
    const vec4 bias = stem_bias[block];
    [[unroll]] for (uint r = 0; r < kWinogradInput; ++r)
      [[unroll]] for (uint x = 0; x < kWinogradInput; ++x) {
        vec4 sum = bias;
        [[unroll]] for (uint tap = 0; tap < 9u; ++tap) sum += w[tap] * image_block[r + tap / 3u][x + tap % 3u];
        d[h][r][x] = on_image(t, r, x) ? max(sum, 0.0) : vec4(0.0);
      }
  }
  store_transformed(t, d);
}
