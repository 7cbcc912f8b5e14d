// Pluecker / orthonormal lines: round trips, transforms, the projection matrix K_L against brute-force projection
// of 3D points, endpoint trimming, the point a pixel's ray meets.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "geometry/line3d.hpp"
#include "scene.hpp"

namespace vkvo::geometry {
namespace {

// Two random points seen by the camera at the origin.
std::pair<Eigen::Vector3d, Eigen::Vector3d> random_segment(std::mt19937& rng, const PinholeCamera& cam) {
  while (true) {
    const Eigen::Vector3d a = test::random_visible_point(rng, cam, Eigen::Isometry3d::Identity(), 1.0, 8.0);
    const Eigen::Vector3d b = test::random_visible_point(rng, cam, Eigen::Isometry3d::Identity(), 1.0, 8.0);
    if ((a - b).norm() > 0.5) return {a, b};
  }
}

TEST(Line3d, PlueckerFromPointsSatisfiesDefinition) {
  std::mt19937 rng(3);
  const PinholeCamera cam = test::test_stereo_camera().camera;
  for (int i = 0; i < 100; ++i) {
    const auto [X1, X2] = random_segment(rng, cam);
    const PlueckerLine L = PlueckerLine::from_points(X1, X2);
    EXPECT_NEAR(L.v.norm(), 1.0, 1e-12);
    EXPECT_NEAR(L.n.dot(L.v), 0.0, 1e-12);
    // n = X x v for every point of the line.
    const Eigen::Vector3d X = X1 + 0.37 * (X2 - X1);
    EXPECT_LT((X.cross(L.v) - L.n).norm(), 1e-12);
    EXPECT_LT(L.distance_to(X), 1e-12);
    EXPECT_LT(L.distance_to(L.closest_point_to_origin()), 1e-12);
    EXPECT_NEAR(L.closest_point_to_origin().dot(L.v), 0.0, 1e-12);
  }
}

TEST(Line3d, OrthonormalRoundTripAndUpdate) {
  std::mt19937 rng(4);
  const PinholeCamera cam = test::test_stereo_camera().camera;
  for (int i = 0; i < 100; ++i) {
    const auto [X1, X2] = random_segment(rng, cam);
    const PlueckerLine L = PlueckerLine::from_points(X1, X2);
    const OrthonormalLine O = OrthonormalLine::from_pluecker(L);
    EXPECT_LT((O.U.transpose() * O.U - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_NEAR(O.U.determinant(), 1.0, 1e-12);
    EXPECT_LT((O.W.transpose() * O.W - Eigen::Matrix2d::Identity()).norm(), 1e-12);
    const PlueckerLine back = O.to_pluecker();
    EXPECT_LT((back.n - L.n).norm(), 1e-12);
    EXPECT_LT((back.v - L.v).norm(), 1e-12);
    // A scaled Pluecker vector is the same line: same orthonormal form.
    const OrthonormalLine O2 = OrthonormalLine::from_pluecker({3.0 * L.n, 3.0 * L.v});
    EXPECT_LT((O2.U - O.U).norm(), 1e-12);
    EXPECT_LT((O2.W - O.W).norm(), 1e-12);
    // Zero update is the identity; a W update changes only the distance to the origin.
    test::expect_same_line(O.plus(Eigen::Vector4d::Zero()).to_pluecker(), L, 1e-12);
    // (a negative angle grows w1 / w2: the line moves away from the origin and n keeps its sign)
    const PlueckerLine moved = O.plus(Eigen::Vector4d(0, 0, 0, -0.1)).to_pluecker();
    EXPECT_LT((moved.v - L.v).norm(), 1e-12);
    EXPECT_LT((moved.n.normalized() - L.n.normalized()).norm(), 1e-12);
    EXPECT_GT(std::abs(moved.n.norm() - L.n.norm()), 1e-3);
    // Rotating about u1 (the plane normal) keeps the line in its plane through the origin.
    const PlueckerLine in_plane = O.plus(Eigen::Vector4d(0.2, 0, 0, 0)).to_pluecker();
    EXPECT_NEAR(in_plane.v.dot(L.n), 0.0, 1e-12);
  }
}

TEST(Line3d, TransformMatchesTransformingPoints) {
  std::mt19937 rng(5);
  const PinholeCamera cam = test::test_stereo_camera().camera;
  for (int i = 0; i < 50; ++i) {
    const auto [X1, X2] = random_segment(rng, cam);
    const Eigen::Isometry3d T = test::random_pose(rng, 3.0, 1.0);
    const PlueckerLine moved = transform_line(T, PlueckerLine::from_points(X1, X2));
    const PlueckerLine expect = PlueckerLine::from_points(T * X1, T * X2);
    EXPECT_LT((moved.n - expect.n).norm(), 1e-12);
    EXPECT_LT((moved.v - expect.v).norm(), 1e-12);
  }
}

// K_L n must be the image line through the projections of any two points of the 3D line (brute force). fx != fy in
// the test camera, so the swapped diagonal printed in the paper would fail here.
TEST(Line3d, ProjectionMatrixMatchesProjectedEndpoints) {
  std::mt19937 rng(6);
  const PinholeCamera cam = test::test_stereo_camera().camera;
  ASSERT_NE(cam.fx, cam.fy);
  for (int i = 0; i < 100; ++i) {
    const auto [X1, X2] = random_segment(rng, cam);
    const Eigen::Isometry3d T_camera_world = test::random_pose(rng, 0.3, 0.2);
    const PlueckerLine L_world =
        PlueckerLine::from_points(T_camera_world.inverse() * X1, T_camera_world.inverse() * X2);
    const Eigen::Vector3d l = project_line(cam, transform_line(T_camera_world, L_world));
    const Eigen::Vector2d p1 = cam.project(X1), p2 = cam.project(X2);
    const Eigen::Vector3d brute = image_line({p1.x(), p1.y(), p2.x(), p2.y()});
    EXPECT_LT(l.normalized().cross(brute.normalized()).norm(), 1e-9);  // same homogeneous line
    for (double s : {-0.5, 0.0, 0.3, 1.0, 2.0}) {
      const Eigen::Vector3d X = X1 + s * (X2 - X1);
      if (X.z() > 0.1) {
        EXPECT_NEAR(point_line_distance(l, cam.project(X)), 0.0, 1e-8);
      }
    }
  }
  // Closed form, fx = 400, fy = 300, cx = 320, cy = 240: K_L = fx fy K^-T.
  const PinholeCamera c{400, 300, 320, 240, 640, 480};
  const Eigen::Matrix3d expect = 400.0 * 300.0 * c.K().inverse().transpose();
  EXPECT_LT((line_projection_matrix(c) - expect).norm(), 1e-9);
  Eigen::Matrix3d closed;
  closed << 300, 0, 0, 0, 400, 0, -300 * 320, -400 * 240, 400 * 300;
  EXPECT_LT((line_projection_matrix(c) - closed).norm(), 1e-9);
}

TEST(Line3d, TrimRecoversObservedExtent) {
  std::mt19937 rng(8);
  const PinholeCamera cam = test::test_stereo_camera().camera;
  for (int i = 0; i < 30; ++i) {
    const auto [A, B] = random_segment(rng, cam);  // in the first camera = world
    const PlueckerLine L = PlueckerLine::from_points(A, B);
    // Camera 1 sees the middle part [0.2, 0.7]; camera 2 the part [0.1, 0.6]: the union is [0.1, 0.7].
    const Eigen::Isometry3d T2 = test::random_pose(rng, 0.2, 0.05);
    auto seg = [&](const Eigen::Isometry3d& T_world_camera, double s0, double s1) {
      const Eigen::Vector2d a = cam.project(T_world_camera.inverse() * (A + s0 * (B - A)));
      const Eigen::Vector2d b = cam.project(T_world_camera.inverse() * (A + s1 * (B - A)));
      return LineObservation{T_world_camera, Segment2d(a.x(), a.y(), b.x(), b.y())};
    };
    if ((T2.inverse() * A).z() < 0.2 || (T2.inverse() * B).z() < 0.2) continue;
    const auto [E1, E2] = trim_line(L, cam, {seg(Eigen::Isometry3d::Identity(), 0.2, 0.7), seg(T2, 0.6, 0.1)});
    EXPECT_LT((E1 - (A + 0.1 * (B - A))).norm(), 1e-7);
    EXPECT_LT((E2 - (A + 0.7 * (B - A))).norm(), 1e-7);
  }
}

// The ray through the image of a point of the line meets the line at that point, from any pose that sees it; a ray
// along the line's direction meets it nowhere.
TEST(Line3d, PointSeenAtAPixelOfTheLinesImage) {
  std::mt19937 rng(11);
  const PinholeCamera cam = test::test_stereo_camera().camera;
  for (int i = 0; i < 30; ++i) {
    const auto [A, B] = random_segment(rng, cam);
    const PlueckerLine L = PlueckerLine::from_points(A, B);
    const Eigen::Isometry3d T = test::random_pose(rng, 0.2, 0.05);
    const Eigen::Vector3d X = A + 0.3 * (B - A);
    if ((T.inverse() * X).z() < 0.2) continue;
    const auto seen = point_on_line_seen_at(L, cam, T, cam.project(T.inverse() * X));
    ASSERT_TRUE(seen.has_value());
    EXPECT_LT((*seen - X).norm(), 1e-7);
  }
  // The line through the optical axis: the principal point's ray runs along it.
  const PlueckerLine axis = PlueckerLine::from_points({0, 0, 1}, {0, 0, 2});
  EXPECT_FALSE(point_on_line_seen_at(axis, cam, Eigen::Isometry3d::Identity(), {cam.cx, cam.cy}).has_value());
}

// The reprojection error is the larger perpendicular distance of the observed endpoints to the projected line:
// exact segments give 0, endpoints moved off the line by 2 and 5 px along the image normal give 5.
TEST(Line3d, ReprojectionErrorIsTheLargerEndpointDistance) {
  std::mt19937 rng(9);
  const PinholeCamera cam = test::test_stereo_camera().camera;
  for (int i = 0; i < 30; ++i) {
    const auto [A, B] = random_segment(rng, cam);
    const Eigen::Isometry3d T = test::random_pose(rng, 1.0, 0.3);  // the camera at the origin is then T^-1
    const PlueckerLine L_world = PlueckerLine::from_points(T * A, T * B);
    const Eigen::Vector2d a = cam.project(A), b = cam.project(B);
    LineObservation obs{T, Segment2d(a.x(), a.y(), b.x(), b.y())};
    EXPECT_LT(line_reprojection_error(L_world, cam, obs), 1e-6);
    const Eigen::Vector2d d = (b - a).normalized(), normal(-d.y(), d.x());
    const Eigen::Vector2d a2 = a + 2.0 * normal + 7.0 * d, b2 = b - 5.0 * normal;  // sliding along it is free
    obs.segment = Segment2d(a2.x(), a2.y(), b2.x(), b2.y());
    EXPECT_NEAR(line_reprojection_error(L_world, cam, obs), 5.0, 1e-6);
  }
  // A line through the camera centre projects to a point: no distance is defined.
  const PlueckerLine through_centre = PlueckerLine::from_points({0, 0, 1}, {0, 0, 3});
  EXPECT_TRUE(std::isinf(
      line_reprojection_error(through_centre, cam, {Eigen::Isometry3d::Identity(), Segment2d(300, 200, 400, 250)})));
}

}  // namespace
}  // namespace vkvo::geometry
