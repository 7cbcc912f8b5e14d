// The mutual-nearest-neighbour matcher on synthetic descriptor sets whose answer is known by construction and
// checked against a brute-force CPU matcher.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "common/gpu.hpp"
#include "features/nn_matcher.hpp"
#include "superglue_reference.hpp"

namespace vkvo::features {
namespace {

using test::gpu;

// Brute force: mutual best by cosine similarity, gate, ratio on L2 distances.
PointMatches brute_force(const PointFeatures& a, const PointFeatures& b, const NnMatcherParams& p) {
  const Eigen::MatrixXd s = a.descriptors.cast<double>() * b.descriptors.cast<double>().transpose();
  PointMatches out;
  out.matches0.assign(a.size(), -1);
  out.scores0.assign(a.size(), 0.0f);
  for (Eigen::Index i = 0; i < s.rows(); ++i) {
    Eigen::Index j = 0, back = 0;
    const double best = s.row(i).maxCoeff(&j);
    s.col(j).maxCoeff(&back);
    if (back != i || 1.0 - best > p.max_cosine_distance) continue;
    if (p.ratio > 0 && s.cols() > 1) {
      Eigen::RowVectorXd row = s.row(i);
      row(j) = -1e9;
      const double second = row.maxCoeff();
      if (std::sqrt(std::max(0.0, 2 - 2 * best)) >= p.ratio * std::sqrt(std::max(0.0, 2 - 2 * second))) continue;
    }
    out.matches0[std::size_t(i)] = int(j);
    out.scores0[std::size_t(i)] = float(best);
  }
  return out;
}

// Plants slightly perturbed copies of a's first `count` descriptors in b, a's keypoint i at b's index perm[i]
// (a random permutation of b's indices); returns perm.
std::vector<int> plant_copies(const PointFeatures& a, int count, PointFeatures& b, std::mt19937& rng) {
  std::vector<int> perm(b.size());
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), rng);
  std::normal_distribution<float> noise(0.0f, 0.02f);
  for (int i = 0; i < count; ++i) {
    for (Eigen::Index c = 0; c < a.descriptors.cols(); ++c)
      b.descriptors(perm[std::size_t(i)], c) = a.descriptors(i, c) + noise(rng);
    b.descriptors.row(perm[std::size_t(i)]).normalize();
  }
  return perm;
}

// A call is one queue submission once the set sizes' buffers exist, through staging buffers as with mapped ones,
// and what it finds does not depend on the path.
TEST(NnMatcher, OneQueueSubmissionPerCall) {
  const rt::Context discrete({.use_unified_memory = false});
  std::mt19937 rng(5);
  const PointFeatures a = test::random_features(120, 256, rng);
  PointFeatures b = test::random_features(150, 256, rng);
  plant_copies(a, 80, b, rng);
  const PointMatches want = brute_force(a, b, NnMatcherParams{});
  for (const rt::Context* context : {&static_cast<const rt::Context&>(gpu()), &discrete}) {
    SCOPED_TRACE(context == &discrete ? "staged" : "mapped");
    NnMatcher matcher(*context);
    matcher.match(a, b);  // allocates and records for these sizes
    for (int call = 0; call < 3; ++call) {
      const std::uint64_t before = context->submission_count();
      EXPECT_EQ(matcher.match(a, b).matches0, want.matches0);
      EXPECT_EQ(context->submission_count() - before, 1u) << "call " << call;
    }
  }
}

TEST(NnMatcher, FindsPlantedCorrespondences) {
  std::mt19937 rng(3);
  const PointFeatures a = test::random_features(120, 256, rng);
  PointFeatures b = test::random_features(150, 256, rng);
  const std::vector<int> perm = plant_copies(a, 80, b, rng);  // the other 40 of a are unrelated
  NnMatcher matcher(gpu());
  const PointMatches m = matcher.match(a, b);
  EXPECT_TRUE(matcher.last_timings().empty()) << "no timestamps unless profiling";
  // Profiling re-records with a timestamp per dispatch and changes no result.
  matcher.set_profiling(true);
  const PointMatches profiled = matcher.match(a, b);
  EXPECT_EQ(profiled.matches0, m.matches0);
  EXPECT_EQ(profiled.scores0, m.scores0);
  if (gpu().caps().timestamps) {
    const auto timings = matcher.last_timings();
    ASSERT_EQ(timings.size(), 3u);
    EXPECT_EQ(timings[0].label, "similarity");
    EXPECT_EQ(timings[2].label, "select");
  }
  ASSERT_EQ(m.matches0.size(), 120u);
  for (int i = 0; i < 80; ++i) {
    EXPECT_EQ(m.matches0[std::size_t(i)], perm[std::size_t(i)]) << "planted keypoint " << i;
    EXPECT_GT(m.scores0[std::size_t(i)], 0.9f);
  }
  // Random 256-D unit vectors have cosine ~ N(0, 1/16): far outside the 0.245 cosine-distance gate.
  for (int i = 80; i < 120; ++i) EXPECT_EQ(m.matches0[std::size_t(i)], -1) << "unrelated keypoint " << i;
  EXPECT_EQ(m.matches0, brute_force(a, b, {}).matches0);
}

