#pragma once
// 3x3 convolution (stride 1, pad 1) + bias (+ ReLU) (+ 2x2 max-pool) by Winograd's F(m x m, 3x3), m = 4 or 6: an
// input transform, a batch of (m + 2)^2 GEMMs (one per transformed point: tiles x in_channels times in_channels x
// out_channels) and an output transform (the shader table's winograd_f43_* and winograd_f63_* ops:
// shaders/winograd_input.comp, winograd_input_stem.comp, winograd_output.comp). F(4x4, 3x3) does 4x fewer
// multiply-adds than the direct convolution, F(6x6, 3x3) 5.1x, for two extra passes over memory. fp32 only (the
// table builds no other variant): F(4x4, 3x3)'s transforms scale values by up to 10 (input: B^T's largest absolute
// row sum) and 19 (output: A^T's) per dimension, F(6x6, 3x3)'s by 12.5 and 67, more than 16-bit storage's 11 bits
// can carry within the golden tolerances (docs/performance-history.md, "Precision").
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "runtime/buffer.hpp"
#include "runtime/kernel.hpp"
#include "runtime/ops.hpp"
#include "runtime/sequence.hpp"
#include "runtime/winograd_tile.hpp"

namespace vkvo::rt {

class WinogradConv3x3 {
 public:
  using Tile = WinogradTile;
  // Transformed values per tile ((m + 2)^2): the GEMM batch.
  static constexpr std::uint32_t points(Tile tile) { return (std::uint32_t(tile) + 2) * (std::uint32_t(tile) + 2); }

  // Scratch bytes per band by default: within lavapipe's 128 MiB storage-buffer range and a few times a desktop
  // CPU's last-level cache; larger bands measured no faster (docs/performance-history.md, "SuperPoint").
  static constexpr std::size_t kDefaultBandBytes = std::size_t(32) << 20;

  // Throws std::invalid_argument unless `precision` is fp32 and the device reads the tiled kernels' texel formats.
  // `max_band_bytes` is capped by the device's storage-buffer range and texel count.
  WinogradConv3x3(const Context& context, Precision precision, Tile tile,
                  std::size_t max_band_bytes = kDefaultBandBytes);

  Tile tile() const { return tile_; }

  // o4-layout 3x3 weights (runtime/tensor_layout.hpp) -> the GEMMs' B^T operands for `tile`, U = G g G^T:
  // [points(tile)][round_up(out_channels, 4)][in_channels] floats, padded output channels zero.
  static std::vector<float> transform_weights(std::span<const float> o4, std::uint32_t out_channels,
                                              std::uint32_t in_channels, Tile tile);

  // Tiles cover the image in rows of ceil(width / m); a convolution runs in bands of whole tile rows, so that
  // each band's scratch fits the device's storage-buffer range and texel count, and the band written by the input
  // transform is still in cache when its GEMMs read it.
  std::uint32_t tiles_x(const ActivationShape& in) const { return (in.width + side() - 1) / side(); }
  std::uint32_t tiles_y(const ActivationShape& in) const { return (in.height + side() - 1) / side(); }
  // Tile rows per band (0: not even one row fits).
  std::uint32_t band_rows(const ActivationShape& in, std::uint32_t out_channels) const;
  // Bytes of the scratch buffers a convolution of `in` to `out_channels` needs (one band): transformed input and
  // the GEMMs' products. One pair serves a whole network when sized for its largest layer.
  std::size_t transformed_input_bytes(const ActivationShape& in, std::uint32_t out_channels) const;
  std::size_t products_bytes(const ActivationShape& in, std::uint32_t out_channels) const;

  // Whether this op can run a convolution of `in` (1-pixel border, channels a multiple of 4) to `out_channels`
  // on this device: the input's texel view and one band's scratch must fit the device's limits.
  bool supports(const ActivationShape& in, std::uint32_t out_channels) const;

  // Whether the input transform of `in` takes 8 channels per invocation (one 32-byte store per transformed point:
  // the device has shaderInt64 and in.channels is a multiple of 8) rather than 4.
  bool wide_input_transform(const ActivationShape& in) const;

  // A 1-channel 3x3 convolution + bias + ReLU computed inside the input transform (SuperPoint's conv1a before
  // conv1b), so that its output is never stored: weights in the "o4" layout (in.channels x 1 x 3 x 3), bias fp32
  // padded to 4.
  struct Stem {
    Binding weights, bias;
  };

  // `weights`: transform_weights() output, bound at a 256-byte aligned offset; `bias`: fp32, padded to 4.
  // `transformed`, `products`: scratch of at least the sizes above. `out`: in's size, or half of it with
  // `max_pool` (floor). With a `stem`, `input` is the stem's 1-channel image (1-pixel border, in's size) and `in`
  // the shape of the stem's output. Records 3 dispatches per band.
  void record(Sequence& seq, const Buffer& input, const ActivationShape& in, const Binding& weights,
              const Binding& bias, const Buffer& transformed, const Buffer& products, const Buffer& output,
              const ActivationShape& out, bool relu, bool max_pool, const std::string& label,
              const Stem* stem = nullptr) const;

 private:
  std::uint32_t side() const { return static_cast<std::uint32_t>(tile_); }

  Tile tile_;
  Kernel input_transform_, stem_input_transform_, output_transform_, output_pool_transform_;
  // The input transforms that take 8 channels per invocation in 32-byte stores (winograd_input_body.glsl says
  // why), where the device has shaderInt64; they serve inputs whose channels are a multiple of 8.
  std::optional<Kernel> wide_input_transform_, wide_stem_input_transform_;
  Gemm gemm_;
  std::size_t max_texel_elements_;
  std::size_t max_band_bytes_;  // per scratch buffer
};

}  // namespace vkvo::rt
