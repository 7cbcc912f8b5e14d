#include "features/lines/point_line_association.hpp"

#include <algorithm>
#include <cmath>

namespace vkvo::features {
namespace {

// Points bucketed into square cells, stored compressed: the points of cell c are
// point_ids[cell_begin[c] .. cell_begin[c + 1]).
struct PointGrid {
  Eigen::Vector2f origin;
  float cell_size = 1.0f;
  int cols = 0, rows = 0;
  std::vector<int> cell_begin;
  std::vector<int> point_ids;

  PointGrid(const std::vector<Eigen::Vector2f>& points, float cell) : cell_size(cell) {
    Eigen::Vector2f lo = points.front(), hi = points.front();
    for (const auto& p : points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    origin = lo;
    cols = static_cast<int>((hi.x() - lo.x()) / cell_size) + 1;
    rows = static_cast<int>((hi.y() - lo.y()) / cell_size) + 1;
    std::vector<int> cell_of_point(points.size());
    cell_begin.assign(static_cast<size_t>(cols) * rows + 1, 0);
    for (size_t i = 0; i < points.size(); ++i) {
      const int cx = std::min(cols - 1, static_cast<int>((points[i].x() - origin.x()) / cell_size));
      const int cy = std::min(rows - 1, static_cast<int>((points[i].y() - origin.y()) / cell_size));
      cell_of_point[i] = cy * cols + cx;
      ++cell_begin[cell_of_point[i] + 1];
    }
    for (size_t c = 1; c < cell_begin.size(); ++c) cell_begin[c] += cell_begin[c - 1];
    point_ids.resize(points.size());
    std::vector<int> fill(cell_begin.begin(), cell_begin.end() - 1);
    for (size_t i = 0; i < points.size(); ++i) point_ids[fill[cell_of_point[i]]++] = static_cast<int>(i);
  }

  // Cell index range [lo, hi] covering the coordinate interval [a, b] on one axis, clamped to the grid.
  static bool cell_range(float a, float b, float origin, float cell, int count, int& lo, int& hi) {
    lo = std::max(0, static_cast<int>(std::floor((a - origin) / cell)));
    hi = std::min(count - 1, static_cast<int>(std::floor((b - origin) / cell)));
    return lo <= hi;
  }
};

// A segment's supporting line and its extent grown by the margin, computed once per line.
struct PreparedSegment {
  Eigen::Vector3f abc = Eigen::Vector3f::Zero();
  float x_min = 0, x_max = 0, y_min = 0, y_max = 0;
  bool valid = false;  // false for a degenerate (zero-length) segment: no supporting line

  PreparedSegment(const LineSegment& line, float margin) {
    valid = line.length() > 0.0f;
    if (!valid) return;
    abc = line.coefficients();
    x_min = std::min(line.p0.x(), line.p1.x()) - margin;
    x_max = std::max(line.p0.x(), line.p1.x()) + margin;
    y_min = std::min(line.p0.y(), line.p1.y()) - margin;
    y_max = std::max(line.p0.y(), line.p1.y()) + margin;
  }

  bool contains(const Eigen::Vector2f& p, const AssociationParams& params) const {
    if (!valid || !(std::abs(abc.x() * p.x() + abc.y() * p.y() + abc.z()) < params.max_distance)) return false;
    const bool in_x = p.x() >= x_min && p.x() <= x_max;
    const bool in_y = p.y() >= y_min && p.y() <= y_max;
    return params.require_both_extents ? (in_x && in_y) : (in_x || in_y);
  }
};

// Fills lines_of_point from points_of_line (both ascending as the lines are visited in order).
void fill_lines_of_point(PointLineAssociation& association) {
  for (size_t l = 0; l < association.points_of_line.size(); ++l)
    for (int p : association.points_of_line[l]) association.lines_of_point[p].push_back(static_cast<int>(l));
}

}  // namespace

bool point_belongs_to_segment(const Eigen::Vector2f& point, const LineSegment& line, const AssociationParams& params) {
  return PreparedSegment(line, params.extent_margin).contains(point, params);
}

PointLineAssociation associate_points_to_lines_brute_force(const std::vector<Eigen::Vector2f>& points,
                                                           const std::vector<LineSegment>& lines,
                                                           const AssociationParams& params) {
  PointLineAssociation association;
  association.points_of_line.resize(lines.size());
  association.lines_of_point.resize(points.size());
  for (size_t l = 0; l < lines.size(); ++l) {
    const PreparedSegment segment(lines[l], params.extent_margin);
    for (size_t p = 0; p < points.size(); ++p)
      if (segment.contains(points[p], params)) association.points_of_line[l].push_back(static_cast<int>(p));
  }
  fill_lines_of_point(association);
  return association;
}

PointLineAssociation associate_points_to_lines(const std::vector<Eigen::Vector2f>& points,
                                               const std::vector<LineSegment>& lines, const AssociationParams& params) {
  PointLineAssociation association;
  association.points_of_line.resize(lines.size());
  association.lines_of_point.resize(points.size());
  if (points.empty() || lines.empty()) return association;

  Eigen::Vector2f lo = points.front(), hi = points.front();
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Eigen::Vector2f cells = (hi - lo) / params.grid_cell_size;
  if (!(cells.x() * cells.y() < 4.0f * 1024 * 1024))  // absurd spread (or NaN): a grid would not pay
    return associate_points_to_lines_brute_force(points, lines, params);

  const PointGrid grid(points, params.grid_cell_size);
  const float cell = grid.cell_size;
  // A cell can hold a point within max_distance of the line only if its centre is within this distance.
  const float corridor = params.max_distance + 0.5f * std::sqrt(2.0f) * cell;
  const float grid_max_x = grid.origin.x() + grid.cols * cell;
  const float grid_max_y = grid.origin.y() + grid.rows * cell;

  for (size_t l = 0; l < lines.size(); ++l) {
    const LineSegment& line = lines[l];
    const PreparedSegment segment(line, params.extent_margin);
    if (!segment.valid) continue;
    const Eigen::Vector3f& abc = segment.abc;
    // Search window: the segment's box grown by margin (and by the corridor) when both extents are required;
    // with the paper's "or" rule a point can lie anywhere along the supporting line.
    float x0 = grid.origin.x(), x1 = grid_max_x, y0 = grid.origin.y(), y1 = grid_max_y;
    if (params.require_both_extents) {
      x0 = segment.x_min;
      x1 = segment.x_max;
      y0 = segment.y_min;
      y1 = segment.y_max;
    }
    int cx0, cx1, cy0, cy1;
    if (!PointGrid::cell_range(x0, x1, grid.origin.x(), cell, grid.cols, cx0, cx1) ||
        !PointGrid::cell_range(y0, y1, grid.origin.y(), cell, grid.rows, cy0, cy1))
      continue;
    auto& members = association.points_of_line[l];
    for (int cy = cy0; cy <= cy1; ++cy) {
      const float centre_y = grid.origin.y() + (cy + 0.5f) * cell;
      for (int cx = cx0; cx <= cx1; ++cx) {
        const float centre_x = grid.origin.x() + (cx + 0.5f) * cell;
        if (std::abs(abc.x() * centre_x + abc.y() * centre_y + abc.z()) > corridor) continue;
        const int c = cy * grid.cols + cx;
        for (int k = grid.cell_begin[c]; k < grid.cell_begin[c + 1]; ++k) {
          const int p = grid.point_ids[k];
          if (segment.contains(points[p], params)) members.push_back(p);
        }
      }
    }
    std::sort(members.begin(), members.end());
  }
  fill_lines_of_point(association);
  return association;
}

}  // namespace vkvo::features
