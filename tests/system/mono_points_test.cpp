// Mono multi-view map points: exact synthetic observations of known 3D points from two keyframes; only keypoints
// mapped on neither side and without a stereo match are triangulated, and only with enough parallax and a
// consistent reprojection in both views.
#include <gtest/gtest.h>

#include "geometry/scene.hpp"  // tests/geometry: test_stereo_camera
#include "system/mono_points.hpp"

namespace vkvo::system {
namespace {

TEST(MonoPoints, TriangulatesUnmappedMatchesWithParallaxAndBothObservations) {
  const geometry::PinholeCamera camera = test::test_stereo_camera().camera;
  Eigen::Isometry3d T_current = Eigen::Isometry3d::Identity();
  T_current.translation() = Eigen::Vector3d(0.4, 0.05, 0.1);
  T_current.linear() = Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY()).toRotationMatrix();
  // Keypoint k of both keyframes sees point k. Point 4 is 200 m away: 0.4 m of baseline gives it about 0.1 deg.
  const std::vector<Eigen::Vector3d> points = {{0.3, 0.2, 4.0},   {-0.5, 0.1, 3.0}, {0.6, -0.4, 5.0}, {-0.2, -0.3, 3.5},
                                               {5.0, 3.0, 200.0}, {0.9, 0.5, 6.0},  {-0.9, 0.6, 2.5}};
  map::Map map;
  map::Id reference = map::kInvalidId, current = map::kInvalidId;
  for (const Eigen::Isometry3d& T : {Eigen::Isometry3d::Identity(), T_current}) {
    map::Frame f;
    f.T_world_camera = T;
    for (const auto& X : points) f.keypoints.push_back(camera.project(T.inverse() * X));
    f.reset_associations();
    (reference == map::kInvalidId ? reference : current) = map.add_keyframe(f).id;
  }
  const map::Id tracked = map.add_point(points[1]);  // keypoint 1 of the new keyframe tracks a map point
  map.add_point_observation(tracked, current, 1);
  map.keyframe(current)->right_x[2] = 100.0;        // keypoint 2 has a stereo match: the stereo pair maps it
  const map::Id mapped = map.add_point(points[3]);  // the reference's keypoint 3 is mapped already
  map.add_point_observation(mapped, reference, 3);
  // Keypoint 5 is wrongly matched to the reference's keypoint 6 (another point).
  const std::vector<int> partner = {0, 1, 2, 3, 4, 6, -1};

  const NewMonoPoints out = add_mono_points(map, current, reference, partner, camera, MonoPointParams{});
  EXPECT_EQ(out.candidates, 3);  // 0, 4, 5
  EXPECT_EQ(out.added, 1);       // 4 lacks parallax, 5's two rays disagree
  const map::Id id = map.keyframe(current)->point_ids[0];
  ASSERT_NE(id, map::kInvalidId);
  const map::MapPoint& p = *map.point(id);
  EXPECT_LT((p.position - points[0]).norm(), 1e-9);  // exact observations: DLT is exact up to rounding
  EXPECT_EQ(p.observations.size(), 2u);
  EXPECT_EQ(p.observations.at(reference), 0);
  EXPECT_EQ(map.keyframe(reference)->point_ids[0], id);
  for (int k : {4, 5}) EXPECT_EQ(map.keyframe(current)->point_ids[k], map::kInvalidId) << "keypoint " << k;
  EXPECT_EQ(map.keyframe(current)->point_ids[2], map::kInvalidId);
  EXPECT_EQ(map.keyframe(current)->point_ids[1], tracked);
}

TEST(MonoPoints, NoisyViewsPassTheGateAndWrongPosesDoNot) {
  // 0.5 px of error per view stays within the 1.96 px gate; a pose off by 5 cm sideways at 3 m (about 8 px) does not.
  const geometry::PinholeCamera camera = test::test_stereo_camera().camera;
  Eigen::Isometry3d T_current = Eigen::Isometry3d::Identity();
  T_current.translation() = Eigen::Vector3d(0.3, 0.0, 0.0);
  const Eigen::Vector3d X(0.2, -0.1, 3.0);
  for (const double pose_error : {0.0, 0.05}) {
    map::Map map;
    map::Frame f;
    f.keypoints = {camera.project(X) + Eigen::Vector2d(0.5, 0.0)};
    f.reset_associations();
    const map::Id reference = map.add_keyframe(f).id;
    f.T_world_camera = T_current;
    f.keypoints = {camera.project(T_current.inverse() * X) + Eigen::Vector2d(0.0, -0.5)};
    f.T_world_camera.translation().y() += pose_error;
    const map::Id current = map.add_keyframe(f).id;
    const NewMonoPoints out = add_mono_points(map, current, reference, {0}, camera, MonoPointParams{});
    EXPECT_EQ(out.candidates, 1);
    EXPECT_EQ(out.added, pose_error == 0.0 ? 1 : 0) << "pose error " << pose_error;
    if (out.added == 1) {
      EXPECT_LT((map.point(map.keyframe(current)->point_ids[0])->position - X).norm(), 0.05);
    }
  }
}

}  // namespace
}  // namespace vkvo::system
