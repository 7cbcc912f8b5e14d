#version 450
// Winograd F(4x4, 3x3) input transform of a convolution whose input is itself a 1-channel 3x3 convolution + bias +
// ReLU of an image (SuperPoint's conv1a before conv1b): the window is computed here from the image, so the stem's
// full-resolution, 64-channel output is never stored nor read back. The transform and its layout:
// winograd_f43_input_body.glsl.
//
// The image is a bordered 1-channel tensor (1-pixel border) read 4 values of a row per texel. Window position
// (r, x) is the stem's output at padded (4ty + r, 4tx + x), the sum over its 3 x 3 taps of padded image rows
// 4ty + r - 1 .. 4ty + r + 1 and columns 4tx + x - 1 .. 4tx + x + 1: the 8 x 8 image block from padded
// (4ty - 1, 4tx - 1), i.e. the last value of texel tx - 1, texel tx and the first 3 values of texel tx + 1 of 8
// rows. Reads outside the tensor are clamped; they only reach positions off the image, which are zero.
#define TRANSFORMED_BINDING 3
#include "texel_buffer.glsl"
#include "winograd_f43_input_body.glsl"

layout(binding = 0) uniform textureBuffer image;         // 4 consecutive values of a padded row per texel
layout(binding = 1) uniform textureBuffer stem_weights;  // "o4": texel block * 9 + tap, 4 output channels
layout(std430, binding = 2) readonly buffer StemBias { vec4 stem_bias[]; };

void main() {
  TileBlock t;
  if (!tile_block(t)) return;
  const uint row_texels = row_stride(p.width, 1u) / 4u;
  const uint col[3] = {max(t.tx, 1u) - 1u, min(t.tx, row_texels - 1u), min(t.tx + 1u, row_texels - 1u)};

  float block[8][8];  // padded image (4ty - 1 + r, 4tx - 1 + c)
  [[unroll]] for (uint r = 0; r < 8u; ++r) {
    const uint row = min(max(t.ty * kWinogradTile + r, 1u) - 1u, p.height + 1u) * row_texels;
    const vec4 before = texelFetch(image, int(row + col[0]));
    const vec4 head = texelFetch(image, int(row + col[1]));
    const vec4 tail = texelFetch(image, int(row + col[2]));
    block[r] = float[8](before.w, head.x, head.y, head.z, head.w, tail.x, tail.y, tail.z);
  }
  vec4 w[9];
  [[unroll]] for (uint tap = 0; tap < 9u; ++tap) w[tap] = texelFetch(stem_weights, int(t.block * 9u + tap));
  const vec4 bias = stem_bias[t.block];

  vec4 d[6][6];  // the stem's ReLU'd output at window position (r, x), one component per channel
  [[unroll]] for (uint r = 0; r < kWinogradInput; ++r)
    [[unroll]] for (uint x = 0; x < kWinogradInput; ++x) {
      vec4 sum = bias;
      [[unroll]] for (uint tap = 0; tap < 9u; ++tap) sum += w[tap] * block[r + tap / 3u][x + tap % 3u];
      d[r][x] = on_image(t, r, x) ? max(sum, 0.0) : vec4(0.0);
    }
  store_transformed(t, d);
}
