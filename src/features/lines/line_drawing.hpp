#pragma once
// Debug overlays for the line pipeline: segments in distinct colours, associated points as circles whose radius
// grows with the number of lines they belong to, matched lines in the same colour across two images.
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "features/lines/line_segment.hpp"
#include "features/lines/point_line_association.hpp"

namespace vkvo::features {

struct LineOverlayView {
  cv::Mat image;  // gray or BGR, 8-bit
  std::vector<LineSegment> lines;
  std::vector<Eigen::Vector2f> points;                // may be empty
  const PointLineAssociation* association = nullptr;  // optional; sizes must match lines/points
};

// A well-spread BGR colour for index i (golden-ratio hue steps).
cv::Scalar distinct_colour(size_t index);

// One image: every line in its own colour, its associated points as circles of that colour.
cv::Mat draw_line_overlay(const LineOverlayView& view);

// Two images side by side (A left, B right). Matched lines share a colour; unmatched lines are grey.
// `line_matches_a_to_b` is the output of match_lines (size = lines of A).
cv::Mat draw_line_matches(const LineOverlayView& a, const LineOverlayView& b,
                          const std::vector<int>& line_matches_a_to_b);

}  // namespace vkvo::features
