#include "runtime/winograd.hpp"

#include <algorithm>
#include <array>
#include <span>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "runtime/context.hpp"
#include "runtime/push_constants.hpp"
#include "runtime/tensor_layout.hpp"

namespace vkvo::rt {
namespace {

using shader::WinogradInputPush;
using shader::WinogradOutputPush;

constexpr std::uint32_t kGroup = 64;  // local_size_x of the transform shaders

// G of F(4x4, 3x3) and of F(6x6, 3x3): the filter transform U = G g G^T ((m + 2) x 3), for the interpolation
// points of the shaders' B^T and A^T (shaders/include/winograd_f43.glsl, winograd_f63.glsl).
constexpr std::array<std::array<double, 3>, 6> kG43{{{1.0 / 4, 0, 0},
                                                     {-1.0 / 6, -1.0 / 6, -1.0 / 6},
                                                     {-1.0 / 6, 1.0 / 6, -1.0 / 6},
                                                     {1.0 / 24, 1.0 / 12, 1.0 / 6},
                                                     {1.0 / 24, -1.0 / 12, 1.0 / 6},
                                                     {0, 0, 1}}};
constexpr std::array<std::array<double, 3>, 8> kG63{{{1, 0, 0},
                                                     {-2.0 / 9, -2.0 / 9, -2.0 / 9},
                                                     {-2.0 / 9, 2.0 / 9, -2.0 / 9},
                                                     {1.0 / 90, 1.0 / 45, 2.0 / 45},
                                                     {1.0 / 90, -1.0 / 45, 2.0 / 45},
                                                     {32.0 / 45, 16.0 / 45, 8.0 / 45},
                                                     {32.0 / 45, -16.0 / 45, 8.0 / 45},
                                                     {0, 0, 1}}};

std::span<const std::array<double, 3>> filter_transform(WinogradConv3x3::Tile tile) {
  if (tile == WinogradConv3x3::Tile::f63) return kG63;
  return kG43;
}

// The transforms of each tile: the shader table's winograd_f43_* and winograd_f63_* ops.
struct TransformOps {
  Op input, input_wide, input_stem, input_stem_wide, output, output_maxpool;
};
TransformOps transform_ops(WinogradConv3x3::Tile tile) {
  if (tile == WinogradConv3x3::Tile::f63)
    return {Op::winograd_f63_input,           Op::winograd_f63_input_wide, Op::winograd_f63_input_stem,
            Op::winograd_f63_input_stem_wide, Op::winograd_f63_output,     Op::winograd_f63_output_maxpool};
  return {Op::winograd_f43_input,           Op::winograd_f43_input_wide, Op::winograd_f43_input_stem,
          Op::winograd_f43_input_stem_wide, Op::winograd_f43_output,     Op::winograd_f43_output_maxpool};
}

// The first `texel_bindings` bindings are read through RGBA texel views.
KernelSpec transform_spec(Op op, Precision precision, std::uint32_t texel_bindings = 1) {
  return {.op = op,
          .precision = precision,
          .texel_formats = std::vector<vk::Format>(texel_bindings, vec4_texel_format(precision))};
}

Precision checked_precision(const Context& context, Precision precision) {
  if (precision != Precision::fp32)
    throw std::invalid_argument("WinogradConv3x3: fp32 only (the transforms need more than 16-bit precision)");
  if (!tiled_kernels_available(context, precision))
    throw std::invalid_argument("WinogradConv3x3: the device does not read the RGBA32F texel buffers it needs");
  return precision;
}

}  // namespace

WinogradConv3x3::WinogradConv3x3(const Context& context, Precision precision, Tile tile, std::size_t max_band_bytes)
    : tile_(tile),
      input_transform_(context, transform_spec(transform_ops(tile).input, checked_precision(context, precision))),
      stem_input_transform_(context, transform_spec(transform_ops(tile).input_stem, precision, 2)),
      output_transform_(context, transform_spec(transform_ops(tile).output, precision)),
      output_pool_transform_(context, transform_spec(transform_ops(tile).output_maxpool, precision)),
      gemm_(context, precision),
      max_texel_elements_(context.caps().max_texel_buffer_elements),
      max_band_bytes_(std::min<std::size_t>({max_band_bytes, context.caps().max_storage_buffer_range,
                                             std::size_t(context.caps().max_texel_buffer_elements) * 16})) {
  if (context.caps().int64) {
    wide_input_transform_.emplace(context, transform_spec(transform_ops(tile).input_wide, precision));
    wide_stem_input_transform_.emplace(context, transform_spec(transform_ops(tile).input_stem_wide, precision, 2));
  }
}

std::vector<float> WinogradConv3x3::transform_weights(std::span<const float> o4, std::uint32_t out_channels,
                                                      std::uint32_t in_channels, Tile tile) {
  const std::size_t out4 = round_up(out_channels, 4);
  if (o4.size() != out4 * in_channels * 9)
    throw std::invalid_argument(
        fmt::format("WinogradConv3x3: {} weights are not a {}x{}x3x3 o4 tensor", o4.size(), out_channels, in_channels));
  const auto G = filter_transform(tile);
  const std::size_t n = G.size();  // m + 2
  std::vector<float> u(n * n * out4 * in_channels, 0.0f);
  for (std::size_t o = 0; o < out_channels; ++o)
    for (std::size_t i = 0; i < in_channels; ++i) {
      const auto g = [&](std::size_t r, std::size_t c) {
        return double(o4[(((o / 4) * in_channels + i) * 9 + r * 3 + c) * 4 + o % 4]);
      };
      double gg[kG63.size()][3] = {};  // G g (the first n rows)
      for (std::size_t a = 0; a < n; ++a)
        for (std::size_t c = 0; c < 3; ++c)
          for (std::size_t r = 0; r < 3; ++r) gg[a][c] += G[a][r] * g(r, c);
      for (std::size_t a = 0; a < n; ++a)
        for (std::size_t b = 0; b < n; ++b) {
          double value = 0;  // (G g G^T)[a][b]
          for (std::size_t c = 0; c < 3; ++c) value += gg[a][c] * G[b][c];
          u[((a * n + b) * out4 + o) * in_channels + i] = static_cast<float>(value);
        }
    }
  return u;
}

std::uint32_t WinogradConv3x3::band_rows(const ActivationShape& in, std::uint32_t out_channels) const {
  const std::size_t row_bytes = std::size_t(points(tile_)) * tiles_x(in) *
                                std::max<std::size_t>(in.channels, round_up(out_channels, 4)) * sizeof(float);
  return static_cast<std::uint32_t>(std::min<std::size_t>(tiles_y(in), max_band_bytes_ / row_bytes));
}

std::size_t WinogradConv3x3::transformed_input_bytes(const ActivationShape& in, std::uint32_t out_channels) const {
  return std::size_t(points(tile_)) * band_rows(in, out_channels) * tiles_x(in) * in.channels * sizeof(float);
}

std::size_t WinogradConv3x3::products_bytes(const ActivationShape& in, std::uint32_t out_channels) const {
  return std::size_t(points(tile_)) * band_rows(in, out_channels) * tiles_x(in) * round_up(out_channels, 4) *
         sizeof(float);
}

bool WinogradConv3x3::wide_input_transform(const ActivationShape& in) const {
  return wide_input_transform_.has_value() && in.channels % 8 == 0;
}

bool WinogradConv3x3::supports(const ActivationShape& in, std::uint32_t out_channels) const {
  return in.pad == 1 && in.channels % 4 == 0 && in.channels > 0 && out_channels > 0 && in.height > 0 && in.width > 0 &&
         in.elements() / 4 <= max_texel_elements_ && band_rows(in, out_channels) > 0;
}

void WinogradConv3x3::record(Sequence& seq, const Buffer& input, const ActivationShape& in, const Binding& weights,
                             const Binding& bias, const Buffer& transformed, const Buffer& products,
                             const Buffer& output, const ActivationShape& out, bool relu, bool max_pool,
                             const std::string& label, const Stem* stem) const {
  const std::uint32_t expected_h = max_pool ? in.height / 2 : in.height,
                      expected_w = max_pool ? in.width / 2 : in.width;
  if (out.height != expected_h || out.width != expected_w)
    throw std::invalid_argument(fmt::format("WinogradConv3x3 {}: a {}x{} input gives {}x{}, not {}x{}", label, in.width,
                                            in.height, expected_w, expected_h, out.width, out.height));
  if (!supports(in, out.channels))
    throw std::invalid_argument(fmt::format(
        "WinogradConv3x3 {}: needs a 1-pixel border, a multiple of 4 input channels and texel views within the "
        "device's {} elements ({} channels, {}x{})",
        label, max_texel_elements_, in.channels, in.width, in.height));
  const std::size_t input_bytes = transformed_input_bytes(in, out.channels);
  const std::size_t product_bytes = products_bytes(in, out.channels);
  if (transformed.size() < input_bytes || products.size() < product_bytes)
    throw std::invalid_argument(fmt::format("WinogradConv3x3 {}: scratch buffers too small", label));

  const std::uint32_t columns = tiles_x(in), rows = tiles_y(in), rows_per_band = band_rows(in, out.channels);
  const std::uint32_t out4 = static_cast<std::uint32_t>(round_up(out.channels, 4));
  const std::string prefix = fmt::format("{} winograd f{}3", label, side());  // "conv2a winograd f63 gemm"
  const Binding transformed_band(transformed, 0, input_bytes), products_band(products, 0, product_bytes);
  const bool wide = wide_input_transform(in);
  for (std::uint32_t first_row = 0; first_row < rows; first_row += rows_per_band) {
    const std::uint32_t band_tiles = std::min(rows_per_band, rows - first_row) * columns;
    const WinogradInputPush input_push{in.channels, in.height, in.width, columns, band_tiles, first_row};
    const Groups input_groups{groups_for(std::size_t(band_tiles) * (in.channels / (wide ? 8 : 4)), kGroup)};
    if (stem)
      seq.dispatch(wide ? *wide_stem_input_transform_ : stem_input_transform_,
                   {input, stem->weights, stem->bias, transformed_band}, input_push, input_groups,
                   prefix + " input+stem");
    else
      seq.dispatch(wide ? *wide_input_transform_ : input_transform_, {input, transformed_band}, input_push,
                   input_groups, prefix + " input");
    const GemmShape shape{.m = band_tiles,
                          .n = out4,
                          .k = in.channels,
                          .b_transposed = true,
                          .batch = points(tile_),
                          .a_batch_stride = band_tiles * in.channels,
                          .b_batch_stride = out4 * in.channels,
                          .c_batch_stride = band_tiles * out4};
    gemm_.record(seq, transformed_band, weights, nullptr, products_band, shape, prefix + " gemm");
    seq.dispatch(
        max_pool ? output_pool_transform_ : output_transform_, {products_band, bias, output},
        WinogradOutputPush{out.channels, in.height, in.width, columns, band_tiles, first_row, out.pad, relu ? 1u : 0u},
        {groups_for(std::size_t(band_tiles) * groups_for(out.channels, 4), kGroup)}, prefix + " output");
  }
}

}  // namespace vkvo::rt
