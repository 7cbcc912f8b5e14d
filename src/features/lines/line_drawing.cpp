#include "features/lines/line_drawing.hpp"

#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace vkvo::features {
namespace {

const cv::Scalar kGrey(140, 140, 140);

cv::Mat to_bgr(const cv::Mat& image) {
  if (image.empty()) throw std::runtime_error("line overlay: empty image");
  cv::Mat bgr;
  if (image.channels() == 1) {
    cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR);
  } else {
    bgr = image.clone();
  }
  return bgr;
}

cv::Point2f to_cv(const Eigen::Vector2f& p, float x_offset) { return {p.x() + x_offset, p.y()}; }

// Draws the lines of `view` with colour line_colour[l] (kGrey = unmatched) and the points associated with
// them. Points on several lines take the colour of their first line; radius 2 + 2 * (line count - 1).
void draw_view(cv::Mat& canvas, const LineOverlayView& view, const std::vector<cv::Scalar>& line_colour,
               float x_offset) {
  constexpr int kShift = 4;  // sub-pixel drawing: coordinates scaled by 2^4
  auto fixed = [&](const Eigen::Vector2f& p) {
    const cv::Point2f q = to_cv(p, x_offset);
    return cv::Point(cvRound(q.x * (1 << kShift)), cvRound(q.y * (1 << kShift)));
  };
  for (size_t l = 0; l < view.lines.size(); ++l) {
    const bool grey = line_colour[l] == kGrey;
    cv::line(canvas, fixed(view.lines[l].p0), fixed(view.lines[l].p1), line_colour[l], grey ? 1 : 2, cv::LINE_AA,
             kShift);
  }
  for (size_t p = 0; p < view.points.size(); ++p) {
    const size_t count = view.association ? view.association->lines_of_point[p].size() : 0;
    if (count == 0) {
      cv::circle(canvas, fixed(view.points[p]), 1 << kShift, kGrey, 1, cv::LINE_AA, kShift);
      continue;
    }
    const cv::Scalar colour = line_colour[view.association->lines_of_point[p].front()];
    const int radius = static_cast<int>(2 + 2 * (count - 1));
    cv::circle(canvas, fixed(view.points[p]), radius << kShift, colour, 1, cv::LINE_AA, kShift);
  }
}

void check_view(const LineOverlayView& view) {
  if (view.association &&
      (view.association->line_count() != view.lines.size() || view.association->point_count() != view.points.size()))
    throw std::invalid_argument("line overlay: association sizes do not match the lines/points given");
}

}  // namespace

cv::Scalar distinct_colour(size_t index) {
  const double hue = std::fmod(index * 0.618033988749895, 1.0) * 180.0;  // OpenCV 8-bit hue range [0, 180)
  cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar(hue, 230, 255)), bgr;
  cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
  const cv::Vec3b c = bgr.at<cv::Vec3b>(0, 0);
  return {double(c[0]), double(c[1]), double(c[2])};
}

cv::Mat draw_line_overlay(const LineOverlayView& view) {
  check_view(view);
  cv::Mat canvas = to_bgr(view.image);
  std::vector<cv::Scalar> colours(view.lines.size());
  for (size_t l = 0; l < colours.size(); ++l) colours[l] = distinct_colour(l);
  draw_view(canvas, view, colours, 0.0f);
  return canvas;
}

cv::Mat draw_line_matches(const LineOverlayView& a, const LineOverlayView& b, const std::vector<int>& matches) {
  check_view(a);
  check_view(b);
  if (matches.size() != a.lines.size())
    throw std::invalid_argument("line overlay: line matches do not cover the lines of image A");
  std::vector<cv::Scalar> colours_a(a.lines.size(), kGrey), colours_b(b.lines.size(), kGrey);
  size_t next = 0;
  for (size_t l = 0; l < matches.size(); ++l) {
    if (matches[l] < 0) continue;
    if (static_cast<size_t>(matches[l]) >= b.lines.size())
      throw std::invalid_argument("line overlay: line match index outside the lines of image B");
    colours_a[l] = colours_b[matches[l]] = distinct_colour(next++);
  }
  const cv::Mat left = to_bgr(a.image), right = to_bgr(b.image);
  cv::Mat canvas(std::max(left.rows, right.rows), left.cols + right.cols, CV_8UC3, cv::Scalar::all(0));
  left.copyTo(canvas(cv::Rect(0, 0, left.cols, left.rows)));
  right.copyTo(canvas(cv::Rect(left.cols, 0, right.cols, right.rows)));
  draw_view(canvas, a, colours_a, 0.0f);
  draw_view(canvas, b, colours_b, static_cast<float>(left.cols));
  return canvas;
}

}  // namespace vkvo::features
