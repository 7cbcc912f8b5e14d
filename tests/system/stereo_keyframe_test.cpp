// The stereo half of keyframe creation on exact synthetic observations: stereo points and their gates, known
// positions preferring tracked map points, and stereo lines from planes, from two points when the planes are
// degenerate or the line has no right partner, and none when neither is possible; lines without point support paired
// by their rendered images.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "features/lines/line_matching.hpp"
#include "features/lines/point_line_association.hpp"
#include "geometry/scene.hpp"  // tests/geometry: test_stereo_camera
#include "system/stereo_keyframe.hpp"

namespace vkvo::system {
namespace {

using geometry::PlueckerLine;

Eigen::Vector2f to_float(const Eigen::Vector2d& pixel) { return pixel.cast<float>(); }

// Keypoints with exact projections; match i of the left image is keypoint i of the right one.
struct StereoKeypoints {
  void add(const geometry::StereoCamera& stereo, const Eigen::Vector3d& p_left) {
    truth.push_back(p_left);
    left.keypoints.push_back(to_float(stereo.camera.project(p_left)));
    right.keypoints.push_back(to_float(stereo.project_right(p_left)));
    matches.matches0.push_back(static_cast<int>(matches.matches0.size()));
  }
  std::vector<Eigen::Vector3d> truth;  // left camera frame
  features::PointFeatures left, right;
  features::PointMatches matches;
};

// 2.5e-5 px of float rounding at 752 px moves a point at 6 m by about 2e-5 m along the ray.
constexpr double kPointTolerance = 1e-4;  // [m]

TEST(StereoKeyframe, StereoPointsTriangulateTheMatchesThatPassTheGates) {
  const geometry::StereoCamera stereo = test::test_stereo_camera();
  StereoKeypoints kp;
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(-0.8, -0.4, 2.0), Eigen::Vector3d(0.3, 0.2, 4.5), Eigen::Vector3d(1.1, 0.6, 6.0),
        Eigen::Vector3d(0.0, 0.0, 3.0), Eigen::Vector3d(-0.2, 0.5, 2.5)})
    kp.add(stereo, p);
  kp.right.keypoints[2].y() += 3.0f;                            // 3 px off the row: beyond max_y_diff = 2
  kp.right.keypoints[3].x() = kp.left.keypoints[3].x() + 1.0f;  // negative disparity
  kp.matches.matches0[4] = -1;                                  // unmatched
  const geometry::TriangulationParams params;

  const StereoPoints out = triangulate_stereo_points(stereo, kp.left, kp.right, kp.matches, params);
  ASSERT_EQ(out.positions.size(), 5u);
  ASSERT_EQ(out.right_x.size(), 5u);
  EXPECT_EQ(out.count, 2);
  for (int i : {0, 1}) {
    ASSERT_TRUE(out.positions[i]) << "keypoint " << i;
    EXPECT_LT((*out.positions[i] - kp.truth[i]).norm(), kPointTolerance) << "keypoint " << i;
    EXPECT_DOUBLE_EQ(out.right_x[i], kp.right.keypoints[i].x());
  }
  for (int i : {2, 3, 4}) {
    EXPECT_FALSE(out.positions[i]) << "keypoint " << i;
    EXPECT_EQ(out.right_x[i], -1.0) << "keypoint " << i;
  }

  geometry::TriangulationParams near_only;
  near_only.max_depth = 4.0;  // the depth gate drops keypoints 1 (4.5 m) and 2
  EXPECT_EQ(triangulate_stereo_points(stereo, kp.left, kp.right, kp.matches, near_only).count, 1);
}

