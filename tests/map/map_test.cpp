// Map bookkeeping: ids, two-way observations, culling and the co-visibility window.
#include <gtest/gtest.h>

#include "map/map.hpp"

namespace vkvo::map {
namespace {

Frame frame_with(int num_points, int num_lines) {
  Frame f;
  for (int i = 0; i < num_points; ++i) f.keypoints.emplace_back(10.0 * i, 5.0);
  f.lines.resize(num_lines);
  f.reset_associations();
  return f;
}

// Every landmark observation is mirrored by the keyframe's association and vice versa.
void expect_consistent(const Map& map) {
  for (const auto& [id, p] : map.points())
    for (const auto& [kf, index] : p.observations) EXPECT_EQ(map.keyframe(kf)->point_ids[index], id);
  for (const auto& [id, l] : map.lines())
    for (const auto& [kf, index] : l.observations) EXPECT_EQ(map.keyframe(kf)->line_ids[index], id);
  for (const auto& [kf_id, kf] : map.keyframes()) {
    for (int i = 0; i < static_cast<int>(kf.point_ids.size()); ++i)
      if (kf.point_ids[i] != kInvalidId) {
        EXPECT_EQ(map.point(kf.point_ids[i])->observations.at(kf_id), i);
      }
    for (int i = 0; i < static_cast<int>(kf.line_ids.size()); ++i)
      if (kf.line_ids[i] != kInvalidId) {
        EXPECT_EQ(map.line(kf.line_ids[i])->observations.at(kf_id), i);
      }
  }
}

TEST(Map, ObservationsBothWaysAndErasure) {
  Map map;
  const Id kf0 = map.add_keyframe(frame_with(5, 2)).id;
  EXPECT_EQ(kf0, 0u);
  const Id p0 = map.add_point({1, 2, 3}), p1 = map.add_point({0, 0, 4});
  const Id l0 = map.add_line(geometry::PlueckerLine::from_points({0, 0, 2}, {1, 0, 2}));
  EXPECT_NE(p0, p1);
  map.add_point_observation(p0, kf0, 1);
  map.add_point_observation(p1, kf0, 3);
  map.add_line_observation(l0, kf0, 0);
  // A second keyframe carrying ids from tracking registers them on insertion; a stale id is dropped.
  Frame f = frame_with(4, 1);
  f.point_ids[0] = p0;
  f.point_ids[2] = 999;
  f.line_ids[0] = l0;
  const Id kf1 = map.add_keyframe(f).id;
  EXPECT_EQ(map.point(p0)->observations.size(), 2u);
  EXPECT_EQ(map.keyframe(kf1)->point_ids[2], kInvalidId);
  EXPECT_EQ(map.line(l0)->observations.size(), 2u);
  expect_consistent(map);
  // Re-associating a feature moves the observation.
  map.add_point_observation(p1, kf1, 0);
  EXPECT_EQ(map.point(p0)->observations.count(kf1), 0u);
  EXPECT_EQ(map.keyframe(kf1)->point_ids[0], p1);
  expect_consistent(map);
  map.erase_point(p1);
  EXPECT_EQ(map.point(p1), nullptr);
  EXPECT_EQ(map.keyframe(kf0)->point_ids[3], kInvalidId);
  EXPECT_EQ(map.keyframe(kf1)->point_ids[0], kInvalidId);
  map.erase_keyframe(kf0);
  EXPECT_TRUE(map.point(p0)->observations.empty());
  EXPECT_EQ(map.line(l0)->observations.size(), 1u);
  expect_consistent(map);
  EXPECT_THROW(map.add_point_observation(p0, 77, 0), std::out_of_range);
}

TEST(Map, CullingAndCovisibility) {
  Map map;
  std::vector<Id> kfs;
  for (int k = 0; k < 5; ++k) kfs.push_back(map.add_keyframe(frame_with(10, 0)).id);
  // Point i seen by keyframes 0..i (so point 0 only by keyframe 0).
  std::vector<Id> pts;
  for (int i = 0; i < 5; ++i) {
    pts.push_back(map.add_point(Eigen::Vector3d::Constant(i)));
    for (int k = 0; k <= i; ++k) map.add_point_observation(pts[i], kfs[k], i);
  }
  const auto cov = map.covisible_keyframes(kfs[4]);
  ASSERT_EQ(cov.size(), 4u);
  EXPECT_EQ(cov.front().second, 1);  // kf4 sees only point 4, which every keyframe sees
  const auto cov1 = map.covisible_keyframes(kfs[1]);
  EXPECT_EQ(cov1.front().first, kfs[0]);  // kf0 and kf1 share points 1..4 (4), kf2 shares 2..4 (3)
  EXPECT_EQ(cov1.front().second, 4);
  EXPECT_EQ(map.covisible_keyframes(kfs[1], 4).size(), 1u);
  const auto window = map.local_window(kfs[3], 3);
  EXPECT_EQ(window, (std::vector<Id>{kfs[3], kfs[4], kfs[2]}));

  map.point(pts[3])->bad = true;
  MapParams params;
  params.min_point_observations = 2;
  params.culling_grace_keyframes = 2;
  const auto [points_culled, lines_culled] = map.cull(params);
  EXPECT_EQ(points_culled, 2);  // point 0 (one observation, old) and point 3 (bad)
  EXPECT_EQ(lines_culled, 0);
  EXPECT_EQ(map.point(pts[0]), nullptr);
  EXPECT_EQ(map.point(pts[3]), nullptr);
  EXPECT_NE(map.point(pts[1]), nullptr);
  expect_consistent(map);
}

// Merging segment 1 into segment 0 moves its keyframes, points and lines by the transform and nothing else.
TEST(Map, MergeSegmentMovesItsKeyframesAndLandmarks) {
  Map map;
  Frame f = frame_with(2, 1);
  f.T_world_camera.translation() = Eigen::Vector3d(1, 0, 0);
  const Id old_kf = map.add_keyframe(f).id;
  const Id old_point = map.add_point({0, 0, 5});
  map.add_point_observation(old_point, old_kf, 0);
  const Id young_kf = map.add_keyframe(f).id;
  map.keyframe(young_kf)->segment = 1;
  const Id young_point = map.add_point({0, 1, 5});
  const Id young_line = map.add_line(geometry::PlueckerLine::from_points({0, 0, 4}, {1, 0, 4}));
  map.line(young_line)->endpoints = std::make_pair(Eigen::Vector3d(0, 0, 4), Eigen::Vector3d(1, 0, 4));
  map.add_point_observation(young_point, young_kf, 0);
  map.add_line_observation(young_line, young_kf, 0);
  EXPECT_EQ(map.segments(), (std::vector<int>{0, 1}));

  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0, 0, 1);
  map.merge_segment(1, 0, T);
  EXPECT_EQ(map.segments(), (std::vector<int>{0}));
  EXPECT_TRUE(map.keyframe(young_kf)->T_world_camera.isApprox(T * f.T_world_camera, 1e-12));
  EXPECT_TRUE(map.keyframe(old_kf)->T_world_camera.isApprox(f.T_world_camera, 1e-12));
  EXPECT_TRUE(map.point(young_point)->position.isApprox(Eigen::Vector3d(-1, 0, 6), 1e-12));
  EXPECT_TRUE(map.point(old_point)->position.isApprox(Eigen::Vector3d(0, 0, 5), 1e-12));
  // The moved line passes through the moved points of the original and keeps |v| = 1.
  const geometry::PlueckerLine& moved = map.line(young_line)->line;
  EXPECT_NEAR(moved.distance_to(T * Eigen::Vector3d(0, 0, 4)), 0.0, 1e-12);
  EXPECT_NEAR(moved.distance_to(T * Eigen::Vector3d(1, 0, 4)), 0.0, 1e-12);
  EXPECT_NEAR(moved.v.norm(), 1.0, 1e-12);
  EXPECT_TRUE(map.line(young_line)->endpoints->second.isApprox(T * Eigen::Vector3d(1, 0, 4), 1e-12));
}

// Fusing a landmark into another moves its observations; a keyframe that sees both keeps the target's.
TEST(Map, FuseMovesObservationsToTheSurvivor) {
  Map map;
  const Id kf0 = map.add_keyframe(frame_with(3, 2)).id;
  const Id kf1 = map.add_keyframe(frame_with(3, 2)).id;
  const Id keep = map.add_point({0, 0, 5}), drop = map.add_point({0, 0, 5.01});
  map.add_point_observation(keep, kf0, 0);
  map.add_point_observation(drop, kf0, 1);  // kf0 sees both: keeps `keep` at feature 0
  map.add_point_observation(drop, kf1, 2);
  const Id line_keep = map.add_line(geometry::PlueckerLine::from_points({0, 0, 2}, {1, 0, 2}));
  const Id line_drop = map.add_line(geometry::PlueckerLine::from_points({0, 0, 2}, {1, 0, 2}));
  map.add_line_observation(line_drop, kf1, 1);
  map.fuse_point(drop, keep);
  map.fuse_line(line_drop, line_keep);
  EXPECT_EQ(map.point(drop), nullptr);
  EXPECT_EQ(map.line(line_drop), nullptr);
  EXPECT_EQ(map.point(keep)->observations, (std::map<Id, int>{{kf0, 0}, {kf1, 2}}));
  EXPECT_EQ(map.keyframe(kf0)->point_ids[1], kInvalidId);
  EXPECT_EQ(map.keyframe(kf1)->point_ids[2], keep);
  EXPECT_EQ(map.keyframe(kf1)->line_ids[1], line_keep);
  expect_consistent(map);
}

TEST(Map, LoadParams) {
  const MapParams p = load_map_params(YAML::Load("{min_point_observations: 3}"));
  EXPECT_EQ(p.min_point_observations, 3);
  EXPECT_EQ(p.min_line_observations, 2);
  EXPECT_THROW(load_map_params(YAML::Load("{culling_grace_keyframes: many}")), std::runtime_error);
  EXPECT_FALSE(p.mono_points);
  const MapParams mono = load_map_params(YAML::Load("{mono_points: true, mono_point_min_parallax_deg: 2.5}"));
  EXPECT_TRUE(mono.mono_points);
  EXPECT_DOUBLE_EQ(mono.mono_point_min_parallax_deg, 2.5);
  EXPECT_THROW(load_map_params(YAML::Load("{mono_points: sometimes}")), std::runtime_error);
}

}  // namespace
}  // namespace vkvo::map
