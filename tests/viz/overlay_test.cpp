// The overlay frame and the top-down picture, drawn from hand-made inputs: the expected colours at the pixels
// where the features and the trajectory were put.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "viz/overlay.hpp"
#include "viz/topdown.hpp"

namespace vkvo::viz {
namespace {

cv::Scalar at(const cv::Mat& image, cv::Point p) {
  const cv::Vec3b v = image.at<cv::Vec3b>(p);
  return {double(v[0]), double(v[1]), double(v[2])};
}

// A 160 x 101 black image (odd height: the overlay rounds it up), one keypoint of each role, a matched line with
// two associated keypoints and an unmatched line.
system::OdometryPose synthetic_pose() {
  auto o = std::make_shared<system::FrameObservations>();
  o->left = cv::Mat(101, 160, CV_8UC1, cv::Scalar(0));
  o->keypoints = {{20, 20}, {60, 20}, {100, 20}, {140, 20}, {40, 70}, {120, 70}};
  o->roles = {system::KeypointRole::inlier,    system::KeypointRole::outlier, system::KeypointRole::new_point,
              system::KeypointRole::unmatched, system::KeypointRole::inlier,  system::KeypointRole::inlier};
  o->lines = {geometry::Segment2d(30, 60, 130, 60), geometry::Segment2d(10, 95, 150, 95)};
  o->line_roles = {system::LineRole::matched, system::LineRole::unmatched};
  o->line_points = {{4, 5}, {}};
  system::OdometryPose pose;
  pose.frame_index = 7;
  pose.timestamp_ns = 1'500'000'000;
  pose.state = system::FrameState::tracked;
  pose.tracked = pose.keyframe = true;
  pose.tracked_points = 3;
  pose.observations = o;
  return pose;
}

TEST(Overlay, ColoursEveryFeatureByItsRole) {
  const cv::Mat overlay = draw_overlay(synthetic_pose(), {160, 101});
  ASSERT_EQ(overlay.type(), CV_8UC3);
  EXPECT_EQ(overlay.size(), cv::Size(160, 102 + kTextBandHeight));  // band added, height rounded up to even
  const cv::Point band(0, kTextBandHeight);
  EXPECT_EQ(at(overlay, band + cv::Point(20, 20)), colour::inlier);
  EXPECT_EQ(at(overlay, band + cv::Point(60, 20)), colour::outlier);
  EXPECT_EQ(at(overlay, band + cv::Point(100, 20)), colour::new_point);
  EXPECT_EQ(at(overlay, band + cv::Point(140, 20)), colour::unmatched);
  // Inliers and outliers are discs of kPointRadius, unmatched keypoints single dots.
  EXPECT_EQ(at(overlay, band + cv::Point(20 + kPointRadius, 20)), colour::inlier);
  EXPECT_EQ(at(overlay, band + cv::Point(140 + kPointRadius, 20)), cv::Scalar(0, 0, 0));
  // Lines in their colours, away from the keypoints on them.
  EXPECT_EQ(at(overlay, band + cv::Point(80, 60)), colour::matched_line);
  EXPECT_EQ(at(overlay, band + cv::Point(80, 95)), colour::unmatched_line);
  // The associated keypoints: in their role's colour, ringed in their line's.
  EXPECT_EQ(at(overlay, band + cv::Point(40, 70)), colour::inlier);
  EXPECT_EQ(at(overlay, band + cv::Point(40, 70 + kAssociationRadius)), colour::matched_line);
  EXPECT_EQ(at(overlay, band + cv::Point(120, 70 - kAssociationRadius)), colour::matched_line);
  // The text band: text, the TRACKED and KEYFRAME tags at its right edge.
  const cv::Mat text = overlay(cv::Rect(0, 0, overlay.cols, kTextBandHeight));
  EXPECT_EQ(at(text, {overlay.cols - 5, 4}), colour::tracked);
  EXPECT_EQ(at(text, {overlay.cols - 5, 25}), colour::keyframe);
  cv::Mat white;
  cv::inRange(text(cv::Rect(0, 0, 40, kTextBandHeight)), cv::Scalar::all(128), cv::Scalar::all(255), white);
  EXPECT_GT(cv::countNonZero(white), 20);
}

TEST(Overlay, APoseWithoutObservationsIsABlackFrameWithItsText) {
  system::OdometryPose pose;
  pose.state = system::FrameState::lost;
  const cv::Mat overlay = draw_overlay(pose, {64, 48});
  EXPECT_EQ(overlay.size(), cv::Size(64, 48 + kTextBandHeight));
  EXPECT_EQ(cv::countNonZero(overlay(cv::Rect(0, kTextBandHeight, 64, 48)).reshape(1)), 0);
  EXPECT_EQ(at(overlay, {overlay.cols - 5, 4}), colour::lost);
  EXPECT_EQ(at(overlay, {overlay.cols - 5, 25}), cv::Scalar(0, 0, 0));  // no keyframe tag
}

TEST(Topdown, DrawsTheTrajectoryPointsAndLinesSeenFromAbove) {
  io::MapGeometry map;
  for (int i = 0; i <= 10; ++i) map.trajectory.emplace_back(0.1 * i, -5.0 * i, 0.2 * i);  // y (down) is dropped
  map.points = {{-1, 0, 3}, {3, 0, 3}, {1, 0, -1}};
  map.lines = {{{-1, 0, 1}, {-1, 0, 2}}};
  const cv::Size size(400, 400);
  const cv::Mat image = draw_topdown(map, size);
  ASSERT_EQ(image.size(), size);
  const auto count = [&](const cv::Scalar& c) {
    cv::Mat mask;
    cv::inRange(image, c, c, mask);
    return cv::countNonZero(mask);
  };
  EXPECT_GT(count(topdown_colour::trajectory), 20);
  EXPECT_GT(count(topdown_colour::start), 20);
  EXPECT_GT(count(topdown_colour::line), 5);
  EXPECT_GE(count(topdown_colour::point), 3);
  // Equal scale, z upwards: the point at x = 3 is right of the one at x = -1, the one at z = -1 below both.
  cv::Mat grey_points;
  cv::inRange(image, topdown_colour::point, topdown_colour::point, grey_points);
  std::vector<cv::Point> found;
  cv::findNonZero(grey_points, found);
  const cv::Rect box = cv::boundingRect(found);
  EXPECT_GT(box.width, 100);
  EXPECT_NEAR(static_cast<double>(box.height) / box.width, 1.0, 0.05);  // 4 m across, 4 m deep
}

}  // namespace
}  // namespace vkvo::viz
