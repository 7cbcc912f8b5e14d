// Motion-only pose estimation on synthetic matches: noise, 30% outliers, a poor prior (PnP start), lines only,
// points only.
#include <random>

#include <gtest/gtest.h>

#include "backend/pose_estimation.hpp"
#include "scene_fixture.hpp"

namespace vkvo::backend {
namespace {

struct Matches {
  std::vector<PointMatch> points;
  std::vector<LineMatch> lines;
  std::vector<bool> point_is_outlier, line_is_outlier;
};

// Matches of keyframe k of the scene against the true landmarks; a fraction of them replaced by gross outliers
// (measurements moved 20-80 px).
Matches make_matches(const test::Scene& s, int k, double outlier_fraction, std::mt19937& rng) {
  Matches m;
  std::uniform_real_distribution<double> u01(0, 1), shift(20, 80);
  std::uniform_int_distribution<int> sign(0, 1);
  auto gross = [&] { return (sign(rng) ? 1.0 : -1.0) * shift(rng); };
  for (const auto& o : s.point_obs[k]) {
    PointMatch pm{s.points[o.point], {o.pixel, o.right_x}};
    const bool outlier = u01(rng) < outlier_fraction;
    if (outlier) {
      pm.measurement.pixel += Eigen::Vector2d(gross(), gross());
      if (pm.measurement.stereo()) pm.measurement.right_x = pm.measurement.pixel.x() - 5.0;
    }
    m.points.push_back(pm);
    m.point_is_outlier.push_back(outlier);
  }
  for (const auto& o : s.line_obs[k]) {
    LineMatch lm{geometry::PlueckerLine::from_points(s.segments[o.line].first, s.segments[o.line].second),
                 {o.left, o.right}};
    const bool outlier = u01(rng) < outlier_fraction;
    if (outlier) {
      const double dx = gross(), dy = gross();
      lm.measurement.left += geometry::Segment2d(dx, dy, dx, -dy);
      if (lm.measurement.right) *lm.measurement.right += geometry::Segment2d(dx, dy, dx, -dy);
    }
    m.lines.push_back(lm);
    m.line_is_outlier.push_back(outlier);
  }
  return m;
}

// Share of matches whose inlier flag agrees with the truth.
double flag_accuracy(const std::vector<bool>& flags, const std::vector<bool>& is_outlier) {
  int agree = 0;
  for (size_t i = 0; i < flags.size(); ++i) agree += flags[i] != is_outlier[i];
  return flags.empty() ? 1.0 : double(agree) / double(flags.size());
}

// Whether `estimate` is within `max_translation` (m) and `max_rotation` (rad) of `truth`; says both errors.
::testing::AssertionResult pose_near(const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth,
                                     double max_translation, double max_rotation) {
  const double t = test::translation_error(estimate, truth), r = test::rotation_error(estimate, truth);
  if (t < max_translation && r < max_rotation) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "pose off by " << t << " m (limit " << max_translation << ") and " << r
                                       << " rad (limit " << max_rotation << ")";
}

TEST(PoseEstimation, RecoversPoseWithNoiseAnd30PercentOutliers) {
  const test::Scene s = test::make_scene({.num_keyframes = 4, .pixel_noise = 0.5, .seed = 31});
  std::mt19937 rng(32);
  for (int k = 1; k < 4; ++k) {
    const Matches m = make_matches(s, k, 0.3, rng);
    ASSERT_GT(m.points.size(), 100u);
    ASSERT_GT(m.lines.size(), 15u);
    const Eigen::Isometry3d prior = test::perturb(s.T_world_camera[k], rng, 0.05, 0.03);
    const PoseEstimate est = estimate_pose(s.stereo, prior, m.points, m.lines, OptimizationParams{});
    EXPECT_TRUE(est.success);
    // 0.5 px noise on ~150 matches at 2.5-8 m: the pose is good to a few millimetres / tenths of a milliradian.
    EXPECT_TRUE(pose_near(est.T_world_camera, s.T_world_camera[k], 0.01, 2e-3)) << "keyframe " << k;
    EXPECT_GT(flag_accuracy(est.point_inliers, m.point_is_outlier), 0.97);
    EXPECT_GT(flag_accuracy(est.line_inliers, m.line_is_outlier), 0.9);
    EXPECT_EQ(est.num_point_inliers, std::count(est.point_inliers.begin(), est.point_inliers.end(), true));
  }
}

TEST(PoseEstimation, PoorPriorStartsFromPnpRansac) {
  const test::Scene s = test::make_scene({.num_keyframes = 3, .pixel_noise = 0.5, .seed = 33});
  std::mt19937 rng(34);
  const Matches m = make_matches(s, 2, 0.3, rng);
  // Prior 0.6 m and 0.4 rad off: almost no match agrees with it.
  const Eigen::Isometry3d prior = test::perturb(s.T_world_camera[2], rng, 0.6, 0.4);
  const PoseEstimate est = estimate_pose(s.stereo, prior, m.points, m.lines, OptimizationParams{});
  EXPECT_TRUE(est.used_pnp);
  EXPECT_TRUE(est.success);
  EXPECT_TRUE(pose_near(est.T_world_camera, s.T_world_camera[2], 0.01, 2e-3));
}

TEST(PoseEstimation, LinesOnlyAndPointsOnlyConverge) {
  const test::Scene s = test::make_scene({.num_keyframes = 3, .num_lines = 120, .pixel_noise = 0.3, .seed = 35});
  std::mt19937 rng(36);
  const Matches m = make_matches(s, 2, 0.0, rng);
  const Eigen::Isometry3d prior = test::perturb(s.T_world_camera[2], rng, 0.05, 0.03);
  const PoseEstimate lines_only = estimate_pose(s.stereo, prior, {}, m.lines, OptimizationParams{});
  EXPECT_TRUE(lines_only.success);
  EXPECT_EQ(lines_only.num_point_inliers, 0);
  EXPECT_TRUE(pose_near(lines_only.T_world_camera, s.T_world_camera[2], 0.01, 2e-3));
  const PoseEstimate points_only = estimate_pose(s.stereo, prior, m.points, {}, OptimizationParams{});
  EXPECT_TRUE(points_only.success);
  EXPECT_TRUE(pose_near(points_only.T_world_camera, s.T_world_camera[2], 0.01, 2e-3));
}

// Keyframe 2 of a scene with 0.3 px noise and every line measured 3 px off, which pulls a joint estimate
// away from the points-only pose; and a perturbed prior.
struct ShiftedLinesCase {
  test::Scene scene;
  Matches matches;
  Eigen::Isometry3d prior;
};
ShiftedLinesCase make_shifted_lines_case(unsigned seed) {
  ShiftedLinesCase c{test::make_scene({.num_keyframes = 3, .num_lines = 60, .pixel_noise = 0.3, .seed = seed}),
                     {},
                     Eigen::Isometry3d::Identity()};
  std::mt19937 rng(seed + 1);
  c.matches = make_matches(c.scene, 2, 0.0, rng);
  for (auto& l : c.matches.lines) l.measurement.left += geometry::Segment2d(3, 3, 3, 3);
  c.prior = test::perturb(c.scene.T_world_camera[2], rng, 0.05, 0.03);
  return c;
}

// AirVO's choice (optimization.pose_with_lines: false): the lines do not move the pose, which is then exactly the
// points-only estimate, yet they are still classified against it (the inlier flags feed the BA and the counts).
TEST(PoseEstimation, WithoutLinesInThePoseTheLinesAreOnlyClassified) {
  const auto [s, m, prior] = make_shifted_lines_case(41);
  OptimizationParams points_first;
  points_first.pose_with_lines = false;
  const PoseEstimate airvo = estimate_pose(s.stereo, prior, m.points, m.lines, points_first);
  const PoseEstimate points_only = estimate_pose(s.stereo, prior, m.points, {}, points_first);
  const PoseEstimate joint = estimate_pose(s.stereo, prior, m.points, m.lines, OptimizationParams{});
  EXPECT_TRUE(pose_near(airvo.T_world_camera, points_only.T_world_camera, 1e-9, 1e-9));
  EXPECT_GT(test::translation_error(joint.T_world_camera, points_only.T_world_camera), 1e-6)
      << "the shifted lines should move the joint estimate";
  EXPECT_EQ(airvo.line_inliers.size(), m.lines.size());
  EXPECT_GT(airvo.num_line_inliers, static_cast<int>(m.lines.size()) / 2);  // 3 px is well inside sqrt(50) * 0.8
}

// optimization.line_weight scales the lines' robust cost (AirVO's code: 0.1): a smaller weight moves the joint
// estimate of the test above towards the points-only pose.
TEST(PoseEstimation, LineWeightScalesTheLinesPull) {
  const auto [s, m, prior] = make_shifted_lines_case(43);
  const PoseEstimate points_only = estimate_pose(s.stereo, prior, m.points, {}, OptimizationParams{});
  OptimizationParams weighted;
  weighted.line_weight = 0.1;
  const double full_pull =
      test::translation_error(estimate_pose(s.stereo, prior, m.points, m.lines, OptimizationParams{}).T_world_camera,
                              points_only.T_world_camera);
  const double weak_pull = test::translation_error(
      estimate_pose(s.stereo, prior, m.points, m.lines, weighted).T_world_camera, points_only.T_world_camera);
  EXPECT_LT(weak_pull, 0.5 * full_pull) << "weight 0.1: " << weak_pull << " m, weight 1: " << full_pull << " m";
}

TEST(PoseEstimation, NoiselessIsExactAndTooFewMatchesFail) {
  const test::Scene s = test::make_scene({.num_keyframes = 2, .seed = 37});
  std::mt19937 rng(38);
  const Matches m = make_matches(s, 1, 0.0, rng);
  const Eigen::Isometry3d prior = test::perturb(s.T_world_camera[1], rng, 0.05, 0.03);
  OptimizationParams params;
  params.pose_iterations = 50;
  const PoseEstimate est = estimate_pose(s.stereo, prior, m.points, m.lines, params);
  EXPECT_TRUE(pose_near(est.T_world_camera, s.T_world_camera[1], 1e-7, 1e-8));
  EXPECT_EQ(est.num_point_inliers, static_cast<int>(m.points.size()));
  // A prior that already explains the matches (~1 px off) needs no PnP start.
  const PoseEstimate near =
      estimate_pose(s.stereo, test::perturb(s.T_world_camera[1], rng, 0.005, 0.002), m.points, m.lines, params);
  EXPECT_FALSE(near.used_pnp);
  EXPECT_LT(test::translation_error(near.T_world_camera, s.T_world_camera[1]), 1e-7);
  const std::vector<PointMatch> few(m.points.begin(), m.points.begin() + 5);
  EXPECT_FALSE(estimate_pose(s.stereo, prior, few, {}, params).success);
}

}  // namespace
}  // namespace vkvo::backend