TEST(NnMatcher, GateAndRatioTestAgreeWithBruteForce) {
  std::mt19937 rng(4);
  const PointFeatures a = test::random_features(64, 32, rng);
  PointFeatures b = test::random_features(70, 32, rng);
  std::normal_distribution<float> noise(0.0f, 0.1f);
  for (int i = 0; i < 64; ++i) {  // noisy copies: some pass the gate, some not; some ambiguous for the ratio
    for (int c = 0; c < 32; ++c) b.descriptors(i, c) = a.descriptors(i, c) + noise(rng);
    b.descriptors.row(i).normalize();
  }
  for (const NnMatcherParams p :
       {NnMatcherParams{0.245f, 0.0f}, NnMatcherParams{0.5f, 0.8f}, NnMatcherParams{2.0f, 0.0f}}) {
    NnMatcher matcher(gpu(), p);
    const PointMatches got = matcher.match(a, b);
    const PointMatches want = brute_force(a, b, p);
    EXPECT_EQ(got.matches0, want.matches0) << "gate " << p.max_cosine_distance << " ratio " << p.ratio;
    for (std::size_t i = 0; i < got.scores0.size(); ++i) EXPECT_NEAR(got.scores0[i], want.scores0[i], 1e-5);
    EXPECT_GT(want.count(), 0u);
  }
}

TEST(NnMatcher, EmptyAndSingleSets) {
  std::mt19937 rng(5);
  const PointFeatures empty = test::random_features(0, 256, rng);
  const PointFeatures one = test::random_features(1, 256, rng);
  NnMatcher matcher(gpu(), {.max_cosine_distance = 0.1f, .ratio = 0.8f});
  EXPECT_TRUE(matcher.match(empty, one).matches0.empty());
  EXPECT_EQ(matcher.match(one, empty).matches0, std::vector<int>{-1});
  EXPECT_EQ(matcher.match(one, one).matches0, std::vector<int>{0}) << "ratio test skipped with one candidate";
}

// The largest sets the matchers are built for (2048 x 2048, 256 dimensions): planted pairs found, and the whole
// answer equal to brute force.
TEST(NnMatcher, LargestSets) {
  std::mt19937 rng(6);
  const PointFeatures a = test::random_features(2048, 256, rng);
  PointFeatures b = test::random_features(2048, 256, rng);
  const std::vector<int> perm = plant_copies(a, 1500, b, rng);
  NnMatcher matcher(gpu());
  const PointMatches m = matcher.match(a, b);
  ASSERT_EQ(m.matches0.size(), 2048u);
  for (int i = 0; i < 1500; ++i)
    EXPECT_EQ(m.matches0[std::size_t(i)], perm[std::size_t(i)]) << "planted keypoint " << i;
  EXPECT_EQ(m.matches0, brute_force(a, b, {}).matches0);
}

TEST(NnMatcher, LoadsYamlSection) {
  auto p = load_nn_matcher_params(YAML::Load("{min_similarity: 0.8, ratio: 0.9}"));
  EXPECT_NEAR(p.max_cosine_distance, 0.2f, 1e-6);
  EXPECT_FLOAT_EQ(p.ratio, 0.9f);
  p = load_nn_matcher_params(YAML::Load("{max_cosine_distance: 0.3}"));
  EXPECT_FLOAT_EQ(p.max_cosine_distance, 0.3f);
  EXPECT_FLOAT_EQ(p.ratio, 0.0f);
  EXPECT_THROW(load_nn_matcher_params(YAML::Load("{max_cosine_distance: 0.3, min_similarity: 0.8}")),
               std::runtime_error);
  EXPECT_THROW(load_nn_matcher_params(YAML::Load("{ratio: abc}")), std::runtime_error);
}

TEST(RandomPointFeatures, AreUnitDescriptorsInsideTheImageAndRepeatWithTheSeed) {
  std::mt19937 rng(5), same_seed(5);
  const PointFeatures f = random_point_features(50, 16, rng, 100, 40);
  ASSERT_EQ(f.size(), 50u);
  ASSERT_EQ(f.scores.size(), 50u);
  ASSERT_EQ(f.descriptors.rows(), 50);
  ASSERT_EQ(f.descriptors.cols(), 16);
  EXPECT_EQ(f.image_width, 100);
  EXPECT_EQ(f.image_height, 40);
  for (std::size_t i = 0; i < f.size(); ++i) {
    EXPECT_GE(f.keypoints[i].x(), 0.0f);
    EXPECT_LT(f.keypoints[i].x(), 100.0f);
    EXPECT_GE(f.keypoints[i].y(), 0.0f);
    EXPECT_LT(f.keypoints[i].y(), 40.0f);
    EXPECT_GE(f.scores[i], 0.0f);
    EXPECT_LT(f.scores[i], 1.0f);
    EXPECT_NEAR(f.descriptors.row(Eigen::Index(i)).norm(), 1.0f, 1e-5f);  // float rounding of the normalisation
  }
  const PointFeatures again = random_point_features(50, 16, same_seed, 100, 40);
  EXPECT_EQ(again.descriptors, f.descriptors);
  EXPECT_EQ(again.keypoints, f.keypoints);
  EXPECT_TRUE(random_point_features(0, 16, rng, 100, 40).descriptors.size() == 0);
}

}  // namespace
}  // namespace vkvo::features
