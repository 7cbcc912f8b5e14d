// Point and line triangulation from noiseless synthetic observations (exact recovery), gates, and the degenerate
// line case falling back to two points; a line fitted over noisy points with outliers.
#include <random>

#include <gtest/gtest.h>

#include "geometry/triangulation.hpp"
#include "scene.hpp"

namespace vkvo::geometry {
namespace {

TEST(Triangulation, StereoPointExactAndGated) {
  const StereoCamera stereo = test::test_stereo_camera();
  const TriangulationParams params;
  std::mt19937 rng(11);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p = test::random_visible_point(rng, stereo.camera, Eigen::Isometry3d::Identity(), 0.5, 9.5);
    const auto X = triangulate_stereo_point(stereo, stereo.camera.project(p), stereo.project_right(p), params);
    ASSERT_TRUE(X.has_value());
    EXPECT_LT((*X - p).norm(), 1e-9 * p.norm());
  }
  const Eigen::Vector3d p(0.3, -0.2, 4.0);
  const Eigen::Vector2d l = stereo.camera.project(p), r = stereo.project_right(p);
  EXPECT_FALSE(triangulate_stereo_point(stereo, l, r + Eigen::Vector2d(0, 2.5), params));  // |dy| > 2 px
  EXPECT_TRUE(triangulate_stereo_point(stereo, l, r + Eigen::Vector2d(0, 1.9), params));
  EXPECT_FALSE(triangulate_stereo_point(stereo, l, l, params));  // zero disparity
  const Eigen::Vector3d far(0.1, 0.1, 12.0), near(0.0, 0.0, 0.08);
  EXPECT_FALSE(triangulate_stereo_point(stereo, stereo.camera.project(far), stereo.project_right(far), params));
  EXPECT_FALSE(triangulate_stereo_point(stereo, stereo.camera.project(near), stereo.project_right(near), params));
}

TEST(Triangulation, TwoViewPointExact) {
  const PinholeCamera cam = test::test_stereo_camera().camera;
  std::mt19937 rng(12);
  int checked = 0;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Isometry3d T1 = test::random_pose(rng, 1.0, 0.3);
    const Eigen::Isometry3d T2 = T1 * test::random_pose(rng, 0.5, 0.2);
    const Eigen::Vector3d X = test::random_visible_point(rng, cam, T1, 1.0, 10.0);
    if ((T2.inverse() * X).z() < 0.5) continue;
    const auto Y = triangulate_two_view(cam, T1, cam.project(T1.inverse() * X), T2, cam.project(T2.inverse() * X));
    ASSERT_TRUE(Y.has_value());
    EXPECT_LT((*Y - X).norm(), 1e-7 * X.norm());
    ++checked;
  }
  EXPECT_GT(checked, 100);
  // Pure rotation: rays meet only at the camera centre or at infinity; a point behind is rejected.
  const Eigen::Vector3d X(0.2, 0.1, 3.0);
  EXPECT_FALSE(triangulate_two_view(cam, Eigen::Isometry3d::Identity(), cam.project(X), Eigen::Isometry3d::Identity(),
                                    cam.project(X))
                   .has_value());
}

LineObservation observe(const PinholeCamera& cam, const Eigen::Isometry3d& T_world_camera, const Eigen::Vector3d& A,
                        const Eigen::Vector3d& B) {
  const Eigen::Vector2d a = cam.project(T_world_camera.inverse() * A), b = cam.project(T_world_camera.inverse() * B);
  return {T_world_camera, Segment2d(a.x(), a.y(), b.x(), b.y())};
}