TEST(StereoKeyframe, KnownPointsPreferTrackedMapPointsInTheCameraFrame) {
  StereoPoints stereo;
  stereo.positions = {Eigen::Vector3d(0.1, 0.2, 3.0), std::nullopt, Eigen::Vector3d(-0.5, 0.0, 5.0), std::nullopt};
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();
  T_world_camera.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()).toRotationMatrix();
  T_world_camera.translation() = Eigen::Vector3d(2.0, -1.0, 0.5);
  const Eigen::Vector3d refined_camera(0.12, 0.21, 3.05), tracked_only_camera(0.4, -0.3, 2.2);
  // Keypoint 0 tracks a map point refined by bundle adjustment; keypoint 1 tracks one without a stereo match.
  const std::vector<std::optional<Eigen::Vector3d>> tracked_world = {
      T_world_camera * refined_camera, T_world_camera * tracked_only_camera, std::nullopt};

  const auto known = known_points_in_camera(stereo, tracked_world, T_world_camera);
  ASSERT_EQ(known.size(), 4u);
  ASSERT_TRUE(known[0] && known[1] && known[2]);
  EXPECT_LT((*known[0] - refined_camera).norm(), 1e-12);
  EXPECT_LT((*known[1] - tracked_only_camera).norm(), 1e-12);
  EXPECT_EQ(*known[2], *stereo.positions[2]);
  EXPECT_FALSE(known[3]);
}

TEST(StereoKeyframe, StereoLinesFromPlanesOrFromTwoKnownPoints) {
  const geometry::StereoCamera stereo = test::test_stereo_camera();
  // Left camera frame. Line 3 is parallel to the baseline: its two back-projected planes coincide.
  const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segments = {
      {{-1.0, -0.6, 3.0}, {-0.7, 0.5, 3.5}},  // 0: planes
      {{0.4, -0.7, 4.0}, {0.7, 0.4, 4.6}},    // 1: planes
      {{1.0, -0.5, 5.0}, {1.3, 0.5, 5.5}},    // 2: no right line: two points
      {{-0.8, 0.8, 3.0}, {0.4, 0.8, 3.0}},    // 3: degenerate planes: two points
      {{-0.4, -0.8, 2.5}, {0.0, -0.3, 2.7}},  // 4: one stereo match only: nothing
  };
  constexpr int kPointsPerLine = 6;
  StereoKeypoints kp;
  std::vector<features::LineSegment> left_lines, right_lines;
  for (const auto& [A, B] : segments) {
    left_lines.push_back({to_float(stereo.camera.project(A)), to_float(stereo.camera.project(B))});
    right_lines.push_back({to_float(stereo.project_right(A)), to_float(stereo.project_right(B))});
    for (int k = 1; k <= kPointsPerLine; ++k) kp.add(stereo, A + (B - A) * k / (kPointsPerLine + 1.0));
  }
  right_lines.erase(right_lines.begin() + 2);  // right lines are now 0, 1, 3, 4 at indices 0-3
  for (int k = 1; k < kPointsPerLine; ++k) kp.matches.matches0[4 * kPointsPerLine + k] = -1;

  const features::AssociationParams association_params;
  const auto left_association = features::associate_points_to_lines(kp.left.keypoints, left_lines, association_params);
  const auto right_association =
      features::associate_points_to_lines(kp.right.keypoints, right_lines, association_params);
  for (std::size_t l = 0; l < segments.size(); ++l)  // the scene's lines are far enough apart to own their points
    ASSERT_EQ(left_association.points_of_line[l].size(), static_cast<std::size_t>(kPointsPerLine)) << "line " << l;

  for (const bool fit : {false, true}) {
    SCOPED_TRACE(fit ? "line fit over points" : "planes, then two points");
    geometry::TriangulationParams params;
    params.line_fit_min_points = fit ? 3 : 0;
    const StereoPoints stereo_points = triangulate_stereo_points(stereo, kp.left, kp.right, kp.matches, params);
    ASSERT_EQ(stereo_points.count, 4 * kPointsPerLine + 1);
    const auto known = known_points_in_camera(stereo_points, {}, Eigen::Isometry3d::Identity());

    const std::vector<int> partner =
        features::match_lines(left_association, right_association, kp.matches.matches0, features::LineMatchParams{});
    const StereoLines out =
        triangulate_stereo_lines(stereo, {left_lines, left_association}, {right_lines, right_association},
                                 {kp.left.keypoints, known}, partner, params);
    ASSERT_EQ(out.lines.size(), segments.size());
    ASSERT_EQ(out.right.size(), segments.size());
    // Fitted over their stereo points (the default), every line with three or more of them; the planes otherwise.
    EXPECT_EQ(out.planes, fit ? 0 : 2);
    EXPECT_EQ(out.points, fit ? 4 : 2);
    const int right_index_of[] = {0, 1, -1, 2, 3};
    for (int l : {0, 1, 3}) {
      ASSERT_TRUE(out.right[l]) << "line " << l;
      EXPECT_EQ(*out.right[l], to_segment(right_lines[right_index_of[l]]));
    }
    for (int l : {2, 4}) EXPECT_FALSE(out.right[l]) << "line " << l;
    for (int l : {0, 1, 2, 3}) {
      ASSERT_TRUE(out.lines[l]) << "line " << l;
      test::expect_same_line(*out.lines[l], PlueckerLine::from_points(segments[l].first, segments[l].second), 1e-3);
    }
    EXPECT_FALSE(out.lines[4]);
  }
}

