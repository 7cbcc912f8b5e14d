#pragma once
// Point-to-line association, paper eq. 1: point p belongs to segment l when its distance to l's supporting line
// is below max_distance and it lies within l's x/y extent (with a margin). A point may belong to several lines.
#include <vector>

#include <Eigen/Core>

#include "features/lines/line_params.hpp"
#include "features/lines/line_segment.hpp"

namespace vkvo::features {

struct PointLineAssociation {
  std::vector<std::vector<int>> points_of_line;  // per line: indices of its points, ascending
  std::vector<std::vector<int>> lines_of_point;  // per point: indices of its lines, ascending

  size_t line_count() const { return points_of_line.size(); }
  size_t point_count() const { return lines_of_point.size(); }
};

// The eq. 1 predicate for one point and one segment.
bool point_belongs_to_segment(const Eigen::Vector2f& point, const LineSegment& line, const AssociationParams& params);

// Uses a uniform grid over the points: each line visits only the cells its distance corridor crosses.
PointLineAssociation associate_points_to_lines(const std::vector<Eigen::Vector2f>& points,
                                               const std::vector<LineSegment>& lines, const AssociationParams& params);

// Reference implementation: tests every point against every line (O(points x lines)).
PointLineAssociation associate_points_to_lines_brute_force(const std::vector<Eigen::Vector2f>& points,
                                                           const std::vector<LineSegment>& lines,
                                                           const AssociationParams& params);

}  // namespace vkvo::features
