#include "system/map_line_projection.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <tuple>

#include "geometry/line3d.hpp"
#include "io/config.hpp"

namespace vkvo::system {
namespace {

// A map line as the frame's camera sees it.
struct ProjectedMapLine {
  map::Id id = map::kInvalidId;
  Eigen::Vector3d image_line = Eigen::Vector3d::Zero();
  std::optional<std::pair<Eigen::Vector2d, Eigen::Vector2d>> extent;  // the projected endpoints
  std::vector<map::Id> points;  // map points associated with it in its keyframes (sorted)
};

// Map points associated with the line in the keyframes that observe it.
std::vector<map::Id> associated_points(const map::Map& map, const map::MapLine& line) {
  std::vector<map::Id> points;
  for (const auto& [kf_id, index] : line.observations) {
    const map::KeyFrame* kf = map.keyframe(kf_id);
    if (!kf || static_cast<std::size_t>(index) >= kf->line_points.size()) continue;
    for (const int k : kf->line_points[static_cast<std::size_t>(index)])
      if (static_cast<std::size_t>(k) < kf->point_ids.size() && kf->point_ids[k] != map::kInvalidId)
        points.push_back(kf->point_ids[k]);
  }
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());
  return points;
}

std::optional<ProjectedMapLine> project(const map::Map& map, const map::MapLine& line,
                                        const Eigen::Isometry3d& T_camera_world,
                                        const geometry::PinholeCamera& camera) {
  constexpr double kMinDepth = 1e-3;  // m: an endpoint behind (or at) the camera has no image
  ProjectedMapLine out;
  out.id = line.id;
  out.image_line = geometry::project_line(camera, geometry::transform_line(T_camera_world, line.line));
  if (out.image_line.head<2>().norm() < 1e-12) return std::nullopt;  // through the camera centre
  if (line.endpoints) {
    const Eigen::Vector3d A = T_camera_world * line.endpoints->first, B = T_camera_world * line.endpoints->second;
    if (A.z() < kMinDepth || B.z() < kMinDepth) return std::nullopt;
    out.extent = std::pair{camera.project(A), camera.project(B)};
  }
  out.points = associated_points(map, line);
  return out;
}

// The common extent of the frame segment and the projected one along the segment, over the shorter of the two.
double overlap(const geometry::Segment2d& segment, const std::pair<Eigen::Vector2d, Eigen::Vector2d>& extent) {
  const Eigen::Vector2d p = segment.head<2>(), q = segment.tail<2>();
  const double length = (q - p).norm();
  if (length <= 0) return 0;
  const Eigen::Vector2d u = (q - p) / length;
  const double a = u.dot(extent.first - p), b = u.dot(extent.second - p);
  const double lo = std::min(a, b), hi = std::max(a, b);
  const double shorter = std::min(length, hi - lo);
  if (shorter <= 0) return 0;
  return std::max(0.0, std::min(length, hi) - std::max(0.0, lo)) / shorter;
}

int shared_points(const std::vector<int>& keypoints, const std::vector<map::Id>& point_ids,
                  const std::vector<map::Id>& line_points) {
  int shared = 0;
  for (const int k : keypoints)
    if (static_cast<std::size_t>(k) < point_ids.size() && point_ids[k] != map::kInvalidId &&
        std::binary_search(line_points.begin(), line_points.end(), point_ids[k]))
      ++shared;
  return shared;
}

}  // namespace

LineProjectionParams load_line_projection_params(const YAML::Node& section) {
  LineProjectionParams params;
  io::require_map(section, "lines.projection");
  io::read_param(section, "enabled", params.enabled);
  io::read_param(section, "max_distance", params.max_distance);
  io::read_param(section, "min_overlap", params.min_overlap);
  return params;
}

std::vector<map::Id> lines_observed_by(const map::Map& map, const std::vector<map::Id>& window) {
  std::set<map::Id> ids;
  for (const map::Id kf_id : window)
    if (const map::KeyFrame* kf = map.keyframe(kf_id))
      for (const map::Id id : kf->line_ids)
        if (const map::MapLine* line = id == map::kInvalidId ? nullptr : map.line(id); line && !line->bad)
          ids.insert(id);
  return {ids.begin(), ids.end()};
}

std::vector<ProjectedLineMatch> match_lines_by_projection(const map::Map& map, const std::vector<map::Id>& candidates,
                                                          const LineProjectionQuery& query,
                                                          const geometry::PinholeCamera& camera,
                                                          const LineProjectionParams& params) {
  const std::set<map::Id> tracked(query.line_ids.begin(), query.line_ids.end());
  const Eigen::Isometry3d T_camera_world = query.T_world_camera.inverse();
  std::vector<ProjectedMapLine> projected;
  for (const map::Id id : candidates) {
    const map::MapLine* line = map.line(id);
    if (!line || line->bad || tracked.count(id)) continue;
    if (auto p = project(map, *line, T_camera_world, camera)) projected.push_back(std::move(*p));
  }

  std::vector<ProjectedLineMatch> pairs;
  for (std::size_t l = 0; l < query.lines.size(); ++l) {
    if (l < query.line_ids.size() && query.line_ids[l] != map::kInvalidId) continue;
    const geometry::Segment2d& segment = query.lines[l].left;
    const std::vector<int> no_keypoints;
    const std::vector<int>& keypoints = l < query.points_of_line.size() ? query.points_of_line[l] : no_keypoints;
    std::vector<ProjectedLineMatch> fits;
    for (const ProjectedMapLine& p : projected) {
      const double distance = std::max(std::abs(geometry::point_line_distance(p.image_line, segment.head<2>())),
                                       std::abs(geometry::point_line_distance(p.image_line, segment.tail<2>())));
      if (distance > params.max_distance) continue;
      if (p.extent && overlap(segment, *p.extent) < params.min_overlap) continue;
      const int support = shared_points(keypoints, query.point_ids, p.points);
      if (!p.extent && support == 0) continue;  // nothing says where along the image line it lies
      fits.push_back({static_cast<int>(l), p.id, support, distance});
    }
    // Without support, geometry must single one map line out.
    const bool supported =
        std::any_of(fits.begin(), fits.end(), [](const ProjectedLineMatch& m) { return m.support > 0; });
    if (supported || fits.size() == 1)
      for (const ProjectedLineMatch& m : fits)
        if (m.support > 0 || !supported) pairs.push_back(m);
  }

  // One-to-one, the best supported and closest first.
  std::sort(pairs.begin(), pairs.end(), [](const ProjectedLineMatch& a, const ProjectedLineMatch& b) {
    return std::tie(b.support, a.distance_px) < std::tie(a.support, b.distance_px);
  });
  std::set<int> used_lines;
  std::set<map::Id> used_map_lines;
  std::vector<ProjectedLineMatch> matches;
  for (const ProjectedLineMatch& m : pairs) {
    if (used_lines.count(m.line) || used_map_lines.count(m.map_line)) continue;
    used_lines.insert(m.line);
    used_map_lines.insert(m.map_line);
    matches.push_back(m);
  }
  return matches;
}

}  // namespace vkvo::system