TEST(StereoKeyframe, LinesWithoutPointSupportArePairedByTheirImages) {
  const geometry::StereoCamera stereo = test::test_stereo_camera();
  // Left camera frame; no keypoints at all, as in the dark. Line 2 is parallel to the baseline.
  const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segments = {
      {{-1.0, -0.6, 3.0}, {-0.9, 0.5, 3.5}},
      {{0.4, -0.7, 4.0}, {0.5, 0.4, 4.6}},
      {{-0.8, 0.8, 3.0}, {0.4, 0.8, 3.0}},
  };
  const cv::Size size(stereo.camera.width, stereo.camera.height);
  cv::Mat left_image(size, CV_8UC1, cv::Scalar(120)), right_image(size, CV_8UC1, cv::Scalar(120));
  const int grey[] = {230, 10, 230};  // a bright and a dark ridge: otherwise each line would fit the other's image
  std::vector<features::LineSegment> left_lines, right_lines;
  const auto to_cv = [](const Eigen::Vector2d& p) { return cv::Point2d(p.x(), p.y()); };
  for (std::size_t l = 0; l < segments.size(); ++l) {
    const auto& [A, B] = segments[l];
    left_lines.push_back({to_float(stereo.camera.project(A)), to_float(stereo.camera.project(B))});
    right_lines.push_back({to_float(stereo.project_right(A)), to_float(stereo.project_right(B))});
    cv::line(left_image, to_cv(stereo.camera.project(A)), to_cv(stereo.camera.project(B)), grey[l], 3, cv::LINE_AA);
    cv::line(right_image, to_cv(stereo.project_right(A)), to_cv(stereo.project_right(B)), grey[l], 3, cv::LINE_AA);
  }
  std::reverse(right_lines.begin(), right_lines.end());
  const features::PointLineAssociation no_points{std::vector<std::vector<int>>(3), {}};
  const std::vector<int> no_matches;
  const std::vector<std::optional<Eigen::Vector3d>> no_positions;
  const std::vector<Eigen::Vector2f> no_pixels;
  const geometry::TriangulationParams gates;

  features::LinePipelineParams params;
  for (const bool by_appearance : {false, true}) {
    SCOPED_TRACE(by_appearance ? "by appearance" : "through point matches only");
    params.stereo_matching.by_appearance = by_appearance;
    const std::vector<int> partner = match_stereo_lines(stereo, {left_lines, no_points}, {right_lines, no_points},
                                                        {left_image, right_image}, no_matches, params, gates);
    const std::vector<int> expected = by_appearance ? std::vector<int>{2, 1, -1} : std::vector<int>{-1, -1, -1};
    EXPECT_EQ(partner, expected);
    const StereoLines out = triangulate_stereo_lines(stereo, {left_lines, no_points}, {right_lines, no_points},
                                                     {no_pixels, no_positions}, partner, gates);
    EXPECT_EQ(out.planes, by_appearance ? 2 : 0);
    EXPECT_EQ(out.points, 0);
    for (int l : {0, 1}) {
      ASSERT_EQ(out.lines[l].has_value(), by_appearance) << "line " << l;
      // The drawn lines' images are exact to float rounding: the planes meet on the 3D line.
      if (by_appearance)
        test::expect_same_line(*out.lines[l], PlueckerLine::from_points(segments[l].first, segments[l].second), 1e-3);
    }
    EXPECT_FALSE(out.lines[2]);
  }
}

}  // namespace
}  // namespace vkvo::system
