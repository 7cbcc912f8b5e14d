// Debug overlays: line colours, matched lines sharing a colour across the two halves, circle radius by the
// number of lines a point belongs to.
#include "features/lines/line_drawing.hpp"
#include "common/test_support.hpp"

namespace vkvo::features {
namespace {

cv::Vec3b at(const cv::Mat& image, int x, int y) { return image.at<cv::Vec3b>(y, x); }

// Anti-aliased drawing on a black background blends edge pixels to alpha * colour: true when some pixel within
// 1 px of (x, y) is such a blend with alpha >= 0.4 (each channel within 25 of alpha * colour).
bool colour_near(const cv::Mat& image, int x, int y, const cv::Scalar& colour) {
  const cv::Vec3d c(colour[0], colour[1], colour[2]);
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const cv::Vec3b q = at(image, x + dx, y + dy);
      const cv::Vec3d p(q[0], q[1], q[2]);
      const double alpha = p.dot(c) / c.dot(c);
      bool close = alpha >= 0.4;
      for (int k = 0; k < 3; ++k) close = close && std::abs(p[k] - alpha * c[k]) <= 25.0;
      if (close) return true;
    }
  return false;
}

TEST(LineDrawing, DistinctColoursDiffer) {
  for (size_t i = 0; i < 20; ++i)
    for (size_t j = i + 1; j < 20; ++j) EXPECT_NE(distinct_colour(i), distinct_colour(j)) << i << " " << j;
}

TEST(LineDrawing, SingleImageOverlayDrawsLinesAndPointCircles) {
  LineOverlayView view;
  view.image = cv::Mat(100, 200, CV_8UC1, cv::Scalar(0));
  view.lines = {{{10, 20}, {190, 20}}, {{100, 5}, {100, 95}}};
  view.points = {{100, 20}, {50, 20}, {150, 80}};
  PointLineAssociation association;
  association.points_of_line = {{0, 1}, {0}};
  association.lines_of_point = {{0, 1}, {0}, {}};
  view.association = &association;
  const cv::Mat overlay = draw_line_overlay(view);
  ASSERT_EQ(overlay.type(), CV_8UC3);
  EXPECT_TRUE(colour_near(overlay, 150, 20, distinct_colour(0)));  // on line 0, away from points
  EXPECT_TRUE(colour_near(overlay, 100, 60, distinct_colour(1)));  // on line 1
  EXPECT_FALSE(colour_near(overlay, 150, 20, distinct_colour(1)));
  // Point 0 lies on two lines: radius 4 (2 + 2 * (2 - 1)); point 1 on one line: radius 2.
  // Up-left diagonal, 3-5 px from the point and clear of line 0 (rows 19-21): ring of radius 4 only.
  EXPECT_TRUE(colour_near(overlay, 97, 16, distinct_colour(0)));
  EXPECT_FALSE(colour_near(overlay, 47, 16, distinct_colour(0)));
  EXPECT_TRUE(colour_near(overlay, 50, 17, distinct_colour(0)));  // ring of point 1, 2-3 px above
  EXPECT_EQ(at(overlay, 0, 0), cv::Vec3b(0, 0, 0));

  PointLineAssociation wrong;
  wrong.points_of_line = {{}};
  view.association = &wrong;
  EXPECT_THROW(draw_line_overlay(view), std::invalid_argument);
}

TEST(LineDrawing, MatchedLinesShareAColourUnmatchedAreGrey) {
  LineOverlayView a, b;
  a.image = cv::Mat(100, 100, CV_8UC1, cv::Scalar(0));
  b.image = a.image.clone();
  a.lines = {{{10, 10}, {90, 10}}, {{10, 50}, {90, 50}}};
  b.lines = {{{10, 70}, {90, 70}}, {{10, 30}, {90, 30}}};
  const cv::Mat overlay = draw_line_matches(a, b, {1, -1});
  ASSERT_EQ(overlay.cols, 200);
  EXPECT_TRUE(colour_near(overlay, 50, 10, distinct_colour(0)));  // A0 <-> B1 share a colour
  EXPECT_TRUE(colour_near(overlay, 150, 30, distinct_colour(0)));
  EXPECT_TRUE(colour_near(overlay, 50, 50, cv::Scalar::all(140)));  // unmatched: grey
  EXPECT_TRUE(colour_near(overlay, 150, 70, cv::Scalar::all(140)));
  EXPECT_FALSE(colour_near(overlay, 50, 50, distinct_colour(0)));
  EXPECT_THROW(draw_line_matches(a, b, {2, -1}), std::invalid_argument);
  EXPECT_THROW(draw_line_matches(a, b, {0}), std::invalid_argument);
}

}  // namespace
}  // namespace vkvo::features