TEST(Triangulation, TwoViewLineFromPlanesExact) {
  const PinholeCamera cam = test::test_stereo_camera().camera;
  const TriangulationParams params;
  std::mt19937 rng(13);
  int checked = 0;
  for (int i = 0; i < 300; ++i) {
    const Eigen::Isometry3d T1 = test::random_pose(rng, 1.0, 0.3);
    const Eigen::Isometry3d T2 = T1 * test::random_pose(rng, 0.6, 0.2);
    const Eigen::Vector3d A = test::random_visible_point(rng, cam, T1, 1.0, 8.0);
    const Eigen::Vector3d B = test::random_visible_point(rng, cam, T1, 1.0, 8.0);
    if ((T2.inverse() * A).z() < 0.5 || (T2.inverse() * B).z() < 0.5 || (A - B).norm() < 0.5) continue;
    const LineObservation a = observe(cam, T1, A, B), b = observe(cam, T2, A, B);
    const auto result = triangulate_line(cam, a, b, std::nullopt, params);
    const auto gated = triangulate_two_view_line(cam, a, b, params);  // these depths all pass its gate
    EXPECT_EQ(gated.has_value(), result.method != LineTriangulationMethod::failed);
    if (result.method == LineTriangulationMethod::failed) continue;  // degenerate geometry, checked below
    EXPECT_EQ(result.method, LineTriangulationMethod::planes);
    test::expect_same_line(result.line, PlueckerLine::from_points(A, B), 1e-7);
    if (gated) test::expect_same_line(*gated, PlueckerLine::from_points(A, B), 1e-7);
    ++checked;
  }
  EXPECT_GT(checked, 200);
}

// triangulate_two_view_line's gates: refused along the motion (one plane twice) and beyond the depth gate of the
// first view (its exact recovery is checked with TwoViewLineFromPlanesExact's scenes).
TEST(Triangulation, TwoViewLineGated) {
  const PinholeCamera cam = test::test_stereo_camera().camera;
  TriangulationParams params;
  params.max_depth = 20.0;
  // The camera moves 0.5 m along the line's own direction: both views back-project to the same plane.
  const Eigen::Vector3d A(-0.5, 0.3, 3.0), B(0.5, 0.3, 4.0);
  Eigen::Isometry3d T2 = Eigen::Isometry3d::Identity();
  T2.translation() = 0.5 * (B - A).normalized();
  const LineObservation first = observe(cam, Eigen::Isometry3d::Identity(), A, B);
  EXPECT_FALSE(triangulate_two_view_line(cam, first, observe(cam, T2, A, B), params));
  // Sideways instead it is found; with the far end beyond max_depth it is refused.
  T2.translation() = Eigen::Vector3d(0.0, 0.5, 0.0);
  ASSERT_TRUE(triangulate_two_view_line(cam, first, observe(cam, T2, A, B), params));
  params.max_depth = 3.5;
  EXPECT_FALSE(triangulate_two_view_line(cam, first, observe(cam, T2, A, B), params));
}

