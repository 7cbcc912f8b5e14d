// The Winograd F(4x4, 3x3) and F(6x6, 3x3) convolutions (runtime/winograd.hpp) against the plain C++ convolution
// (and max-pool), at sizes that leave partial tiles and partial 64-tile workgroups, and their filter transforms
// against the closed form.
#include <limits>

#include <gtest/gtest.h>

#include "common/gpu.hpp"
#include "conv_reference.hpp"
#include "kernel_test_util.hpp"
#include "runtime/context.hpp"
#include "runtime/tensor_layout.hpp"
#include "runtime/winograd.hpp"

namespace vkvo::rt {
namespace {

using test::gpu;

bool winograd_available() { return tiled_kernels_available(gpu(), Precision::fp32); }

using Tile = WinogradConv3x3::Tile;
constexpr Tile kTiles[] = {Tile::f43, Tile::f63};

struct WinogradCase {
  int in_c, out_c, h, w, out_pad;
  bool relu, max_pool;
  // Scratch for this many tile rows a band (0: the default band size), plus a few bytes that round down.
  std::uint32_t band_rows = 0;
  // The input is the ReLU'd output of a 1-channel 3x3 convolution of an image, computed in the input transform.
  bool stem = false;
};

// The transforms are exact in exact arithmetic; in fp32 F(4x4, 3x3) scales intermediate values by up to 10 (B^T's
// rows sum to 10 in absolute value) and its output transform's 8s amplify the products' rounding, so the error
// bound is 2e-5 of the output scale, against the direct kernels' 1e-5 (kernel_test_util.hpp). F(6x6, 3x3)'s
// constants are larger (B^T's rows sum to 12.5, A^T has 32s): bound 4e-5 of the scale. What both measure here:
// docs/accuracy.md.
float winograd_tolerance(const std::vector<float>& reference, Tile tile) {
  float scale = 0;
  for (float r : reference) scale = std::max(scale, std::abs(r));
  return (tile == Tile::f43 ? 2e-5f : 4e-5f) * scale + 1e-6f;
}

// The columns that round a bordered row up to whole texels (past the right border) belong to no pixel; no kernel
// writes them, and a tile reading them must not let them reach its outputs: NaN there would poison the whole tile
// through the transforms unless the input transform reads zeros past the border.
std::vector<float> with_nan_row_padding(std::vector<float> bordered, const ActivationShape& shape) {
  const std::size_t stride = shape.row_stride(), used = shape.width + 2 * shape.pad;
  for (std::size_t row = 0; row < bordered.size() / stride; ++row)
    for (std::size_t x = used; x < stride; ++x) bordered[row * stride + x] = std::numeric_limits<float>::quiet_NaN();
  return bordered;
}

void check_winograd(const WinogradCase& c, std::uint32_t seed, Tile tile, const Context& ctx = gpu()) {
  const auto image = test::random_values(std::size_t(c.h) * c.w, seed + 3, 0.0f, 1.0f);
  const auto stem_weights = test::random_values(std::size_t(c.in_c) * 9, seed + 4, -0.5f, 0.5f);
  const auto stem_bias = test::random_values(c.in_c, seed + 5, -0.2f, 0.2f);
  const auto input = c.stem ? test::reference_conv(image, stem_weights, stem_bias, 1, c.in_c, c.h, c.w, 3, true)
                            : test::random_values(std::size_t(c.in_c) * c.h * c.w, seed);
  const auto weights = test::random_values(std::size_t(c.out_c) * c.in_c * 9, seed + 1, -0.5f, 0.5f);
  const auto bias = test::random_values(c.out_c, seed + 2);
  const auto conv = test::reference_conv(input, weights, bias, c.in_c, c.out_c, c.h, c.w, 3, c.relu);
  const auto expected = c.max_pool ? test::reference_max_pool(conv, c.out_c, c.h, c.w) : conv;

  const int oh = c.max_pool ? c.h / 2 : c.h, ow = c.max_pool ? c.w / 2 : c.w;
  const ActivationShape in{std::uint32_t(c.in_c), std::uint32_t(c.h), std::uint32_t(c.w), 1};
  const ActivationShape out{std::uint32_t(c.out_c), std::uint32_t(oh), std::uint32_t(ow), std::uint32_t(c.out_pad)};
  const Precision fp32 = Precision::fp32;
  const ActivationShape image_shape{1, std::uint32_t(c.h), std::uint32_t(c.w), 1};
  auto in_buf =
      c.stem
          ? test::upload_tensor(ctx, with_nan_row_padding(test::add_border(image, 1, c.h, c.w, 1), image_shape), fp32)
          : test::upload_tensor(ctx, with_nan_row_padding(test::add_border(input, c.in_c, c.h, c.w, 1), in), fp32);
  auto stem_w_buf = test::upload_tensor(ctx, pack_conv_o4(stem_weights, c.in_c, 1, 3, 3), fp32);
  Buffer stem_b_buf(ctx, round_up(c.in_c, 4) * sizeof(float));
  stem_b_buf.upload(std::span<const float>(pad_bias_o4(stem_bias)));
  const WinogradConv3x3::Stem stem{Binding(stem_w_buf), Binding(stem_b_buf)};
  const auto transformed_weights = WinogradConv3x3::transform_weights(
      pack_conv_o4(weights, c.out_c, c.in_c, 3, 3), std::uint32_t(c.out_c), std::uint32_t(c.in_c), tile);
  auto w_buf = test::upload_tensor(ctx, transformed_weights, fp32);
  Buffer b_buf(ctx, round_up(c.out_c, 4) * sizeof(float));
  b_buf.upload(std::span<const float>(pad_bias_o4(bias)));
  const WinogradConv3x3 sizing(ctx, fp32, tile);
  const std::size_t row_bytes = std::size_t(WinogradConv3x3::points(tile)) * sizing.tiles_x(in) *
                                std::max<std::size_t>(c.in_c, round_up(c.out_c, 4)) * sizeof(float);
  const WinogradConv3x3 op(ctx, fp32, tile,
                           c.band_rows ? c.band_rows * row_bytes + 5 : WinogradConv3x3::kDefaultBandBytes);
  if (c.band_rows) {
    ASSERT_EQ(op.band_rows(in, out.channels), c.band_rows);
  }
  ASSERT_TRUE(op.supports(in, out.channels));
  Buffer transformed(ctx, op.transformed_input_bytes(in, out.channels));
  Buffer products(ctx, op.products_bytes(in, out.channels));
  Buffer out_buf(ctx, activation_bytes(out, fp32));
  out_buf.fill_zero();

  Sequence seq(ctx);
  seq.begin();
  op.record(seq, in_buf, in, w_buf, b_buf, transformed, products, out_buf, out, c.relu, c.max_pool, "conv",
            c.stem ? &stem : nullptr);
  seq.end();
  seq.submit();
  const auto padded = test::download_tensor(out_buf, out.elements(), fp32);
  const auto got = test::strip_border(padded, c.out_c, oh, ow, c.out_pad);
  EXPECT_LE(test::max_abs_diff(got, expected), winograd_tolerance(conv, tile))
      << "winograd F(" << std::uint32_t(tile) << "x" << std::uint32_t(tile) << ", 3x3) conv "
      << (c.stem ? "(after a 1-channel stem) " : "") << c.in_c << "->" << c.out_c << " at " << c.w << "x" << c.h
      << (c.max_pool ? " + maxpool" : "") << ", "
      << (op.tiles_y(in) + op.band_rows(in, out.channels) - 1) / op.band_rows(in, out.channels) << " band(s), "
      << (op.wide_input_transform(in) ? 8 : 4) << " channels per input-transform invocation";
  // The border of a padded output must stay zero: the next 3x3 layer reads it as padding.
  if (c.out_pad) {
    const auto interior = test::add_border(got, c.out_c, oh, ow, c.out_pad);
    EXPECT_EQ(test::max_abs_diff(padded, interior), 0.0f) << "output border was written";
  }
}

// Sizes that are not multiples of the tile (the input transform must read zeros past the bordered tensor, not the
// next row's values; F(6x6, 3x3)'s windows start mid-texel in odd tile columns), output channels not a multiple of
// 4, more tiles than one workgroup, SuperPoint's channel counts.
TEST(WinogradConv3x3, MatchesTheDirectConvolution) {
  if (!winograd_available()) GTEST_SKIP() << gpu().caps().name << " lacks the texel formats";
  for (const Tile tile : kTiles) {
    check_winograd({4, 8, 5, 6, 0, false, false}, 61, tile);
    check_winograd({16, 6, 9, 7, 1, true, false}, 62, tile);
    check_winograd({64, 64, 13, 29, 1, true, false}, 63, tile);
    check_winograd({8, 4, 41, 37, 1, false, false}, 64, tile);    // 110 (F43) or 49 (F63) tiles
    check_winograd({8, 4, 61, 67, 1, false, false}, 66, tile);    // 204 or 132 tiles: 3 workgroups
    check_winograd({128, 256, 6, 10, 0, true, false}, 65, tile);  // convPa / convDa's shape
  }
}

// Bands of tile rows (scratch capped below one convolution's needs): one row per band, and bands of 3 rows with a
// shorter last band, with and without the pool.
TEST(WinogradConv3x3, BandsOfTileRowsMatchTheDirectConvolution) {
  if (!winograd_available()) GTEST_SKIP() << gpu().caps().name << " lacks the texel formats";
  for (const Tile tile : kTiles) {
    check_winograd({8, 8, 21, 13, 1, true, false, 1}, 81, tile);
    check_winograd({8, 8, 40, 16, 1, false, true, 3}, 82, tile);
    check_winograd({8, 4, 45, 14, 0, true, false, 3}, 83, tile);
  }
}

// Pooled: odd sizes (the last row and column are dropped), a height whose last tile is half outside.
TEST(WinogradConv3x3, MaxPoolMatchesConvolutionThenPool) {
  if (!winograd_available()) GTEST_SKIP() << gpu().caps().name << " lacks the texel formats";
  for (const Tile tile : kTiles) {
    check_winograd({64, 64, 14, 18, 1, true, true}, 71, tile);
    check_winograd({8, 12, 11, 13, 1, false, true}, 72, tile);
    check_winograd({4, 4, 6, 22, 0, true, true}, 73, tile);
    check_winograd({4, 4, 9, 27, 1, true, true}, 74, tile);
  }
}

// The stem (SuperPoint's conv1a) computed in the input transform: image sizes with partial tiles, the pool, bands,
// and NaN in the image's row padding.
TEST(WinogradConv3x3, StemInTheInputTransformMatchesTwoConvolutions) {
  if (!winograd_available()) GTEST_SKIP() << gpu().caps().name << " lacks the texel formats";
  for (const Tile tile : kTiles) {
    check_winograd({64, 64, 13, 29, 1, true, false, 0, true}, 91, tile);
    check_winograd({8, 12, 22, 18, 1, true, true, 0, true}, 92, tile);
    check_winograd({8, 8, 30, 17, 1, true, true, 2, true}, 93, tile);  // 2 tile rows a band
  }
}

// The input transform takes 8 channels per invocation (one 32-byte store per point) where the device has
// shaderInt64 and the channels are a multiple of 8, else 4: the cases above run the 8-channel form at 8, 16, 64 and
// 128 channels on such a device; here the 4-channel form, on a device without shaderInt64 and at 12 channels.
TEST(WinogradConv3x3, InputTransformTakesEightChannelsWhereTheDeviceHasInt64) {
  if (!winograd_available()) GTEST_SKIP() << gpu().caps().name << " lacks the texel formats";
  const WinogradConv3x3 op(gpu(), Precision::fp32, Tile::f63);
  EXPECT_EQ(op.wide_input_transform({64, 8, 8, 1}), gpu().caps().int64);
  EXPECT_FALSE(op.wide_input_transform({12, 8, 8, 1}));
  EXPECT_FALSE(op.wide_input_transform({4, 8, 8, 1}));
  const Context without_int64({.pipeline_cache = false, .use_int64 = false});
  EXPECT_FALSE(without_int64.caps().int64);
  EXPECT_FALSE(WinogradConv3x3(without_int64, Precision::fp32, Tile::f63).wide_input_transform({64, 8, 8, 1}));
  for (const Tile tile : kTiles) {
    check_winograd({64, 64, 13, 29, 1, true, false}, 101, tile, without_int64);
    check_winograd({64, 16, 14, 18, 1, true, true, 0, true}, 102, tile, without_int64);  // stem + pool
    check_winograd({12, 8, 15, 19, 1, true, false}, 103, tile);
    check_winograd({12, 8, 15, 19, 1, true, true, 0, true}, 104, tile);
  }
}

// U = G g G^T: a filter with only its centre tap gives the outer product of G's middle column with itself, placed at
// [point][output channel][input channel]; padded output channels are zero.
void check_filter_transform(Tile tile, const std::vector<double>& g_middle) {
  const std::uint32_t out_c = 3, in_c = 2, n = std::uint32_t(g_middle.size());
  std::vector<float> oihw(out_c * in_c * 9, 0.0f);
  oihw[(2 * in_c + 1) * 9 + 4] = 6.0f;  // output channel 2, input channel 1, centre tap
  const auto u = WinogradConv3x3::transform_weights(pack_conv_o4(oihw, out_c, in_c, 3, 3), out_c, in_c, tile);
  ASSERT_EQ(u.size(), std::size_t(n) * n * 4 * in_c);
  ASSERT_EQ(n * n, WinogradConv3x3::points(tile));
  for (std::uint32_t a = 0; a < n; ++a)
    for (std::uint32_t b = 0; b < n; ++b)
      for (std::uint32_t o = 0; o < 4; ++o)
        for (std::uint32_t i = 0; i < in_c; ++i) {
          const double expected = o == 2 && i == 1 ? 6.0 * g_middle[a] * g_middle[b] : 0.0;
          EXPECT_NEAR(u[((a * n + b) * 4 + o) * in_c + i], expected, 1e-7) << a << "," << b << " o" << o << " i" << i;
        }
}

TEST(WinogradConv3x3, FilterTransformIsTheClosedForm) {
  check_filter_transform(Tile::f43, {0, -1.0 / 6, 1.0 / 6, 1.0 / 12, -1.0 / 12, 0});
  check_filter_transform(Tile::f63, {0, -2.0 / 9, 2.0 / 9, 1.0 / 45, -1.0 / 45, 16.0 / 45, -16.0 / 45, 0});
}

TEST(WinogradConv3x3, UnsupportedShapesAreAClearError) {
  if (!winograd_available()) GTEST_SKIP() << gpu().caps().name << " lacks the texel formats";
  const WinogradConv3x3 op(gpu(), Precision::fp32, Tile::f63);
  const ActivationShape three_channels{3, 8, 8, 1}, unbordered{4, 8, 8, 0};
  EXPECT_FALSE(op.supports(three_channels, 8));
  EXPECT_FALSE(op.supports(unbordered, 8));
  EXPECT_TRUE(op.supports({4, 8, 8, 1}, 8));
  Buffer input(gpu(), activation_bytes(three_channels, Precision::fp32)), weights(gpu(), 4096), bias(gpu(), 64);
  Buffer scratch(gpu(), 1 << 16), output(gpu(), activation_bytes({8, 8, 8, 1}, Precision::fp32));
  Sequence seq(gpu());
  seq.begin();
  try {
    op.record(seq, input, three_channels, Binding(weights), Binding(bias), scratch, scratch, output, {8, 8, 8, 1},
              false, false, "conv9");
    FAIL() << "3 input channels were accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("conv9"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("multiple of 4 input channels"), std::string::npos) << e.what();
  }
  EXPECT_THROW(WinogradConv3x3(gpu(), Precision::fp16s, Tile::f43), std::invalid_argument);
}

}  // namespace
}  // namespace vkvo::rt
