#include "system/stereo_keyframe.hpp"

#include <algorithm>
#include <limits>

#include "features/lines/line_matching.hpp"
#include "features/lines/stereo_line_matching.hpp"

namespace vkvo::system {

geometry::Segment2d to_segment(const features::LineSegment& line) {
  return {line.p0.x(), line.p0.y(), line.p1.x(), line.p1.y()};
}

StereoPoints triangulate_stereo_points(const geometry::StereoCamera& stereo, const features::PointFeatures& left,
                                       const features::PointFeatures& right, const features::PointMatches& matches,
                                       const geometry::TriangulationParams& params) {
  StereoPoints out;
  out.right_x.assign(left.size(), -1.0);
  out.positions.assign(left.size(), std::nullopt);
  for (std::size_t i = 0; i < left.size() && i < matches.matches0.size(); ++i) {
    const int j = matches.matches0[i];
    if (j < 0) continue;
    const Eigen::Vector2d l = left.keypoints[i].cast<double>();
    const Eigen::Vector2d r = right.keypoints[static_cast<std::size_t>(j)].cast<double>();
    if (auto p = geometry::triangulate_stereo_point(stereo, l, r, params)) {
      out.right_x[i] = r.x();
      out.positions[i] = *p;
      ++out.count;
    }
  }
  return out;
}

std::vector<std::optional<Eigen::Vector3d>> known_points_in_camera(
    const StereoPoints& stereo, const std::vector<std::optional<Eigen::Vector3d>>& tracked_world,
    const Eigen::Isometry3d& T_world_camera) {
  const Eigen::Isometry3d T_camera_world = T_world_camera.inverse();
  std::vector<std::optional<Eigen::Vector3d>> known = stereo.positions;
  for (std::size_t i = 0; i < known.size() && i < tracked_world.size(); ++i)
    if (tracked_world[i]) known[i] = T_camera_world * *tracked_world[i];
  return known;
}

namespace {

// The two known 3D points of `line` whose keypoints lie nearest the segment's supporting line.
std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>> two_points_on_line(const features::LineSegment& line,
                                                                              const std::vector<int>& line_points,
                                                                              const LeftKeypoints& keypoints) {
  std::vector<std::pair<float, int>> candidates;
  for (int k : line_points)
    if (keypoints.known_positions[static_cast<std::size_t>(k)])
      candidates.emplace_back(line.distance_to_line(keypoints.pixels[static_cast<std::size_t>(k)]), k);
  if (candidates.size() < 2) return std::nullopt;
  std::partial_sort(candidates.begin(), candidates.begin() + 2, candidates.end());
  const Eigen::Vector3d a = *keypoints.known_positions[static_cast<std::size_t>(candidates[0].second)];
  const Eigen::Vector3d b = *keypoints.known_positions[static_cast<std::size_t>(candidates[1].second)];
  if ((a - b).norm() < 1e-3) return std::nullopt;  // the same 3D point twice: no direction
  return std::make_pair(a, b);
}

// The line fitted over the known 3D points associated with a line (AirVO's map lines), each allowed 3 px across
// the ray (the association distance) and, beyond the baseline's depth, 3 px of disparity error along it.
std::optional<geometry::PlueckerLine> line_through_points(const geometry::StereoCamera& stereo,
                                                          const std::vector<int>& line_points,
                                                          const LeftKeypoints& keypoints, int min_points) {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> tolerances;
  for (int k : line_points)
    if (const auto& p = keypoints.known_positions[static_cast<std::size_t>(k)]) {
      const double per_pixel = p->z() / stereo.camera.fx;
      points.push_back(*p);
      tolerances.push_back(3.0 * per_pixel * std::max(1.0, p->z() / stereo.baseline));
    }
  return geometry::fit_line_to_points(points, tolerances, min_points);
}

}  // namespace

std::vector<int> match_stereo_lines(const geometry::StereoCamera& stereo, const AssociatedLines& left,
                                    const AssociatedLines& right, const StereoImages& images,
                                    const std::vector<int>& right_matches, const features::LinePipelineParams& params,
                                    const geometry::TriangulationParams& gates) {
  std::vector<int> partner = features::match_lines(left.association, right.association, right_matches, params.matching);
  if (params.stereo_matching.by_appearance) {
    const double focal_baseline = stereo.camera.fx * stereo.baseline;
    const features::DisparityRange disparity{focal_baseline / gates.max_depth, focal_baseline / gates.min_depth};
    features::add_stereo_partners_by_appearance({images.left, left.segments}, {images.right, right.segments}, disparity,
                                                params.stereo_matching, partner);
  }
  return partner;
}

StereoLines triangulate_stereo_lines(const geometry::StereoCamera& stereo, const AssociatedLines& left,
                                     const AssociatedLines& right, const LeftKeypoints& keypoints,
                                     const std::vector<int>& right_partner,
                                     const geometry::TriangulationParams& params) {
  const std::size_t line_count = left.segments.size();
  StereoLines out;
  out.right.assign(line_count, std::nullopt);
  out.lines.assign(line_count, std::nullopt);
  for (std::size_t l = 0; l < line_count; ++l) {
    const int r = l < right_partner.size() ? right_partner[l] : -1;
    const std::optional<geometry::Segment2d> right_segment =
        r >= 0 ? std::optional(to_segment(right.segments[static_cast<std::size_t>(r)])) : std::nullopt;
    if (params.line_fit_min_points > 0) {
      if (auto fitted =
              line_through_points(stereo, left.association.points_of_line[l], keypoints, params.line_fit_min_points)) {
        out.right[l] = right_segment;
        out.lines[l] = *fitted;
        ++out.points;
        continue;
      }
    }
    const auto points_on_line = two_points_on_line(left.segments[l], left.association.points_of_line[l], keypoints);
    if (right_segment) {
      const auto tri = geometry::triangulate_stereo_line(stereo, to_segment(left.segments[l]), *right_segment,
                                                         points_on_line, params);
      if (tri.method != geometry::LineTriangulationMethod::failed) {
        out.right[l] = right_segment;
        out.lines[l] = tri.line;
        (tri.method == geometry::LineTriangulationMethod::planes ? out.planes : out.points)++;
        continue;
      }
    }
    if (points_on_line) {
      out.lines[l] = geometry::PlueckerLine::from_points(points_on_line->first, points_on_line->second);
      ++out.points;
    }
  }
  return out;
}

}  // namespace vkvo::system
