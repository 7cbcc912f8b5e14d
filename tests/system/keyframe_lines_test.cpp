// A new keyframe's map lines: from its stereo pair, or from the reference keyframe's view of the same unmapped line
// (exact synthetic observations), with both observations where the reference view agrees; and the 3D points the
// stereo two-point fallback may use.
#include <algorithm>

#include <gtest/gtest.h>

#include "geometry/scene.hpp"  // tests/geometry: test_stereo_camera
#include "system/keyframe_lines.hpp"

namespace vkvo::system {
namespace {

using geometry::PlueckerLine;

// Two keyframes 0.4 m apart sideways (the reference first), both seeing five 3D segments as lines 0-4.
struct TwoKeyframes {
  TwoKeyframes() {
    T_current.translation() = Eigen::Vector3d(0.4, 0.05, 0.1);
    for (const Eigen::Isometry3d& T : {T_reference, T_current}) {
      map::Frame f;
      for (const auto& [A, B] : segments) f.lines.push_back({test::observe_segment(camera, T, A, B), std::nullopt});
      f.reset_associations();
      f.T_world_camera = T;
      (T.isApprox(T_reference) ? reference : current) = map.add_keyframe(f).id;
    }
  }
  PlueckerLine truth(int i) const { return PlueckerLine::from_points(segments[i].first, segments[i].second); }
  // Line i of the current keyframe as the stereo pair would triangulate it (its camera frame).
  std::optional<PlueckerLine> stereo(int i) const { return geometry::transform_line(T_current.inverse(), truth(i)); }

  const geometry::PinholeCamera camera = test::test_stereo_camera().camera;
  const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segments = {{{-1.0, -0.5, 4.0}, {-0.6, 0.6, 4.5}},
                                                                             {{0.2, -0.8, 3.0}, {0.5, 0.7, 3.5}},
                                                                             {{1.0, -0.3, 5.0}, {1.2, 0.8, 5.5}},
                                                                             {{-0.3, 0.2, 2.5}, {0.1, 0.9, 2.8}},
                                                                             {{0.6, -0.9, 6.0}, {0.9, -0.2, 6.5}}};
  const Eigen::Isometry3d T_reference = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_current = Eigen::Isometry3d::Identity();
  map::Map map;
  map::Id reference = map::kInvalidId, current = map::kInvalidId;
  KeyframeLineParams params;
};

TEST(KeyframeLines, StereoAndTwoViewLinesWithBothObservations) {
  TwoKeyframes s;
  // Current line 3 already tracks a map line; the reference's line 2 has one.
  const map::Id tracked = s.map.add_line(s.truth(3));
  s.map.add_line_observation(tracked, s.current, 3);
  const map::Id mapped = s.map.add_line(s.truth(2));
  s.map.add_line_observation(mapped, s.reference, 2);
  StereoLines stereo;
  stereo.lines = {s.stereo(0), std::nullopt, std::nullopt, s.stereo(3), s.stereo(4)};
  // Lines 0-2 paired with their own views; line 4 wrongly with the reference's line 3 (another 3D segment).
  const std::vector<int> partner = {0, 1, 2, -1, 3};

  const NewKeyframeLines out = add_keyframe_lines(s.map, s.current, stereo, s.reference, partner, s.camera, s.params);
  EXPECT_EQ(out.added, 3);  // 0 (stereo), 1 (two views), 4 (stereo); 2's partner is mapped, 3 is tracked
  EXPECT_EQ(out.two_view, 1);
  EXPECT_EQ(out.seen_twice, 2);  // 0 and 1: line 4's partner does not lie on its projection
  const map::KeyFrame& kf = *s.map.keyframe(s.current);
  const map::KeyFrame& ref = *s.map.keyframe(s.reference);
  EXPECT_EQ(kf.line_ids[2], map::kInvalidId);
  EXPECT_EQ(kf.line_ids[3], tracked);
  EXPECT_EQ(s.map.line(tracked)->observations.size(), 1u);
  for (int l : {0, 1}) {
    const map::MapLine* line = s.map.line(kf.line_ids[l]);
    ASSERT_NE(line, nullptr) << "line " << l;
    test::expect_same_line(line->line, s.truth(l), 1e-7);
    EXPECT_EQ(line->observations.size(), 2u) << "line " << l;
    EXPECT_EQ(ref.line_ids[l], kf.line_ids[l]) << "line " << l;
    ASSERT_TRUE(line->endpoints.has_value());
    const auto [E0, E1] = *line->endpoints;  // both views see the whole segment, in either order
    const auto [A, B] = s.segments[l];
    EXPECT_LT(std::min((E0 - A).norm() + (E1 - B).norm(), (E0 - B).norm() + (E1 - A).norm()), 1e-6);
  }
  const map::MapLine* wrong = s.map.line(kf.line_ids[4]);
  ASSERT_NE(wrong, nullptr);
  EXPECT_EQ(wrong->observations.size(), 1u);
  EXPECT_EQ(ref.line_ids[3], map::kInvalidId);
}

// Without a reference (a new map segment) only the stereo lines are made, each seen once.
TEST(KeyframeLines, WithoutAReferenceOnlyStereoLines) {
  TwoKeyframes s;
  StereoLines stereo;
  stereo.lines = {s.stereo(0), std::nullopt, std::nullopt, std::nullopt, s.stereo(4)};
  const NewKeyframeLines out =
      add_keyframe_lines(s.map, s.current, stereo, map::kInvalidId, {0, 1, 2, 3, 4}, s.camera, s.params);
  EXPECT_EQ(out.added, 2);
  EXPECT_EQ(out.two_view, 0);
  EXPECT_EQ(out.seen_twice, 0);
  for (const auto& [id, line] : s.map.lines()) EXPECT_EQ(line.observations.size(), 1u);
  for (map::Id id : s.map.keyframe(s.reference)->line_ids) EXPECT_EQ(id, map::kInvalidId);
}

// The two-point fallback's points: a tracked map point (world frame) wins over the keyframe's stereo point.
TEST(KeyframeLines, KnownPointsPreferTrackedMapPoints) {
  StereoPoints stereo;
  stereo.positions = {Eigen::Vector3d(0, 0, 2), std::nullopt, Eigen::Vector3d(1, 0, 3), std::nullopt};
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();
  T_world_camera.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T_world_camera.translation() = Eigen::Vector3d(1, 2, 3);
  const Eigen::Vector3d world(0.5, 2.5, 7.0);
  const auto known = known_points_in_camera(stereo, {std::nullopt, std::nullopt, world, std::nullopt}, T_world_camera);
  ASSERT_EQ(known.size(), 4u);
  EXPECT_EQ(*known[0], Eigen::Vector3d(0, 0, 2));
  EXPECT_FALSE(known[1]);
  EXPECT_LT((T_world_camera * *known[2] - world).norm(), 1e-12);
  EXPECT_FALSE(known[3]);
}

}  // namespace
}  // namespace vkvo::system
