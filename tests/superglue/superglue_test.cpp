// SuperGlue on the device against the double-precision reference (tests/superglue/superglue_reference.hpp) with
// random weights, in every precision the device supports: the whole network, networks reduced to single stages
// (no GNN layer: encoder + scores + Sinkhorn + extraction; one self layer: attention), edge cases.
#include <algorithm>

#include <gtest/gtest.h>

#include "common/gpu.hpp"
#include "features/superglue.hpp"
#include "runtime/context.hpp"
#include "runtime/ops.hpp"
#include "superglue_reference.hpp"

namespace vkvo::features {
namespace {

using test::gpu;

// Sinkhorn's timed dispatches in a profiled call.
std::ptrdiff_t sinkhorn_dispatches(const std::vector<rt::CommandTiming>& timings) {
  return std::count_if(timings.begin(), timings.end(), [](const auto& t) { return t.label == "sinkhorn"; });
}

// Attention computed as q.k GEMM, softmax and p.v GEMM rather than by the fused kernel.
std::ptrdiff_t three_pass_attentions(const std::vector<rt::CommandTiming>& timings) {
  return std::count_if(timings.begin(), timings.end(), [](const auto& t) { return t.label.ends_with(" attn q.k"); });
}

class SuperGlueRandom : public ::testing::TestWithParam<rt::Precision> {
 protected:
  bool reads_packed_texels() const { return gpu().supports_uniform_texel_format(rt::packed_texel_format(GetParam())); }
  void SetUp() override {
    if (!gpu().caps().supports(GetParam()))
      GTEST_SKIP() << gpu().caps().name << " does not support " << rt::to_string(GetParam());
  }
  SuperGlueParams params() const {
    return {.match_threshold = 0.2f, .sinkhorn_iterations = 0, .precision = GetParam()};
  }
  // Log-assignment tolerance: fp32 shaders vs the double reference differ by summation order only; fp16 storage
  // rounds every activation to 11 bits (same bound as golden/README.md).
  double tolerance() const { return GetParam() == rt::Precision::fp32 ? 1e-3 : 0.05; }
};

// Noisy copies of part of set a, plus fresh points, so that there is something to match.
std::pair<PointFeatures, PointFeatures> make_pair(std::size_t n0, std::size_t n1, int dim, std::uint32_t seed) {
  std::mt19937 rng(seed);
  PointFeatures a = test::random_features(n0, dim, rng);
  PointFeatures b = test::random_features(n1, dim, rng);
  std::normal_distribution<float> noise(0.0f, 0.15f);
  for (std::size_t j = 0; j < std::min(n0, n1) * 2 / 3; ++j) {
    const std::size_t i = (j * 7 + 3) % n0;
    b.keypoints[j] = a.keypoints[i] + Eigen::Vector2f(noise(rng) * 10, noise(rng) * 10);
    for (int c = 0; c < dim; ++c)
      b.descriptors(Eigen::Index(j), c) = a.descriptors(Eigen::Index(i), c) + noise(rng) / 4;
    b.descriptors.row(Eigen::Index(j)).normalize();
  }
  return {a, b};
}

void expect_matches_reference(SuperGlue& net, const io::ModelPack& pack, const PointFeatures& a, const PointFeatures& b,
                              double tolerance, double min_identical) {
  Eigen::MatrixXf la;
  const PointMatches got = net.match(a, b, &la);
  const auto ref = test::reference_superglue(pack, a, b, 0.2, net.config().sinkhorn_iterations);
  ASSERT_EQ(la.rows(), ref.log_assignment.rows());
  ASSERT_EQ(la.cols(), ref.log_assignment.cols());
  const double err = (la.cast<double>() - ref.log_assignment).cwiseAbs().maxCoeff();
  EXPECT_LE(err, tolerance) << a.size() << " x " << b.size() << " log-assignment";
  ASSERT_EQ(got.matches0.size(), a.size());
  std::size_t same = 0;
  for (std::size_t i = 0; i < a.size(); ++i) same += got.matches0[i] == ref.matches.matches0[i];
  EXPECT_GE(double(same), min_identical * double(a.size())) << same << " of " << a.size() << " identical matches0";
  EXPECT_GT(ref.matches.count(), 0u) << "the case should produce matches";
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (got.matches0[i] == ref.matches.matches0[i] && got.matches0[i] >= 0) {
      EXPECT_NEAR(got.scores0[i], ref.matches.scores0[i], tolerance * 2) << "matching score of keypoint " << i;
    }
  }
}

TEST_P(SuperGlueRandom, WholeNetworkMatchesReference) {
  const auto pack = test::random_superglue_pack({});
  SuperGlue net(gpu(), pack, params());
  EXPECT_EQ(net.precision(), GetParam());
  EXPECT_EQ(net.config().cross_layers.size(), 3u);
  const auto [a, b] = make_pair(37, 23, 32, 1);  // N != M, neither a multiple of the tiles
  expect_matches_reference(net, pack, a, b, tolerance(), GetParam() == rt::Precision::fp32 ? 1.0 : 0.9);
  // Same sizes again (recorded sequence reused), then swapped sizes (re-recorded).
  const auto [c, d] = make_pair(37, 23, 32, 2);
  expect_matches_reference(net, pack, c, d, tolerance(), GetParam() == rt::Precision::fp32 ? 1.0 : 0.9);
  expect_matches_reference(net, pack, d, c, tolerance(), GetParam() == rt::Precision::fp32 ? 1.0 : 0.9);
  EXPECT_TRUE(net.last_timings().empty()) << "no timestamps unless profiling";
  // Profiling re-records with a timestamp per dispatch and changes no result.
  const PointMatches plain = net.match(c, d);
  net.set_profiling(true);
  const PointMatches profiled = net.match(c, d);
  EXPECT_EQ(profiled.matches0, plain.matches0);
  EXPECT_EQ(profiled.scores0, plain.scores0);
  if (gpu().caps().timestamps) {
    const auto timings = net.last_timings();
    EXPECT_GE(sinkhorn_dispatches(timings), 1) << "the stage table needs Sinkhorn's dispatches";
    EXPECT_GT(timings.size(), 5u * net.config().cross_layers.size()) << "a timestamp per dispatch";
  }
}

TEST_P(SuperGlueRandom, SinkhornAndExtractionWithoutGnn) {
  test::RandomSuperGlueSpec spec;
  spec.cross = {};
  spec.sinkhorn_iterations = 20;
  const auto pack = test::random_superglue_pack(spec);
  // Every Sinkhorn kernel: through texel buffers (the default where the device reads them) with a dispatch per
  // half-iteration (an invocation or a workgroup per line) and as one fused workgroup, and the storage-buffer
  // fallback; 50 + 1 and 41 + 1 lines are not multiples of the texel width.
  struct Form {
    bool texel_kernels, fused, workgroup_per_line;
    const char* name;
  };
  for (const auto& [texel_kernels, fused, workgroup_per_line, name] :
       {Form{true, false, false, "texel-buffer Sinkhorn, an invocation per line"},
        Form{true, false, true, "texel-buffer Sinkhorn, a workgroup per line"},
        Form{true, true, false, "fused texel-buffer Sinkhorn"}, Form{false, false, false, "storage-buffer Sinkhorn"}}) {
    SCOPED_TRACE(name);
    SuperGlueParams p = params();
    p.texel_kernels = texel_kernels;
    p.fused_sinkhorn = fused;
    p.sinkhorn_workgroup_per_line = workgroup_per_line;
    SuperGlue net(gpu(), pack, p);
    net.set_profiling(true);
    EXPECT_EQ(net.config().sinkhorn_iterations, 20);
    const auto [a, b] = make_pair(50, 41, 32, 3);
    expect_matches_reference(net, pack, a, b, tolerance(), GetParam() == rt::Precision::fp32 ? 1.0 : 0.9);
    const bool texel_sinkhorn = texel_kernels && gpu().supports_uniform_texel_format(vk::Format::eR32G32B32A32Sfloat);
    if (gpu().caps().timestamps && texel_sinkhorn) {
      EXPECT_EQ(sinkhorn_dispatches(net.last_timings()), fused ? 1 : 2 * 20) << "dispatches of the Sinkhorn iterations";
    }
  }
}

TEST_P(SuperGlueRandom, SingleSelfAndCrossAttentionLayers) {
  for (bool cross : {false, true}) {
    test::RandomSuperGlueSpec spec;
    spec.cross = {cross};
    spec.dim = 64;
    spec.heads = 4;
    spec.seed = cross ? 11 : 12;
    spec.proj_gain = 8.0;  // scores = gain^2 cos / sqrt(64): strong enough to beat the bin score
    const auto pack = test::random_superglue_pack(spec);
    // The fused attention kernel (the default where the device reads texel buffers) in its register form with 4
    // and 8 query rows per invocation and in its shared-memory form (GPUs' choice), and the fallback's q.k GEMM,
    // softmax and p.v GEMM.
    struct Form {
      bool texel_kernels;
      int rows;
      bool shared;
    };
    for (const auto& [texel_kernels, rows, shared] :
         {Form{true, 4, false}, Form{true, 8, false}, Form{true, 0, true}, Form{false, 0, false}}) {
      SCOPED_TRACE(!texel_kernels ? "three-pass attention"
                   : shared       ? "fused attention, shared-memory tiles"
                                  : "fused attention, " + std::to_string(rows) + " rows");
      SuperGlueParams p = params();
      p.texel_kernels = texel_kernels;
      p.attention_rows = rows;
      p.shared_attention = shared;
      SuperGlue net(gpu(), pack, p);
      net.set_profiling(true);
      if (texel_kernels && reads_packed_texels()) {
        EXPECT_EQ(net.attention_form(), shared ? "shared" : "registers");
      }
      // Set sizes that are not multiples of 4 or 8, then multiples of 8: the fused kernel's last query group and
      // key block are partial; the fallback's softmax and p.v GEMM take their general paths, then the vec4
      // softmax and the tiled p.v.
      for (const auto& [n0, n1] : {std::pair{29, 66}, std::pair{24, 40}}) {
        const auto [a, b] = make_pair(n0, n1, 64, 4);
        expect_matches_reference(net, pack, a, b, tolerance(), GetParam() == rt::Precision::fp32 ? 1.0 : 0.9);
        if (gpu().caps().timestamps) {
          EXPECT_EQ(three_pass_attentions(net.last_timings()) == 0, texel_kernels && reads_packed_texels())
              << "the fused kernel runs where the device reads packed texels, the three passes elsewhere";
        }
      }
    }
  }
}

// A head of 4 dimensions is half a packed texel of halves: the 16-bit variants fall back to the three-pass
// attention, fp32 (4 values per texel) keeps the fused kernel; both match the reference.
TEST_P(SuperGlueRandom, HeadsNarrowerThanAPackedTexel) {
  test::RandomSuperGlueSpec spec;
  spec.cross = {true};
  spec.dim = 16;
  spec.heads = 4;
  spec.seed = 13;
  spec.proj_gain = 8.0;
  const auto pack = test::random_superglue_pack(spec);
  SuperGlue net(gpu(), pack, params());
  net.set_profiling(true);
  const auto [a, b] = make_pair(21, 30, 16, 5);
  expect_matches_reference(net, pack, a, b, tolerance(), GetParam() == rt::Precision::fp32 ? 1.0 : 0.9);
  if (gpu().caps().timestamps) {
    EXPECT_EQ(three_pass_attentions(net.last_timings()) == 0,
              GetParam() == rt::Precision::fp32 && reads_packed_texels());
  }
}

// The largest sets the matcher is built for, N = M = 2048 (2049 lines of couplings with the dustbins): every
// buffer, texel view and dispatch grid at its largest, and the per-dispatch Sinkhorn rather than the fused one.
// A shallow network (32 dimensions, one self and one cross layer) and 20 Sinkhorn iterations keep the double
// reference to seconds: the sizes are under test here, the depth is in the tests above.
TEST_P(SuperGlueRandom, LargestSets) {
  test::RandomSuperGlueSpec spec;
  spec.cross = {false, true};
  spec.sinkhorn_iterations = 20;
  spec.proj_gain = 8.0;  // peaked enough among 2048 candidates for matches above the 0.2 threshold
  const auto pack = test::random_superglue_pack(spec);
  SuperGlue net(gpu(), pack, params());
  net.set_profiling(true);
  const auto [a, b] = make_pair(2048, 2048, 32, 6);
  expect_matches_reference(net, pack, a, b, tolerance(), GetParam() == rt::Precision::fp32 ? 1.0 : 0.9);
  if (gpu().caps().timestamps) {  // every Sinkhorn form but the fused one dispatches once per half-iteration
    EXPECT_EQ(sinkhorn_dispatches(net.last_timings()), 2 * 20) << "no fused Sinkhorn at this size";
  }
}

TEST_P(SuperGlueRandom, EdgeCases) {
  const auto pack = test::random_superglue_pack({});
  SuperGlue net(gpu(), pack, params());
  net.set_profiling(true);  // so that "nothing ran" below is seen, not a lack of timestamps
  std::mt19937 rng(5);
  const PointFeatures empty = test::random_features(0, 32, rng);
  const PointFeatures some = test::random_features(10, 32, rng);
  Eigen::MatrixXf la;
  auto r = net.match(empty, some, &la);
  EXPECT_TRUE(r.matches0.empty());
  EXPECT_EQ(la.size(), 0);
  r = net.match(some, empty);
  ASSERT_EQ(r.matches0.size(), 10u);
  EXPECT_EQ(r.count(), 0u);
  EXPECT_TRUE(net.last_timings().empty()) << "nothing should run on the device for an empty set";
  // One keypoint on each side, and one against many.
  PointFeatures one = test::random_features(1, 32, rng);
  PointFeatures copy = one;
  expect_matches_reference(net, pack, one, copy, tolerance(), 1.0);
  EXPECT_EQ(net.match(one, copy).matches0, std::vector<int>{0}) << "a single identical point must match";
  PointFeatures many = some;
  many.descriptors.row(6) = one.descriptors.row(0);
  many.keypoints[6] = one.keypoints[0];
  expect_matches_reference(net, pack, one, many, tolerance(), 1.0);
  // Missing image size or descriptor width mismatch are errors, not crashes.
  PointFeatures bad = some;
  bad.image_width = 0;
  EXPECT_THROW(net.match(some, bad), std::invalid_argument);
  bad = some;
  bad.descriptors.conservativeResize(10, 16);
  EXPECT_THROW(net.match(some, bad), std::invalid_argument);
  // An attention row count the kernel is not built for is refused when the matcher is made.
  SuperGlueParams too_many = params();
  too_many.attention_rows = 17;
  EXPECT_THROW(SuperGlue(gpu(), pack, too_many), std::invalid_argument);
}

INSTANTIATE_TEST_SUITE_P(AllPrecisions, SuperGlueRandom, ::testing::ValuesIn(rt::kAllPrecisions),
                         [](const auto& info) { return std::string(rt::to_string(info.param)); });

// On a context used as a discrete GPU (keypoints, scores and descriptors in, matches out through staging buffers,
// kept from the second call on) the network gives what it gives with mapped buffers, call after call.
TEST(SuperGlueDiscreteMemory, SameMatchesAsWithMappedBuffers) {
  const rt::Context discrete({.use_unified_memory = false});
  const auto pack = test::random_superglue_pack({});
  SuperGlue mapped(gpu(), pack), staged(discrete, pack);
  for (std::uint32_t seed : {7u, 8u, 9u}) {
    const auto [a, b] = make_pair(37, 23, 32, seed);
    Eigen::MatrixXf want_la, got_la;
    const PointMatches want = mapped.match(a, b, &want_la), got = staged.match(a, b, &got_la);
    EXPECT_GT(want.count(), 0u);
    EXPECT_EQ(got.matches0, want.matches0) << "pair " << seed;
    EXPECT_EQ(got.scores0, want.scores0) << "pair " << seed;
    EXPECT_EQ(got_la, want_la) << "pair " << seed;
  }
}

// A call is one queue submission once the set sizes' buffers exist, through staging buffers as with mapped ones.
TEST(SuperGlueSubmissions, OneQueueSubmissionPerCall) {
  const rt::Context discrete({.use_unified_memory = false});
  const auto pack = test::random_superglue_pack({});
  for (const rt::Context* context : {&static_cast<const rt::Context&>(gpu()), &discrete}) {
    SCOPED_TRACE(context == &discrete ? "staged" : "mapped");
    SuperGlue net(*context, pack);
    const auto [a, b] = make_pair(37, 23, 32, 7);
    net.match(a, b);  // allocates and records for these sizes
    for (std::uint32_t seed : {8u, 9u, 10u}) {
      const auto [c, d] = make_pair(37, 23, 32, seed);
      const std::uint64_t before = context->submission_count();
      EXPECT_GT(net.match(c, d).count(), 0u);
      EXPECT_EQ(context->submission_count() - before, 1u) << "pair " << seed;
    }
  }
}

TEST(SuperGlueParams, LoadsYamlSection) {
  const auto p = load_superglue_params(YAML::Load("{match_threshold: 0.3, sinkhorn_iterations: 50, precision: fp32}"));
  EXPECT_FLOAT_EQ(p.match_threshold, 0.3f);
  EXPECT_EQ(p.sinkhorn_iterations, 50);
  ASSERT_TRUE(p.precision.has_value());
  EXPECT_EQ(*p.precision, rt::Precision::fp32);
  const auto d = load_superglue_params(YAML::Node());
  EXPECT_FLOAT_EQ(d.match_threshold, 0.2f);
  EXPECT_EQ(d.sinkhorn_iterations, 100);
  EXPECT_FALSE(d.precision.has_value());
  EXPECT_FALSE(load_superglue_params(YAML::Load("{precision: auto}")).precision.has_value());
  EXPECT_THROW(load_superglue_params(YAML::Load("{precision: fp64}")), std::runtime_error);
  EXPECT_THROW(load_superglue_params(YAML::Load("{match_threshold: [1, 2]}")), std::runtime_error);
}

}  // namespace
}  // namespace vkvo::features
