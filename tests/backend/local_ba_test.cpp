// Local bundle adjustment on synthetic stereo scenes: exact recovery from noiseless data, the noise floor from
// noisy data, fixed keyframes untouched, lines-only and points-only windows, outlier observations erased.
#include <algorithm>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "backend/local_ba.hpp"
#include "scene_fixture.hpp"

namespace vkvo::backend {
namespace {

// Perturbs the poses of the keyframes in `which`, and every landmark, in place.
void perturb_map(test::SceneMap& sm, const std::vector<map::Id>& which, std::mt19937& rng, double pose_t, double pose_r,
                 double point_sigma, double line_delta) {
  std::normal_distribution<double> n(0.0, 1.0);
  for (map::Id id : which) {
    auto* kf = sm.map.keyframe(id);
    kf->T_world_camera = test::perturb(kf->T_world_camera, rng, pose_t, pose_r);
  }
  for (const auto& [id, p] : sm.map.points())
    sm.map.point(id)->position += point_sigma * Eigen::Vector3d(n(rng), n(rng), n(rng));
  for (const auto& [id, l] : sm.map.lines())
    sm.map.line(id)->line = geometry::OrthonormalLine::from_pluecker(l.line)
                                .plus(line_delta * Eigen::Vector4d(n(rng), n(rng), n(rng), n(rng)))
                                .to_pluecker();
}

struct Errors {
  double max_pose_t = 0, max_pose_r = 0, rms_point = 0, max_line_angle = 0;
};

// A landmark counts when a keyframe of `keyframes` observes it (others are not optimised).
template <typename Landmark>
bool seen_by(const Landmark& l, const std::vector<map::Id>& keyframes) {
  for (map::Id k : keyframes)
    if (l.observations.count(k)) return true;
  return false;
}

Errors errors(const test::SceneMap& sm, const test::Scene& s, const std::vector<map::Id>& keyframes) {
  Errors e;
  for (map::Id id : keyframes) {
    e.max_pose_t =
        std::max(e.max_pose_t, test::translation_error(sm.map.keyframe(id)->T_world_camera, s.T_world_camera[id]));
    e.max_pose_r =
        std::max(e.max_pose_r, test::rotation_error(sm.map.keyframe(id)->T_world_camera, s.T_world_camera[id]));
  }
  int n = 0;
  for (size_t i = 0; i < sm.point_ids.size(); ++i)
    if (const auto* p = sm.map.point(sm.point_ids[i]); p && seen_by(*p, keyframes)) {
      e.rms_point += (p->position - s.points[i]).squaredNorm();
      ++n;
    }
  e.rms_point = n ? std::sqrt(e.rms_point / n) : 0.0;
  for (size_t j = 0; j < sm.line_ids.size(); ++j)
    if (const auto* l = sm.map.line(sm.line_ids[j]); l && seen_by(*l, keyframes)) {
      const auto truth = geometry::PlueckerLine::from_points(s.segments[j].first, s.segments[j].second);
      // Direction angle and the distance of a true point from the estimated line.
      e.max_line_angle =
          std::max(e.max_line_angle, std::acos(std::min(1.0, std::abs(l->line.direction().dot(truth.v)))));
      e.max_line_angle = std::max(e.max_line_angle, l->line.distance_to(s.segments[j].first) / 5.0);
    }
  return e;
}

OptimizationParams ba_params(int window) {
  OptimizationParams p;
  p.window_size = window;
  p.ba_iterations = 20;
  return p;
}

TEST(LocalBA, NoiselessRecoversExactlyAndFixedKeyframesStay) {
  const test::Scene s = test::make_scene({.num_keyframes = 6, .seed = 41});
  test::SceneMap sm = test::make_scene_map(s);
  std::mt19937 rng(42);
  const std::vector<map::Id> window_truth{5, 4, 3, 2};
  perturb_map(sm, window_truth, rng, 0.03, 0.01, 0.05, 0.01);
  std::map<map::Id, Eigen::Matrix4d> before;
  for (const auto& [id, kf] : sm.map.keyframes()) before[id] = kf.T_world_camera.matrix();

  OptimizationParams params = ba_params(4);
  params.ba_iterations = 50;
  const LocalBAResult r = local_bundle_adjustment(sm.map, 5, s.stereo, params);
  ASSERT_TRUE(r.solved);
  EXPECT_EQ(r.window, window_truth);
  EXPECT_EQ(r.fixed, (std::vector<map::Id>{0, 1}));
  EXPECT_LT(r.final_cost, 1e-12 * r.initial_cost);
  EXPECT_EQ(r.point_outliers + r.line_outliers, 0);
  for (map::Id id : r.fixed) EXPECT_EQ(sm.map.keyframe(id)->T_world_camera.matrix(), before[id]);  // bitwise
  const Errors e = errors(sm, s, r.window);
  EXPECT_LT(e.max_pose_t, 1e-7);
  EXPECT_LT(e.max_pose_r, 1e-8);
  EXPECT_LT(e.rms_point, 1e-7);
  EXPECT_LT(e.max_line_angle, 1e-7);
}

// Noise floor: the solution reached from perturbed values has the same cost as the one reached from the truth.
TEST(LocalBA, NoisyConvergesToTheNoiseFloor) {
  const test::Scene s = test::make_scene({.num_keyframes = 6, .pixel_noise = 0.5, .seed = 43});
  const OptimizationParams params = ba_params(6);
  test::SceneMap from_truth = test::make_scene_map(s);
  const LocalBAResult ref = local_bundle_adjustment(from_truth.map, 5, s.stereo, params);
  ASSERT_TRUE(ref.solved);

  test::SceneMap sm = test::make_scene_map(s);
  std::mt19937 rng(44);
  perturb_map(sm, {1, 2, 3, 4, 5}, rng, 0.05, 0.02, 0.1, 0.02);
  const Errors start = errors(sm, s, {1, 2, 3, 4, 5});
  const Eigen::Matrix4d first = sm.map.keyframe(0)->T_world_camera.matrix();
  const LocalBAResult r = local_bundle_adjustment(sm.map, 5, s.stereo, params);
  ASSERT_TRUE(r.solved);
  EXPECT_EQ(r.fixed, (std::vector<map::Id>{0}));  // the whole map is in the window: the oldest keyframe holds the gauge
  EXPECT_EQ(sm.map.keyframe(0)->T_world_camera.matrix(), first);
  EXPECT_NEAR(r.final_cost, ref.final_cost, 0.01 * ref.final_cost);
  // Whitened cost per residual ~ noise: 0.5 px / 0.8 px sigma -> E|r|^2/2 ~ 0.2 per residual.
  const double per_residual = r.final_cost / (2.5 * (r.point_observations + r.line_observations));
  EXPECT_LT(per_residual, 0.25);
  const Errors end = errors(sm, s, {1, 2, 3, 4, 5});
  EXPECT_LT(end.max_pose_t, 0.01);
  EXPECT_LT(end.max_pose_r, 2e-3);
  EXPECT_LT(end.rms_point, 0.5 * start.rms_point);
  EXPECT_LT(end.max_line_angle, 0.5 * start.max_line_angle);
  // Same minimum as the solve started from the truth (far stereo points are only good to centimetres, so compare
  // the two solutions rather than the truth).
  double rms = 0;
  for (const auto& [id, p] : sm.map.points()) rms += (p.position - from_truth.map.point(id)->position).squaredNorm();
  EXPECT_LT(std::sqrt(rms / sm.map.points().size()), 1e-3);
  for (map::Id k = 1; k < 6; ++k)
    EXPECT_LT(test::translation_error(sm.map.keyframe(k)->T_world_camera, from_truth.map.keyframe(k)->T_world_camera),
              1e-4);
}

// Ceres orders an elimination group's blocks by address; the result must not depend on where the heap puts them.
// The second solve runs after the allocator's free lists were scrambled, so storage allocated block by block (as
// std::map nodes) would land in another address order. Bitwise equal poses, points and lines.
TEST(LocalBA, SameResultBitForBitWhateverTheHeapLayout) {
  const test::Scene s = test::make_scene({.num_keyframes = 6, .pixel_noise = 0.5, .seed = 47});
  const OptimizationParams params = ba_params(6);
  test::SceneMap first = test::make_scene_map(s);
  std::mt19937 rng(48);
  perturb_map(first, {1, 2, 3, 4, 5}, rng, 0.05, 0.02, 0.1, 0.02);
  test::SceneMap second = first;
  ASSERT_TRUE(local_bundle_adjustment(first.map, 5, s.stereo, params).solved);

  std::vector<std::unique_ptr<char[]>> blocks;
  for (int i = 0; i < 20000; ++i) blocks.emplace_back(new char[16 + 16 * (i % 8)]);
  std::shuffle(blocks.begin(), blocks.end(), rng);
  blocks.resize(blocks.size() / 2);  // frees half of them, in random address order
  ASSERT_TRUE(local_bundle_adjustment(second.map, 5, s.stereo, params).solved);

  for (const auto& [id, kf] : first.map.keyframes())
    EXPECT_EQ(kf.T_world_camera.matrix(), second.map.keyframe(id)->T_world_camera.matrix()) << "keyframe " << id;
  for (const auto& [id, p] : first.map.points())
    EXPECT_EQ(p.position, second.map.point(id)->position) << "point " << id;
  for (const auto& [id, l] : first.map.lines())
    EXPECT_EQ(l.line.vector(), second.map.line(id)->line.vector()) << "line " << id;
}

TEST(LocalBA, LinesOnlyAndPointsOnlyConverge) {
  for (const bool lines_only : {true, false}) {
    const test::Scene s = test::make_scene(
        {.num_keyframes = 5, .num_points = lines_only ? 0 : 200, .num_lines = lines_only ? 120 : 0, .seed = 45});
    test::SceneMap sm = test::make_scene_map(s);
    std::mt19937 rng(46);
    perturb_map(sm, {1, 2, 3, 4}, rng, 0.03, 0.01, 0.05, 0.01);
    OptimizationParams params = ba_params(5);
    params.ba_iterations = 50;
    const LocalBAResult r = local_bundle_adjustment(sm.map, 4, s.stereo, params);
    ASSERT_TRUE(r.solved) << (lines_only ? "lines only" : "points only");
    EXPECT_EQ(lines_only ? r.point_observations : r.line_observations, 0);
    const Errors e = errors(sm, s, {1, 2, 3, 4});
    EXPECT_LT(e.max_pose_t, 1e-6) << (lines_only ? "lines only" : "points only");
    EXPECT_LT(e.max_pose_r, 1e-7) << (lines_only ? "lines only" : "points only");
    EXPECT_LT(e.rms_point, 1e-6);
    EXPECT_LT(e.max_line_angle, 1e-6);
  }
}

TEST(LocalBA, OutlierObservationsAreErased) {
  const test::Scene s = test::make_scene({.num_keyframes = 5, .pixel_noise = 0.5, .seed = 47});
  test::SceneMap sm = test::make_scene_map(s);
  // Corrupt 10 point observations and 3 line observations of keyframe 3 by 30 px.
  auto* kf = sm.map.keyframe(3);
  std::vector<std::pair<map::Id, map::Id>> corrupted_points, corrupted_lines;
  for (size_t i = 0, done = 0; i < kf->keypoints.size() && done < 10; ++i)
    if (kf->point_ids[i] != map::kInvalidId) {
      kf->keypoints[i] += Eigen::Vector2d(30, -30);
      corrupted_points.emplace_back(kf->point_ids[i], 3);
      ++done;
    }
  for (size_t j = 0, done = 0; j < kf->lines.size() && done < 3; ++j)
    if (kf->line_ids[j] != map::kInvalidId) {
      kf->lines[j].left += geometry::Segment2d(0, 30, 0, 30);
      if (kf->lines[j].right) *kf->lines[j].right += geometry::Segment2d(0, 30, 0, 30);
      corrupted_lines.emplace_back(kf->line_ids[j], 3);
      ++done;
    }
  const LocalBAResult r = local_bundle_adjustment(sm.map, 4, s.stereo, ba_params(5));
  ASSERT_TRUE(r.solved);
  for (const auto& [p, k] : corrupted_points) EXPECT_EQ(sm.map.point(p)->observations.count(k), 0u);
  for (const auto& [l, k] : corrupted_lines) EXPECT_EQ(sm.map.line(l)->observations.count(k), 0u);
  EXPECT_GE(r.point_outliers, 10);
  EXPECT_LE(r.point_outliers, 12);  // chi2 50/75 at 0.5 px noise: (almost) no inlier is lost
  EXPECT_GE(r.line_outliers, 3);
  EXPECT_LT(test::translation_error(sm.map.keyframe(3)->T_world_camera, s.T_world_camera[3]), 0.01);
}

}  // namespace
}  // namespace vkvo::backend
