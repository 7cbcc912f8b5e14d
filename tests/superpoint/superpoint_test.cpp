// SuperPoint on the device with random weights (no shared data needed), against the plain C++ reference of
// superpoint_reference.hpp: the network's dense outputs, each post-processing step (NMS, threshold, border,
// top-k order, descriptor sampling) on the device's own dense maps, odd image sizes, parameters and errors.
#include <algorithm>
#include <cmath>
#include <random>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "common/gpu.hpp"
#include "common/test_support.hpp"
#include "features/superpoint.hpp"
#include "io/config.hpp"
#include "runtime/ops.hpp"
#include "superpoint_reference.hpp"

namespace vkvo::features {
namespace {

using test::gpu;

// A textured image: smooth blobs plus noise, so the score map has distinct local maxima.
cv::Mat random_image(int width, int height, std::uint32_t seed) {
  cv::Mat image(height, width, CV_8UC1);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> noise(0, 40);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      image.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(
          120 + 80 * std::sin(0.37 * x + 0.2 * std::cos(0.11 * y)) * std::cos(0.23 * y) + noise(rng));
  return image;
}

struct Tolerance {
  float score_abs, desc_cos;
};
Tolerance tolerance(rt::Precision p) {
  // fp16s keeps 16-bit activations only (fp32 weights); fp16 also multiplies in 16 bits with 16-bit weights, hence
  // its wider bounds (what each measured here: docs/accuracy.md).
  switch (p) {
    case rt::Precision::fp32: return {2e-5f, 0.99999f};
    case rt::Precision::fp16s: return {2e-3f, 0.9999f};
    case rt::Precision::fp16: return {3e-3f, 0.998f};
  }
  return {};
}

class SuperPointRandom : public ::testing::TestWithParam<rt::Precision> {
 protected:
  void SetUp() override {
    if (!gpu().caps().supports(GetParam())) GTEST_SKIP() << gpu().caps().name << " lacks " << rt::to_string(GetParam());
  }
  void check_dense_outputs(bool tiled_kernels, SuperPointParams::Winograd winograd, int width = 53, int height = 42,
                           rt::WinogradConv3x3::Tile tile = SuperPointParams{}.winograd_tile);
};

// Dense outputs of the whole network against the C++ reference, at a size that is not a multiple of 8, with the
// texel-buffer kernels (the default where the device reads them) with and (fp32) without Winograd convolutions
// (both tile sizes), and with the storage-buffer fallback. 30 cells: the tiled detector head's last invocation (4
// cells each) is partial; every layer leaves partial 4 x 4 and 6 x 6 Winograd tiles; convDb's planes do not fill
// whole texels, so it runs conv1x1_tiled. 40 cells fill them: convDb then runs as a GEMM on CPU devices (not in
// fp16s, whose weights are stored in fp32).
TEST_P(SuperPointRandom, DenseOutputsMatchReference) {
  using Winograd = SuperPointParams::Winograd;
  if (GetParam() == rt::Precision::fp32) {
    for (const auto tile : {rt::WinogradConv3x3::Tile::f43, rt::WinogradConv3x3::Tile::f63}) {
      SCOPED_TRACE(fmt::format("tiled kernels, Winograd F({0}x{0}, 3x3) convolutions", std::uint32_t(tile)));
      check_dense_outputs(true, Winograd::on, 53, 42, tile);
    }
  }
  for (const bool tiled : {true, false}) {
    SCOPED_TRACE(tiled ? "tiled kernels" : "storage-buffer kernels");
    check_dense_outputs(tiled, Winograd::off);
  }
  SCOPED_TRACE("tiled kernels, 8 x 5 cells");
  check_dense_outputs(true, Winograd::automatic, 67, 42);
}

void SuperPointRandom::check_dense_outputs(bool tiled_kernels, SuperPointParams::Winograd winograd, int width,
                                           int height, rt::WinogradConv3x3::Tile tile) {
  const auto pack = reference::random_superpoint_pack(7);
  SuperPointParams params;
  params.precision = GetParam();
  params.tiled_kernels = tiled_kernels;
  params.winograd = winograd;
  params.winograd_tile = tile;
  SuperPoint sp(gpu(), pack, params);
  sp.set_profiling(true);                                // the labels of the timed commands say which path ran
  const cv::Mat image = random_image(width, height, 3);  // 53 x 42 -> 6 x 5 cells, dense 48 x 40
  SuperPointDense dense;
  sp.detect(image, &dense);
  // The per-command labels say which path ran (where the device has timestamps to label).
  if (gpu().caps().timestamps) {
    const auto timings = sp.last_timings();
    const bool ran_winograd = std::any_of(timings.begin(), timings.end(), [](const rt::CommandTiming& t) {
      return t.label.find("winograd") != std::string::npos;
    });
    const bool tiled = tiled_kernels && rt::tiled_kernels_available(gpu(), GetParam());
    const bool winograd_expected = tiled && GetParam() == rt::Precision::fp32 &&
                                   (winograd == SuperPointParams::Winograd::on ||
                                    (winograd == SuperPointParams::Winograd::automatic && gpu().profile().winograd));
    EXPECT_EQ(ran_winograd, winograd_expected);
    if (winograd_expected) {
      const std::string tile_label = fmt::format("winograd f{}3", std::uint32_t(tile));
      EXPECT_TRUE(
          std::any_of(timings.begin(), timings.end(),
                      [&](const rt::CommandTiming& t) { return t.label.find(tile_label) != std::string::npos; }))
          << "no command labelled '" << tile_label << "'";
    }
    const bool ran_gemm = std::any_of(timings.begin(), timings.end(),
                                      [](const rt::CommandTiming& t) { return t.label == "convDb gemm"; });
    const std::size_t cells = std::size_t(width / 8) * (height / 8);
    // Not where the weights are stored wider than the activations (fp16s): the GEMM reads both in one format.
    // The tensor-core GEMM reads any layout.
    const bool same_storage = rt::conv_weight_precision(GetParam()) == GetParam();
    EXPECT_EQ(ran_gemm, (tiled && gpu().profile().conv1x1_as_gemm && same_storage && cells % 8 == 0) ||
                            (tiled_kernels && rt::use_cooperative_matrix(gpu(), GetParam())))
        << "convDb as a GEMM where the device profile says, planes of whole texels";
  }
  const reference::Dense ref = reference::forward(pack, image);
  ASSERT_EQ(dense.cells_h, height / 8);
  ASSERT_EQ(dense.cells_w, width / 8);
  ASSERT_EQ(dense.scores.size(), ref.scores.size());
  // The tensor-core kernels multiply 16-bit weights, as fp16 does (with fp32 sums): fp16's bounds.
  const bool tensor_cores = tiled_kernels && rt::use_cooperative_matrix(gpu(), GetParam());
  const Tolerance tol = tolerance(tensor_cores ? rt::Precision::fp16 : GetParam());
  float max_err = 0;
  for (std::size_t i = 0; i < ref.scores.size(); ++i)
    max_err = std::max(max_err, std::abs(ref.scores[i] - dense.scores[i]));
  EXPECT_LE(max_err, tol.score_abs);
  const std::size_t cells = std::size_t(dense.cells_h) * dense.cells_w;
  for (std::size_t cell = 0; cell < cells; ++cell) {
    double ab = 0, aa = 0, bb = 0;
    for (std::size_t c = 0; c < 256; ++c) {
      const double a = ref.descriptors[c * cells + cell], b = dense.descriptors[c * cells + cell];
      ab += a * b, aa += a * a, bb += b * b;
    }
    EXPECT_GE(ab / std::sqrt(aa * bb), tol.desc_cos) << "cell " << cell;
    EXPECT_NEAR(bb, 1.0, 1e-4) << "unit norm, cell " << cell;
  }
}

// Post-processing: the device's keypoints must equal the C++ post-processing of the device's own dense maps
// exactly (same pixels, same order, same scores), descriptors to 1e-5, for several parameter sets, with the NMS
// read through texel views and through storage buffers. The NMS kernels take 4 pixels per invocation and read
// ceil(r/4) vec4s either side: radii 1, 2, 4 (one), 5 and 9 (two and three), near and away from the map's edges.
TEST_P(SuperPointRandom, PostProcessingMatchesReference) {
  const auto pack = reference::random_superpoint_pack(11);
  struct Setting {
    float threshold;
    int radius, border, max_keypoints;
    bool subpixel;
  };
  const Setting settings[] = {{0.005f, 4, 4, 400, false}, {0.02f, 2, 7, 25, false}, {0.0f, 1, 0, -1, false},
                              {0.002f, 5, 1, 200, false}, {0.0f, 9, 0, -1, false},  {0.005f, 4, 4, 400, true},
                              {0.0f, 1, 0, -1, true}};
  for (const bool tiled : {true, false}) {
    for (const Setting s : settings) {
      const SuperPointParams params{.keypoint_threshold = s.threshold,
                                    .nms_radius = s.radius,
                                    .remove_borders = s.border,
                                    .max_keypoints = s.max_keypoints,
                                    .subpixel = s.subpixel,
                                    .precision = GetParam(),
                                    .tiled_kernels = tiled};
      SuperPoint sp(gpu(), pack, params);
      const cv::Mat image = random_image(101, 67, 5);  // dense 96 x 64
      SuperPointDense dense;
      const PointFeatures got = sp.detect(image, &dense);
      const reference::Dense d{dense.cells_h, dense.cells_w, dense.scores, dense.descriptors};
      const reference::Keypoints want =
          reference::postprocess(d, s.threshold, s.radius, s.border, s.max_keypoints, s.subpixel);
      SCOPED_TRACE(::testing::Message() << (tiled ? "texel" : "storage-buffer") << " NMS, threshold " << s.threshold
                                        << " radius " << s.radius << " border " << s.border << " k " << s.max_keypoints
                                        << (s.subpixel ? " sub-pixel" : ""));
      ASSERT_GT(want.xy.size(), 5u) << "the test image must produce keypoints";
      ASSERT_EQ(got.size(), want.xy.size());
      EXPECT_EQ(got.descriptors.cols(), 256);
      int moved = 0;
      for (std::size_t i = 0; i < got.size(); ++i) {
        // Sub-pixel peaks: the device's float arithmetic against the reference's double, 1e-4 px.
        if (s.subpixel) {
          ASSERT_NEAR(got.keypoints[i].x(), want.xy[i].x(), 1e-4f) << "keypoint " << i;
          ASSERT_NEAR(got.keypoints[i].y(), want.xy[i].y(), 1e-4f) << "keypoint " << i;
          moved += got.keypoints[i] != got.keypoints[i].array().round().matrix();
        } else {
          ASSERT_EQ(got.keypoints[i], want.xy[i]) << "keypoint " << i;
        }
        ASSERT_EQ(got.scores[i], want.scores[i]) << "keypoint " << i;
        for (int c = 0; c < 256; ++c)
          ASSERT_NEAR(got.descriptors(i, c), want.descriptors[i][c], 1e-5f) << i << "," << c;
      }
      if (s.subpixel) {
        EXPECT_GT(moved, static_cast<int>(got.size()) / 2) << "most peaks lie between pixels";
      }
      if (s.max_keypoints < 0) {
        EXPECT_EQ(sp.last_candidate_count(), got.size()) << "no limit keeps every candidate";
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Precisions, SuperPointRandom, ::testing::ValuesIn(rt::kAllPrecisions),
                         [](const auto& info) { return std::string(rt::to_string(info.param)); });

// The NMS reference itself on a hand-made map worked out by hand: the maxima (2: 0.9, 9: 0.5) suppress their
// windows; pixel 5 (0.3) is no maximum of the original scores (0.8 lies in its window) but lies outside every
// suppressed window and is the maximum of the suppressed scores, so round one brings it back.
TEST(SuperPointReference, NmsRecoversSecondaryMaxima) {
  const int h = 1, w = 12, r = 2;
  const std::vector<float> s{0.1f, 0.2f, 0.9f, 0.8f, 0.7f, 0.3f, 0.2f, 0.1f, 0.05f, 0.5f, 0.1f, 0.0f};
  const auto nms = reference::simple_nms(s, h, w, r);
  const std::vector<float> want{0, 0, 0.9f, 0, 0, 0.3f, 0, 0, 0, 0.5f, 0, 0};
  EXPECT_EQ(nms, want);
}

// The reference's sub-pixel peak is exact on a sampled parabola (a sampled Gaussian for the score map, whose log it
// fits) and stays within half a pixel otherwise.
TEST(SuperPointReference, SubpixelPeakOfSampledParabolas) {
  for (const double peak : {-0.45, -0.2, 0.0, 0.13, 0.38}) {
    const auto f = [&](double x) { return 0.9 - 0.1 * (x - peak) * (x - peak); };
    EXPECT_NEAR(reference::parabola_peak(f(-1), f(0), f(1)), peak, 1e-12);
  }
  EXPECT_EQ(reference::parabola_peak(0.5, 0.4, 0.1), -0.5) << "a rising edge clamps to half a pixel";
  EXPECT_EQ(reference::parabola_peak(0.2, 0.2, 0.2), 0.0) << "no peak, no move";
  // 3 x 3 Gaussian score map peaking at (1.25, 0.9).
  const auto g = [](double x, double y) {
    return 0.3 * std::exp(-0.7 * (x - 1.25) * (x - 1.25) - 1.1 * (y - 0.9) * (y - 0.9));
  };
  std::vector<float> map(9);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) map[std::size_t(y) * 3 + x] = float(g(x, y));
  const Eigen::Vector2f p = reference::subpixel_peak(map, 3, 3, 1, 1);
  EXPECT_NEAR(p.x(), 1.25f, 1e-5f);
  EXPECT_NEAR(p.y(), 0.9f, 1e-5f);
}

TEST(SuperPointParamsTest, LoadsYamlSection) {
  const auto config = io::Config::from_string(
      "point_detector:\n  keypoint_threshold: 0.004\n  nms_radius: 3\n  remove_borders: 8\n  max_keypoints: 500\n"
      "  precision: fp32\n  winograd: off\n  winograd_tile: 4\n  subpixel: true\n");
  const SuperPointParams p = load_superpoint_params(config.section("point_detector"));
  EXPECT_FLOAT_EQ(p.keypoint_threshold, 0.004f);
  EXPECT_EQ(p.nms_radius, 3);
  EXPECT_EQ(p.remove_borders, 8);
  EXPECT_EQ(p.max_keypoints, 500);
  EXPECT_TRUE(p.subpixel);
  ASSERT_TRUE(p.precision.has_value());
  EXPECT_EQ(*p.precision, rt::Precision::fp32);
  EXPECT_EQ(p.winograd, SuperPointParams::Winograd::off);
  EXPECT_EQ(p.winograd_tile, rt::WinogradConv3x3::Tile::f43);

  const SuperPointParams defaults = load_superpoint_params(YAML::Node());
  EXPECT_FLOAT_EQ(defaults.keypoint_threshold, 0.005f);
  EXPECT_EQ(defaults.nms_radius, 4);
  EXPECT_EQ(defaults.remove_borders, 4);
  EXPECT_EQ(defaults.max_keypoints, 400);
  EXPECT_FALSE(defaults.subpixel) << "the reference network's whole pixels unless asked";
  EXPECT_FALSE(defaults.precision.has_value());
  EXPECT_EQ(defaults.winograd, SuperPointParams::Winograd::automatic);
  EXPECT_EQ(defaults.winograd_tile, rt::WinogradConv3x3::Tile::f63);

  EXPECT_THROW(load_superpoint_params(io::Config::from_string("p:\n  nms_radius: abc\n").section("p")),
               std::runtime_error);
  EXPECT_THROW(load_superpoint_params(io::Config::from_string("p:\n  precision: fp8\n").section("p")),
               std::runtime_error);
  EXPECT_THROW(load_superpoint_params(io::Config::from_string("p:\n  winograd: yes\n").section("p")),
               std::runtime_error);
  EXPECT_THROW(load_superpoint_params(io::Config::from_string("p:\n  winograd_tile: 5\n").section("p")),
               std::runtime_error);
}

TEST(SuperPointErrors, RejectsWrongImages) {
  const auto pack = reference::random_superpoint_pack(1);
  SuperPoint sp(gpu(), pack);
  EXPECT_THROW(sp.detect(cv::Mat()), std::invalid_argument);
  EXPECT_THROW(sp.detect(cv::Mat(8, 40, CV_8UC1, cv::Scalar(0))), std::invalid_argument);
  EXPECT_THROW(sp.detect(cv::Mat(40, 40, CV_8UC3, cv::Scalar(0))), std::invalid_argument);
}

// On a context used as a discrete GPU (the image in, keypoints, scores and descriptors out through staging
// buffers, kept from the second call on) detect gives what it gives with mapped buffers, call after call.
TEST(SuperPointDiscreteMemory, SameFeaturesAsWithMappedBuffers) {
  const rt::Context discrete({.use_unified_memory = false});
  const auto pack = reference::random_superpoint_pack(3);
  SuperPoint mapped(gpu(), pack), staged(discrete, pack);
  for (std::uint32_t seed : {4u, 5u, 6u}) {
    const cv::Mat image = random_image(101, 67, seed);
    const PointFeatures want = mapped.detect(image), got = staged.detect(image);
    ASSERT_GT(want.size(), 5u);
    EXPECT_EQ(got.keypoints, want.keypoints) << "image " << seed;
    EXPECT_EQ(got.scores, want.scores) << "image " << seed;
    EXPECT_EQ(got.descriptors, want.descriptors) << "image " << seed;
  }
}

// A call is one queue submission once its plan exists: the image is written into mapped memory and the outputs
// are copied to the host by the recorded sequence, on a context used as a discrete GPU (staging) as on the mapped
// one. Dense maps, asked for, are a transfer of their own.
TEST(SuperPointSubmissions, OneQueueSubmissionPerCall) {
  const rt::Context discrete({.use_unified_memory = false});
  const auto pack = reference::random_superpoint_pack(3);
  for (const rt::Context* context : {&static_cast<const rt::Context&>(gpu()), &discrete}) {
    SCOPED_TRACE(context == &discrete ? "staged" : "mapped");
    SuperPoint sp(*context, pack);
    ASSERT_GT(sp.detect(random_image(101, 67, 4)).size(), 5u);  // builds the plan: buffers, weights, pipelines
    for (std::uint32_t seed : {5u, 6u, 7u}) {
      const cv::Mat image = random_image(101, 67, seed);
      const std::uint64_t before = context->submission_count();
      EXPECT_GT(sp.detect(image).size(), 5u);
      EXPECT_EQ(context->submission_count() - before, 1u) << "image " << seed;
    }
  }
}

// A device without 16-bit features (here lavapipe created without them): `auto` runs fp32, an explicit fp16 or
// fp16s is refused before any pipeline is built, with the device, the missing feature and the way out named.
TEST(SuperPointErrors, DeviceWithout16BitFeatures) {
  const rt::Context fp32_only({.pipeline_cache = false, .use_16bit = false});
  const auto pack = reference::random_superpoint_pack(1);
  SuperPoint automatic(fp32_only, pack);
  EXPECT_EQ(automatic.precision(), rt::Precision::fp32);
  EXPECT_GT(automatic.detect(random_image(64, 48, 3)).keypoints.size(), 0u);
  for (const auto precision : {rt::Precision::fp16s, rt::Precision::fp16}) {
    SuperPointParams params;
    params.precision = precision;
    const std::string error = test::error_of([&] { SuperPoint sp(fp32_only, pack, params); });
    for (const std::string& part :
         std::vector<std::string>{"SuperPoint", fp32_only.caps().name, "16-bit storage", "use fp32 or auto"})
      EXPECT_NE(error.find(part), std::string::npos) << part << " not in: " << error;
  }
}

}  // namespace
}  // namespace vkvo::features
