// The first kernels (conv3x3 + bias + ReLU, conv1x1, 2x2 max-pool, GEMM) against plain C++ references on random
// data, in every precision the device supports, at sizes that are not multiples of the workgroup tiles.
#include <array>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "common/gpu.hpp"
#include "common/test_support.hpp"
#include "conv_reference.hpp"
#include "kernel_test_util.hpp"
#include "runtime/context.hpp"
#include "runtime/ops.hpp"
#include "runtime/tensor_layout.hpp"

namespace vkvo::rt {
namespace {

using test::add_border;
using test::as_stored;
using test::gpu;
using test::random_values;
using test::reference_conv;
using test::reference_max_pool;
using test::strip_border;

class Kernels : public ::testing::TestWithParam<Precision> {
 protected:
  void SetUp() override {
    if (!gpu().caps().supports(GetParam()))
      GTEST_SKIP() << gpu().caps().name << " does not support " << to_string(GetParam());
  }
  Precision precision() const { return GetParam(); }
};

struct ConvCase {
  int in_c, out_c, h, w, k, in_pad, out_pad;
  bool relu;
};

void check_conv(Precision precision, const ConvCase& c, std::uint32_t seed,
                Conv3x3Kernel kernel = Conv3x3Kernel::direct) {
  auto& ctx = gpu();
  const auto input = as_stored(random_values(std::size_t(c.in_c) * c.h * c.w, seed), precision);
  const Precision weight_precision = conv_weight_precision(precision);
  // The tensor-core kernel multiplies the weights rounded to fp16: the reference takes them so rounded, which they
  // are exactly as stored then, and the tolerance of the activations' precision applies.
  const auto weights =
      as_stored(as_stored(random_values(std::size_t(c.out_c) * c.in_c * c.k * c.k, seed + 1, -0.5f, 0.5f),
                          kernel == Conv3x3Kernel::cooperative_matrix ? Precision::fp16 : weight_precision),
                weight_precision);
  const auto bias = random_values(c.out_c, seed + 2);
  const auto expected = reference_conv(input, weights, bias, c.in_c, c.out_c, c.h, c.w, c.k, c.relu);

  const ActivationShape in{std::uint32_t(c.in_c), std::uint32_t(c.h), std::uint32_t(c.w), std::uint32_t(c.in_pad)};
  const ActivationShape out{std::uint32_t(c.out_c), std::uint32_t(c.h), std::uint32_t(c.w), std::uint32_t(c.out_pad)};
  auto in_buf = test::upload_tensor(ctx, add_border(input, c.in_c, c.h, c.w, c.in_pad), precision);
  auto w_buf = test::upload_tensor(ctx, pack_conv_o4(weights, c.out_c, c.in_c, c.k, c.k), weight_precision);
  Buffer b_buf(ctx, round_up(c.out_c, 4) * sizeof(float));
  b_buf.upload(std::span<const float>(pad_bias_o4(bias)));
  Buffer out_buf(ctx, activation_bytes(out, precision));
  out_buf.fill_zero();

  const Conv2d conv(ctx, precision, std::uint32_t(c.k), kernel);
  Sequence seq(ctx);
  seq.begin();
  conv.record(seq, in_buf, in, w_buf, b_buf, out_buf, out, c.relu);
  seq.end();
  seq.submit();
  const auto padded = test::download_tensor(out_buf, out.elements(), precision);
  const auto got = strip_border(padded, c.out_c, c.h, c.w, c.out_pad);
  const float tol = test::tolerance(precision, expected);
  EXPECT_LE(test::max_abs_diff(got, expected), tol)
      << "conv" << c.k << "x" << c.k << " " << c.in_c << "->" << c.out_c << " at " << c.w << "x" << c.h;
  // The border of a padded output must stay zero: the next 3x3 layer reads it as padding.
  if (c.out_pad) {
    const auto interior = add_border(got, c.out_c, c.h, c.w, c.out_pad);
    EXPECT_EQ(test::max_abs_diff(padded, interior), 0.0f) << "output border was written";
  }
}

TEST_P(Kernels, Conv3x3BiasReluMatchesReference) {
  check_conv(precision(), {3, 8, 13, 29, 3, 1, 1, true}, 11);   // odd sizes, partial x blocks and y groups
  check_conv(precision(), {16, 6, 9, 7, 3, 1, 0, false}, 12);   // out channels not a multiple of 4, no ReLU
  check_conv(precision(), {1, 64, 24, 32, 3, 1, 1, true}, 13);  // SuperPoint's first layer shape
}

// The tiled kernel (8 output channels x 4 pixels x 3 rows per invocation): widths that leave partial
// 4-pixel blocks and workgroups, channel counts that leave a partial 8-channel group and a partial 4-block.
TEST_P(Kernels, Conv3x3TiledKernelMatchesReference) {
  if (!tiled_kernels_available(gpu(), precision())) GTEST_SKIP() << gpu().caps().name << " lacks the texel formats";
  check_conv(precision(), {3, 8, 13, 29, 3, 1, 1, true}, 41, Conv3x3Kernel::tiled);
  check_conv(precision(), {16, 6, 9, 7, 3, 1, 0, false}, 42, Conv3x3Kernel::tiled);
  check_conv(precision(), {5, 13, 6, 70, 3, 1, 1, true}, 43, Conv3x3Kernel::tiled);
  check_conv(precision(), {64, 65, 11, 19, 3, 1, 1, false}, 44, Conv3x3Kernel::tiled);
  check_conv(precision(), {1, 64, 24, 32, 3, 1, 1, true}, 45, Conv3x3Kernel::tiled);
}

// The tensor-core implicit GEMM (64 output channels x 64 pixels per workgroup, K = 9 x input channels in steps of
// 32): partial channel and pixel blocks, K of one partial step (SuperPoint's first layer), several steps with a
// partial last one, and SuperPoint's widest layer. Runs where the device has the kernels' shape (an NVIDIA GPU).
TEST_P(Kernels, Conv3x3CooperativeMatrixMatchesReference) {
  if (!use_cooperative_matrix(gpu(), precision()))
    GTEST_SKIP() << gpu().caps().name << " runs no tensor-core kernels at " << to_string(precision());
  constexpr auto coopmat = Conv3x3Kernel::cooperative_matrix;
  ASSERT_TRUE(Conv2d(gpu(), precision(), 3).uses_cooperative_matrix());
  check_conv(precision(), {3, 8, 13, 29, 3, 1, 1, true}, 71, coopmat);
  check_conv(precision(), {16, 6, 9, 7, 3, 1, 0, false}, 72, coopmat);
  check_conv(precision(), {1, 64, 24, 32, 3, 1, 1, true}, 73, coopmat);
  check_conv(precision(), {64, 65, 11, 19, 3, 1, 1, false}, 74, coopmat);
  check_conv(precision(), {128, 256, 15, 20, 3, 1, 0, true}, 75, coopmat);
}

// Where the device has no tensor cores (lavapipe, AMD, Intel) the automatic choice keeps the SIMT kernels, and
// asking for the tensor-core kernel is an error naming the shape it needs.
TEST(Conv2d, CooperativeMatrixOnlyWhereTheProfileHasIt) {
  for (const Precision p : kAllPrecisions) {
    if (!gpu().caps().supports(p)) continue;
    EXPECT_EQ(Conv2d(gpu(), p, 3).uses_cooperative_matrix(), use_cooperative_matrix(gpu(), p)) << to_string(p);
    EXPECT_EQ(Gemm(gpu(), p).uses_cooperative_matrix(), use_cooperative_matrix(gpu(), p)) << to_string(p);
  }
  EXPECT_FALSE(use_cooperative_matrix(gpu(), Precision::fp32));
  if (gpu().profile().cooperative_matrix) GTEST_SKIP() << gpu().caps().name << " has the tensor-core kernels";
  const std::string conv_error =
      test::error_of([] { Conv2d(gpu(), Precision::fp16s, 3, Conv3x3Kernel::cooperative_matrix); });
  EXPECT_NE(conv_error.find("needs cooperative matrices of shape 16x16x16 f16*f16+f32->f32 subgroup"),
            std::string::npos)
      << conv_error;
  EXPECT_THROW(Gemm(gpu(), Precision::fp16s, GemmKernel::cooperative_matrix), std::exception);
}

// The fused conv + max-pool against the reference conv followed by the reference pool. The fused kernel pools
// fp32 accumulators before rounding to the storage type; rounding is monotonic, so the stored maximum is the
// maximum of the rounded outputs and the conv's own tolerance applies.
void check_conv_max_pool(Precision precision, const ConvCase& c, std::uint32_t seed) {
  auto& ctx = gpu();
  const auto input = as_stored(random_values(std::size_t(c.in_c) * c.h * c.w, seed), precision);
  const Precision weight_precision = conv_weight_precision(precision);
  const auto weights =
      as_stored(random_values(std::size_t(c.out_c) * c.in_c * 9, seed + 1, -0.5f, 0.5f), weight_precision);
  const auto bias = random_values(c.out_c, seed + 2);
  const auto conv = reference_conv(input, weights, bias, c.in_c, c.out_c, c.h, c.w, 3, c.relu);
  const auto expected = reference_max_pool(conv, c.out_c, c.h, c.w);

  const int oh = c.h / 2, ow = c.w / 2;
  const ActivationShape in{std::uint32_t(c.in_c), std::uint32_t(c.h), std::uint32_t(c.w), 1};
  const ActivationShape out{std::uint32_t(c.out_c), std::uint32_t(oh), std::uint32_t(ow), std::uint32_t(c.out_pad)};
  auto in_buf = test::upload_tensor(ctx, add_border(input, c.in_c, c.h, c.w, 1), precision);
  auto w_buf = test::upload_tensor(ctx, pack_conv_o4(weights, c.out_c, c.in_c, 3, 3), weight_precision);
  Buffer b_buf(ctx, round_up(c.out_c, 4) * sizeof(float));
  b_buf.upload(std::span<const float>(pad_bias_o4(bias)));
  Buffer out_buf(ctx, activation_bytes(out, precision));
  out_buf.fill_zero();

  const Conv3x3MaxPool op(ctx, precision);
  Sequence seq(ctx);
  seq.begin();
  op.record(seq, in_buf, in, w_buf, b_buf, out_buf, out, c.relu);
  seq.end();
  seq.submit();
  const auto padded = test::download_tensor(out_buf, out.elements(), precision);
  const auto got = strip_border(padded, c.out_c, oh, ow, c.out_pad);
  EXPECT_LE(test::max_abs_diff(got, expected), test::tolerance(precision, conv))
      << "conv3x3+maxpool " << c.in_c << "->" << c.out_c << " at " << c.w << "x" << c.h;
  if (c.out_pad) {
    const auto interior = add_border(got, c.out_c, oh, ow, c.out_pad);
    EXPECT_EQ(test::max_abs_diff(padded, interior), 0.0f) << "output border was written";
  }
}

// Odd sizes (the last row and column are dropped), a height that leaves a partial 4-row tile, partial
// 8-channel groups and 4-blocks, unbordered and bordered pooled outputs.
TEST_P(Kernels, Conv3x3MaxPoolMatchesConvThenPool) {
  if (!tiled_kernels_available(gpu(), precision())) GTEST_SKIP() << gpu().caps().name << " lacks the texel formats";
  check_conv_max_pool(precision(), {3, 8, 13, 29, 3, 1, 1, true}, 51);
  check_conv_max_pool(precision(), {16, 6, 10, 7, 3, 1, 0, false}, 52);
  check_conv_max_pool(precision(), {64, 65, 11, 19, 3, 1, 1, true}, 53);
  check_conv_max_pool(precision(), {5, 13, 6, 70, 3, 1, 1, false}, 54);
}

TEST(Conv3x3MaxPool, WrongPooledShapeIsAClearError) {
  if (!tiled_kernels_available(gpu(), Precision::fp32)) GTEST_SKIP() << gpu().caps().name << " lacks the texel formats";
  const Conv3x3MaxPool op(gpu(), Precision::fp32);
  const ActivationShape in{4, 9, 12, 1}, wrong{4, 5, 6, 1};
  Buffer input(gpu(), activation_bytes(in, Precision::fp32)), weights(gpu(), 4096), bias(gpu(), 64);
  Buffer output(gpu(), activation_bytes(wrong, Precision::fp32));
  Sequence seq(gpu());
  seq.begin();
  try {
    op.record(seq, input, in, Binding(weights), Binding(bias), output, wrong, false);
    FAIL() << "a 6x5 output for a 12x9 input was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("pools to 6x4"), std::string::npos) << e.what();
  }
}

TEST(Conv2d, AutomaticChoiceUsesTheTiledKernelWhereTheDeviceReadsItsTexelFormats) {
  const Conv2d conv(gpu(), Precision::fp32, 3);
  EXPECT_EQ(conv.uses_tiled_kernel(), tiled_kernels_available(gpu(), Precision::fp32));
  EXPECT_FALSE(Conv2d(gpu(), Precision::fp32, 3, Conv3x3Kernel::direct).uses_tiled_kernel());
  EXPECT_FALSE(Conv2d(gpu(), Precision::fp32, 1).uses_tiled_kernel());
}

TEST(Conv2d, MisalignedTexelBindingIsAClearError) {
  if (!tiled_kernels_available(gpu(), Precision::fp32)) GTEST_SKIP() << gpu().caps().name << " lacks the texel formats";
  ASSERT_GT(gpu().caps().min_texel_buffer_offset_alignment, 1u);
  const Conv2d conv(gpu(), Precision::fp32, 3, Conv3x3Kernel::tiled);
  const ActivationShape shape{4, 5, 6, 1};
  Buffer input(gpu(), activation_bytes(shape, Precision::fp32)), weights(gpu(), 4096), bias(gpu(), 64);
  Buffer output(gpu(), activation_bytes(shape, Precision::fp32));
  Sequence seq(gpu());
  seq.begin();
  try {
    conv.record(seq, input, shape, Binding(weights, 4), Binding(bias), output, shape, false);
    FAIL() << "a texel view at byte 4 was accepted";
  } catch (const VulkanError& e) {
    EXPECT_NE(std::string(e.what()).find("texel-buffer offset alignment"), std::string::npos) << e.what();
  }
}

// 37 input channels run conv1x1.comp; the others conv1x1_tiled.comp where the device has it (checked below).
TEST_P(Kernels, Conv1x1MatchesReference) {
  constexpr auto automatic = Conv3x3Kernel::automatic;  // `direct` would keep every 1x1 on conv1x1.comp
  check_conv(precision(), {37, 65, 5, 11, 1, 0, 0, false}, 21, automatic);   // like the 65-channel detector head
  check_conv(precision(), {8, 12, 7, 9, 1, 1, 1, true}, 22, automatic);      // padded input and output
  check_conv(precision(), {256, 65, 7, 13, 1, 0, 0, false}, 23, automatic);  // partial 8-channel group and 8-pixel tile
  check_conv(precision(), {4, 40, 5, 19, 1, 0, 0, true}, 24, automatic);     // one step of 4 input channels
  check_conv(precision(), {12, 9, 3, 17, 1, 1, 0, true}, 25, automatic);     // padded input only
  check_conv(precision(), {8, 12, 7, 9, 1, 1, 1, true}, 26);                 // conv1x1.comp where it would not run
}

TEST(TensorLayout, UnpackConvO4InvertsPackConvO4) {
  for (const auto [o, i, k] : {std::array{5, 3, 3}, std::array{8, 4, 1}, std::array{65, 7, 1}}) {
    const auto oihw = random_values(std::size_t(o) * i * k * k, 61);
    EXPECT_EQ(unpack_conv_o4(pack_conv_o4(oihw, o, i, k, k), o, i, k, k), oihw) << o << "x" << i << "x" << k;
  }
  EXPECT_THROW(unpack_conv_o4(std::vector<float>(10), 5, 2, 1, 1), std::invalid_argument);
}

// A 1x1 convolution as a GEMM over its planes (conv1x1_gemm_shape), with whichever GEMM kernel the shape takes
// (the tiled one where planes and channels fill whole texels, as SuperPoint's convDb does), against the same
// reference as the convolution kernels.
TEST_P(Kernels, Conv1x1AsGemmMatchesReference) {
  auto& ctx = gpu();
  for (const auto [in_c, out_c, h, w] : {std::array{64, 36, 6, 8}, std::array{16, 9, 5, 7}}) {
    const bool relu = in_c == 64;
    const auto input = as_stored(random_values(std::size_t(in_c) * h * w, 62), precision());
    const auto weights = as_stored(random_values(std::size_t(out_c) * in_c, 63, -0.5f, 0.5f), precision());
    const auto bias = random_values(out_c, 64);
    const auto expected = reference_conv(input, weights, bias, in_c, out_c, h, w, 1, relu);
    const ActivationShape in{std::uint32_t(in_c), std::uint32_t(h), std::uint32_t(w), 0};
    auto in_buf = test::upload_tensor(ctx, input, precision());
    auto w_buf = test::upload_tensor(ctx, unpack_conv_o4(pack_conv_o4(weights, out_c, in_c, 1, 1), out_c, in_c, 1, 1),
                                     precision());
    Buffer b_buf(ctx, bias.size() * sizeof(float));
    b_buf.upload(std::span<const float>(bias));
    Buffer out_buf(ctx, expected.size() * storage_bytes(precision()));
    const Gemm gemm(ctx, precision());
    const GemmShape shape = conv1x1_gemm_shape(in, std::uint32_t(out_c), relu);
    const bool tiled = gemm.uses_tiled_kernel(shape, Binding(w_buf), Binding(in_buf));
    if (in_c == 64) {
      EXPECT_EQ(tiled, tiled_kernels_available(ctx, precision())) << "48-pixel planes fill whole texels";
    }
    Sequence seq(ctx);
    seq.begin();
    gemm.record(seq, w_buf, in_buf, &b_buf, out_buf, shape);
    seq.end();
    seq.submit();
    const auto got = test::download_tensor(out_buf, expected.size(), precision());
    EXPECT_LE(test::max_abs_diff(got, expected), test::tolerance(precision(), expected))
        << in_c << "->" << out_c << " at " << w << "x" << h << (tiled ? ", tiled GEMM" : ", direct GEMM");
  }
  EXPECT_THROW(conv1x1_gemm_shape(ActivationShape{8, 4, 4, 1}, 8, false), std::invalid_argument);
}

TEST(Conv2d, Conv1x1UsesTheTiledKernelForMultiplesOfFourInputChannels) {
  const Conv2d conv(gpu(), Precision::fp32, 1);
  const bool available = tiled_kernels_available(gpu(), Precision::fp32);
  EXPECT_EQ(conv.uses_tiled_kernel(ActivationShape{256, 60, 94, 0}), available);
  EXPECT_FALSE(conv.uses_tiled_kernel(ActivationShape{37, 5, 11, 0}));
  EXPECT_FALSE(Conv2d(gpu(), Precision::fp32, 1, Conv3x3Kernel::direct).uses_tiled_kernel(ActivationShape{8, 7, 9, 1}));
}

TEST_P(Kernels, MaxPool2x2MatchesReference) {
  auto& ctx = gpu();
  const int c = 5, h = 13, w = 18;  // odd height: last row dropped (floor)
  const auto input = as_stored(random_values(std::size_t(c) * h * w, 31), precision());
  const int oh = h / 2, ow = w / 2;
  const auto expected = reference_max_pool(input, c, h, w);
  auto in_buf = test::upload_tensor(ctx, add_border(input, c, h, w, 1), precision());
  const ActivationShape out{std::uint32_t(c), std::uint32_t(oh), std::uint32_t(ow), 1};
  Buffer out_buf(ctx, activation_bytes(out, precision()));
  out_buf.fill_zero();
  const MaxPool2x2 pool(ctx, precision());
  Sequence seq(ctx);
  seq.begin();
  pool.record(seq, in_buf, {std::uint32_t(c), std::uint32_t(h), std::uint32_t(w), 1}, out_buf, 1);
  seq.end();
  seq.submit();
  const auto got = strip_border(test::download_tensor(out_buf, out.elements(), precision()), c, oh, ow, 1);
  EXPECT_EQ(test::max_abs_diff(got, expected), 0.0f) << "max-pool selects stored values exactly";
}

void check_gemm(Precision precision, GemmShape s, bool with_bias, std::uint32_t seed,
                GemmKernel kernel = GemmKernel::direct) {
  auto& ctx = gpu();
  const auto a = as_stored(random_values(std::size_t(s.m) * s.k, seed), precision);
  const auto b = as_stored(random_values(std::size_t(s.k) * s.n, seed + 1), precision);
  const auto bias = random_values(s.bias_per_row ? s.m : s.n, seed + 2);
  // C's prior contents: what an accumulating call adds to (a residual connection), else overwritten.
  const auto c_before = as_stored(random_values(std::size_t(s.m) * s.n, seed + 3), precision);
  std::vector<float> expected(std::size_t(s.m) * s.n);
  for (std::uint32_t i = 0; i < s.m; ++i)
    for (std::uint32_t j = 0; j < s.n; ++j) {
      double acc = 0;
      for (std::uint32_t k = 0; k < s.k; ++k)
        acc += double(a[i * s.k + k]) * (s.b_transposed ? b[j * s.k + k] : b[k * s.n + j]);
      float v = s.alpha * float(acc) + (with_bias ? bias[s.bias_per_row ? i : j] : 0.0f);
      if (s.accumulate) v += c_before[i * s.n + j];
      expected[i * s.n + j] = s.relu ? std::max(v, 0.0f) : v;
    }
  auto a_buf = test::upload_tensor(ctx, a, precision);
  auto b_buf = test::upload_tensor(ctx, b, precision);
  Buffer bias_buf(ctx, bias.size() * sizeof(float));
  bias_buf.upload(std::span<const float>(bias));
  Buffer c_buf = test::upload_tensor(ctx, c_before, precision);
  const Gemm gemm(ctx, precision, kernel);
  if (kernel == GemmKernel::tiled || kernel == GemmKernel::tiled_wide) {
    ASSERT_TRUE(gemm.uses_tiled_kernel(s, Binding(a_buf), Binding(b_buf))) << "shape should be vec4-aligned";
  }
  Sequence seq(ctx);
  seq.begin();
  gemm.record(seq, a_buf, b_buf, with_bias ? &bias_buf : nullptr, c_buf, s);
  seq.end();
  seq.submit();
  const auto got = test::download_tensor(c_buf, expected.size(), precision);
  EXPECT_LE(test::max_abs_diff(got, expected), test::tolerance(precision, expected))
      << "gemm " << s.m << "x" << s.n << "x" << s.k << (s.b_transposed ? " B^T" : "") << ", tile "
      << gemm.tiled_tile().rows << "x" << gemm.tiled_tile().cols;
}

TEST_P(Kernels, GemmMatchesReference) {
  check_gemm(precision(), {.m = 37, .n = 70, .k = 129, .b_transposed = false}, true, 41);
  check_gemm(precision(), {.m = 65, .n = 23, .k = 64, .b_transposed = true, .relu = true, .alpha = 0.125f}, true, 42);
  check_gemm(precision(), {.m = 1, .n = 1, .k = 3, .b_transposed = true}, false, 43);
  check_gemm(precision(), {.m = 11, .n = 24, .k = 8, .b_transposed = false, .bias_per_row = true}, true, 44);
  check_gemm(precision(), {.m = 21, .n = 30, .k = 17, .b_transposed = true, .relu = true, .accumulate = true}, true,
             45);
}

// The tiled kernel with either tile (4 x 8 or 8 x 16 blocks of C, operands through texel buffers of 4 fp32 or
// 8 fp16 elements): sizes that leave partial row groups, whole subgroups past the last row (M = 300: 38 of 64
// lanes at 8 rows) and partial column blocks, down to a block wider than N (its texels past N clamped); both
// forms of B; N not a multiple of 4 (scalar stores) and a multiple (vec4); K of a single texel.
TEST_P(Kernels, GemmTiledKernelMatchesReference) {
  if (!tiled_kernels_available(gpu(), precision())) GTEST_SKIP() << gpu().caps().name << " lacks the texel formats";
  const std::uint32_t per_texel = precision() == Precision::fp32 ? 4 : 8;
  for (const GemmKernel tiled : {GemmKernel::tiled, GemmKernel::tiled_wide}) {
    check_gemm(precision(), {.m = 37, .n = 64 + per_texel, .k = 128, .b_transposed = false}, true, 51, tiled);
    check_gemm(precision(), {.m = 65, .n = 23, .k = 64, .b_transposed = true, .relu = true, .alpha = 0.125f}, true, 52,
               tiled);
    check_gemm(precision(), {.m = 300, .n = 40, .k = 256, .b_transposed = true}, false, 53, tiled);
    check_gemm(precision(), {.m = 5, .n = 8 + per_texel, .k = per_texel, .b_transposed = false, .relu = true}, false,
               54, tiled);
    check_gemm(precision(), {.m = 9, .n = 13, .k = per_texel, .b_transposed = true}, false, 55, tiled);
    check_gemm(precision(), {.m = 3, .n = per_texel, .k = 2 * per_texel, .b_transposed = false}, true, 56, tiled);
    // One bias per row (a 1x1 convolution's per output channel), with a partial row group.
    check_gemm(precision(), {.m = 19, .n = 3 * per_texel, .k = 16, .b_transposed = false, .bias_per_row = true}, true,
               57, tiled);
    // Accumulating into C (SuperGlue's residual), ReLU on the sum: vec4 stores (N = 64) and element stores (N = 23),
    // with and without a bias; every epilogue is its own specialised pipeline.
    check_gemm(precision(), {.m = 37, .n = 64, .k = 32, .b_transposed = true, .relu = true, .accumulate = true}, true,
               58, tiled);
    check_gemm(precision(), {.m = 37, .n = 23, .k = 32, .b_transposed = true, .accumulate = true}, false, 59, tiled);
    check_gemm(precision(),
               {.m = 19, .n = 2 * per_texel, .k = 16, .b_transposed = false, .accumulate = true, .bias_per_row = true},
               true, 60, tiled);
  }
}

// The tensor-core GEMM (64 x 64 blocks of C, K in steps of 32, any alignment): partial blocks, K of a partial step,
// both forms of B, every epilogue, SuperGlue's projection (256 x 1000 x 256) and SuperPoint's convDb as a GEMM over
// the planes.
TEST_P(Kernels, GemmCooperativeMatrixMatchesReference) {
  if (!use_cooperative_matrix(gpu(), precision()))
    GTEST_SKIP() << gpu().caps().name << " runs no tensor-core kernels at " << to_string(precision());
  constexpr auto coopmat = GemmKernel::cooperative_matrix;
  check_gemm(precision(), {.m = 37, .n = 70, .k = 129, .b_transposed = false}, true, 81, coopmat);
  check_gemm(precision(), {.m = 65, .n = 23, .k = 64, .b_transposed = true, .relu = true, .alpha = 0.125f}, true, 82,
             coopmat);
  check_gemm(precision(), {.m = 1, .n = 1, .k = 3, .b_transposed = true}, false, 83, coopmat);
  check_gemm(precision(), {.m = 11, .n = 24, .k = 8, .b_transposed = false, .bias_per_row = true}, true, 84, coopmat);
  check_gemm(precision(), {.m = 21, .n = 30, .k = 17, .b_transposed = true, .relu = true, .accumulate = true}, true, 85,
             coopmat);
  check_gemm(precision(), {.m = 256, .n = 1000, .k = 256, .b_transposed = true}, true, 86, coopmat);
  check_gemm(precision(), {.m = 256, .n = 60 * 94, .k = 256, .b_transposed = false, .bias_per_row = true}, true, 87,
             coopmat);
}

// The automatic tile is the device profile's (wide on CPU devices: gemm_tiled.comp says why).
TEST(Gemm, AutomaticTileFollowsTheDeviceProfile) {
  if (!tiled_kernels_available(gpu(), Precision::fp32)) GTEST_SKIP() << gpu().caps().name << " lacks the texel formats";
  EXPECT_EQ(Gemm(gpu(), Precision::fp32).tiled_tile().cols, gpu().profile().wide_gemm_tile ? 16u : 8u);
  EXPECT_EQ(Gemm(gpu(), Precision::fp32, GemmKernel::tiled).tiled_tile().rows, 4u);
  EXPECT_EQ(Gemm(gpu(), Precision::fp32, GemmKernel::tiled_wide).tiled_tile().rows, 8u);
}

TEST(Gemm, UnalignedShapesFallBackToTheDirectKernel) {
  const Gemm gemm(gpu(), Precision::fp32);
  Buffer a(gpu(), 4096), b(gpu(), 4096);
  EXPECT_FALSE(gemm.uses_tiled_kernel({.m = 8, .n = 8, .k = 3, .b_transposed = true}, Binding(a), Binding(b)));
  EXPECT_FALSE(gemm.uses_tiled_kernel({.m = 8, .n = 6, .k = 8}, Binding(a), Binding(b)));  // ldb = 6
  EXPECT_EQ(gemm.uses_tiled_kernel({.m = 8, .n = 8, .k = 8, .b_transposed = true}, Binding(a), Binding(b)),
            tiled_kernels_available(gpu(), Precision::fp32));
  // 16-bit operands are read 8 per texel: K, the leading dimensions and (B not transposed) N must fill them.
  if (!gpu().caps().supports(Precision::fp16s)) return;
  const Gemm half(gpu(), Precision::fp16s);
  EXPECT_FALSE(half.uses_tiled_kernel({.m = 8, .n = 8, .k = 4, .b_transposed = true}, Binding(a), Binding(b)));
  EXPECT_FALSE(half.uses_tiled_kernel({.m = 8, .n = 12, .k = 8}, Binding(a), Binding(b)));
  EXPECT_EQ(half.uses_tiled_kernel({.m = 8, .n = 16, .k = 8}, Binding(a), Binding(b)),
            tiled_kernels_available(gpu(), Precision::fp16s));
}

INSTANTIATE_TEST_SUITE_P(AllPrecisions, Kernels, ::testing::ValuesIn(kAllPrecisions),
                         [](const auto& info) { return std::string(to_string(info.param)); });

}  // namespace
}  // namespace vkvo::rt