TEST(Triangulation, StereoLineExact) {
  const StereoCamera stereo = test::test_stereo_camera();
  const TriangulationParams params;
  std::mt19937 rng(14);
  int checked = 0;
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d A = test::random_visible_point(rng, stereo.camera, Eigen::Isometry3d::Identity(), 1.0, 6.0);
    const Eigen::Vector3d B = test::random_visible_point(rng, stereo.camera, Eigen::Isometry3d::Identity(), 1.0, 6.0);
    if (std::abs((A - B).normalized().x()) > 0.7) continue;  // nearly horizontal: degenerate for a stereo pair
    const LineObservation l = observe(stereo.camera, Eigen::Isometry3d::Identity(), A, B);
    const LineObservation r = observe(stereo.camera, stereo.T_left_right(), A, B);
    const auto result = triangulate_stereo_line(stereo, l.segment, r.segment, std::nullopt, params);
    if (result.method == LineTriangulationMethod::failed) continue;
    test::expect_same_line(result.line, PlueckerLine::from_points(A, B), 1e-7);
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

// A horizontal line seen by a rectified stereo pair back-projects to the same plane in both cameras: the plane
// method must refuse it and the two-point fallback must be used (and said so).
TEST(Triangulation, DegenerateStereoLineFallsBackToPoints) {
  const StereoCamera stereo = test::test_stereo_camera();
  const TriangulationParams params;
  const Eigen::Vector3d A(-0.8, 0.4, 4.0), B(0.9, 0.4, 4.0);
  const LineObservation l = observe(stereo.camera, Eigen::Isometry3d::Identity(), A, B);
  const LineObservation r = observe(stereo.camera, stereo.T_left_right(), A, B);
  EXPECT_FALSE(triangulate_line_from_planes(stereo.camera, l, r, params.min_line_plane_angle_deg * M_PI / 180));
  const auto none = triangulate_stereo_line(stereo, l.segment, r.segment, std::nullopt, params);
  EXPECT_EQ(none.method, LineTriangulationMethod::failed);
  const Eigen::Vector3d P1 = A + 0.25 * (B - A), P2 = A + 0.8 * (B - A);
  const auto fallback = triangulate_stereo_line(stereo, l.segment, r.segment, std::make_pair(P1, P2), params);
  EXPECT_EQ(fallback.method, LineTriangulationMethod::points);
  EXPECT_STREQ(to_string(fallback.method), "points");
  test::expect_same_line(fallback.line, PlueckerLine::from_points(A, B), 1e-12);
}

// Points on a known line with noise inside their tolerance, plus off-line points (a keypoint associated to the
// line's image but lying on the wall behind it): the fit keeps the line's points and recovers it to the noise.
TEST(Triangulation, LineFittedOverPointsIgnoresPointsOffTheLine) {
  const Eigen::Vector3d A(-0.8, 0.4, 4.0), B(0.9, -0.2, 5.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> along(0.0, 1.0), noise(-0.005, 0.005);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 12; ++i)
    points.push_back(A + along(rng) * (B - A) + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
  for (int i = 0; i < 5; ++i) points.push_back(A + along(rng) * (B - A) + Eigen::Vector3d(0, 0, 0.3 + 0.1 * i));
  const std::vector<double> tolerances(points.size(), 0.02);
  const auto line = fit_line_to_points(points, tolerances, 3);
  ASSERT_TRUE(line);
  const PlueckerLine truth = PlueckerLine::from_points(A, B);
  // Each noisy point is within 0.0087 m (the half-diagonal of the noise box) of the line: the fit's ends too.
  EXPECT_LT(line->distance_to(A), 0.01);
  EXPECT_LT(line->distance_to(B), 0.01);
  EXPECT_GT(std::abs(line->direction().dot(truth.direction())), std::cos(0.01));
  // Exactly on the line: exact. Too few agreeing points, or all at one place: no line.
  EXPECT_LT(fit_line_to_points({A, B, 0.5 * (A + B)}, {1e-9, 1e-9, 1e-9}, 3)->distance_to(0.3 * A + 0.7 * B), 1e-9);
  EXPECT_FALSE(fit_line_to_points({A, B, A + Eigen::Vector3d(0, 1, 0)}, {0.01, 0.01, 0.01}, 3));
  EXPECT_FALSE(fit_line_to_points({A, A, A}, {0.01, 0.01, 0.01}, 2));
  EXPECT_FALSE(fit_line_to_points({}, {}, 2));
}

TEST(Triangulation, LoadParams) {
  const YAML::Node node = YAML::Load("{max_y_diff: 3.5, max_depth: 40}");
  const TriangulationParams p = load_triangulation_params(node);
  EXPECT_EQ(p.max_y_diff, 3.5);
  EXPECT_EQ(p.max_depth, 40.0);
  EXPECT_EQ(p.min_depth, 0.1);
  EXPECT_EQ(p.line_fit_min_points, 3);
  EXPECT_EQ(load_triangulation_params(YAML::Load("{line_fit_min_points: 4}")).line_fit_min_points, 4);
  EXPECT_THROW(load_triangulation_params(YAML::Load("{min_depth: [1, 2]}")), std::runtime_error);
}

}  // namespace
}  // namespace vkvo::geometry
