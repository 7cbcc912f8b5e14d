#include "viz/overlay.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

namespace vkvo::viz {
namespace {

cv::Point pixel(const Eigen::Vector2d& p) {
  return {static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y()))};
}

const cv::Scalar& role_colour(system::KeypointRole role) {
  switch (role) {
    case system::KeypointRole::inlier: return colour::inlier;
    case system::KeypointRole::outlier: return colour::outlier;
    case system::KeypointRole::new_point: return colour::new_point;
    case system::KeypointRole::unmatched: break;
  }
  return colour::unmatched;
}

// Lines, the rings of their associated keypoints, then the keypoints on top (unmatched first, so that the
// tracked ones stay visible where they crowd).
void draw_features(cv::Mat& image, const system::FrameObservations& o) {
  for (std::size_t l = 0; l < o.lines.size(); ++l) {
    const bool matched = l < o.line_roles.size() && o.line_roles[l] == system::LineRole::matched;
    const cv::Scalar& c = matched ? colour::matched_line : colour::unmatched_line;
    const geometry::Segment2d& s = o.lines[l];
    cv::line(image, pixel(s.head<2>()), pixel(s.tail<2>()), c, matched ? 2 : 1);
    if (l < o.line_points.size())
      for (const int k : o.line_points[l])
        if (k >= 0 && static_cast<std::size_t>(k) < o.keypoints.size())
          cv::circle(image, pixel(o.keypoints[static_cast<std::size_t>(k)]), kAssociationRadius, c, 1);
  }
  for (const bool tracked_pass : {false, true})
    for (std::size_t i = 0; i < o.keypoints.size() && i < o.roles.size(); ++i) {
      const bool unmatched = o.roles[i] == system::KeypointRole::unmatched;
      if (unmatched == tracked_pass) continue;
      cv::circle(image, pixel(o.keypoints[i]), unmatched ? 1 : kPointRadius, role_colour(o.roles[i]), cv::FILLED);
    }
}

// A filled box with black text, its right edge at `right`, its top at `top`.
void draw_tag(cv::Mat& band, const std::string& text, const cv::Scalar& fill, int right, int top) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, 0.45, 1, &baseline);
  const cv::Rect box(right - size.width - 8, top, size.width + 8, 19);
  cv::rectangle(band, box, fill, cv::FILLED);
  cv::putText(band, text, {box.x + 4, box.y + 14}, cv::FONT_HERSHEY_SIMPLEX, 0.45, {0, 0, 0}, 1, cv::LINE_AA);
}

const cv::Scalar& state_colour(system::FrameState state) {
  switch (state) {
    case system::FrameState::tracked: return colour::tracked;
    case system::FrameState::relocalised: return colour::relocalised;
    case system::FrameState::lost: break;
  }
  return colour::lost;
}

// Line 1: index, time, inliers, segment; line 2: the tracker's note; at the right, the state and keyframe tags.
void draw_text_band(cv::Mat& band, const system::OdometryPose& pose) {
  const cv::Scalar white(255, 255, 255);
  cv::putText(
      band,
      fmt::format("frame {}  t {:.3f} s  inliers {} points / {} lines  segment {}", pose.frame_index,
                  static_cast<double>(pose.timestamp_ns) * 1e-9, pose.tracked_points, pose.tracked_lines, pose.segment),
      {6, 17}, cv::FONT_HERSHEY_SIMPLEX, 0.5, white, 1, cv::LINE_AA);
  if (!pose.note.empty()) cv::putText(band, pose.note, {6, 37}, cv::FONT_HERSHEY_SIMPLEX, 0.45, white, 1, cv::LINE_AA);
  std::string state = system::to_string(pose.state);
  std::transform(state.begin(), state.end(), state.begin(), [](unsigned char c) { return std::toupper(c); });
  draw_tag(band, state, state_colour(pose.state), band.cols - 3, 2);
  if (pose.keyframe) draw_tag(band, "KEYFRAME", colour::keyframe, band.cols - 3, 23);
}

}  // namespace

cv::Size overlay_size(cv::Size image_size) {
  const auto even = [](int n) { return n + (n & 1); };
  return {even(image_size.width), even(image_size.height + kTextBandHeight)};
}

cv::Mat draw_overlay(const system::OdometryPose& pose, cv::Size image_size) {
  const system::FrameObservations* o = pose.observations.get();
  if (o && !o->left.empty()) image_size = o->left.size();
  cv::Mat canvas(overlay_size(image_size), CV_8UC3, cv::Scalar(0, 0, 0));
  cv::Mat image = canvas(cv::Rect(0, kTextBandHeight, image_size.width, image_size.height));
  if (o && !o->left.empty()) {
    if (o->left.channels() == 1)
      cv::cvtColor(o->left, image, cv::COLOR_GRAY2BGR);
    else
      o->left.copyTo(image);
    draw_features(image, *o);
  }
  cv::Mat band = canvas(cv::Rect(0, 0, canvas.cols, kTextBandHeight));
  draw_text_band(band, pose);
  return canvas;
}

}  // namespace vkvo::viz
