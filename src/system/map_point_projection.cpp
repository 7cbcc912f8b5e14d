#include "system/map_point_projection.hpp"

#include <algorithm>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>

#include "io/config.hpp"

namespace vkvo::system {

PointProjectionParams load_point_projection_params(const YAML::Node& section) {
  PointProjectionParams p;
  io::require_map(section, "tracking.point_projection");
  io::read_param(section, "enabled", p.enabled);
  io::read_param(section, "below_point_inliers", p.below_point_inliers);
  io::read_param(section, "radius_px", p.radius_px);
  io::read_param(section, "max_cosine_distance", p.max_cosine_distance);
  io::read_param(section, "max_ratio", p.max_ratio);
  if (p.below_point_inliers < 0)
    throw std::runtime_error("tracking.point_projection.below_point_inliers must not be negative");
  if (!(p.radius_px > 0)) throw std::runtime_error("tracking.point_projection.radius_px must be positive");
  if (!(p.max_cosine_distance > 0 && p.max_cosine_distance <= 2))
    throw std::runtime_error("tracking.point_projection.max_cosine_distance must lie in (0, 2]");
  if (!(p.max_ratio > 0 && p.max_ratio <= 1))
    throw std::runtime_error("tracking.point_projection.max_ratio must lie in (0, 1]");
  return p;
}

std::vector<ProjectedPointMatch> match_points_by_projection(const map::Map& map, const std::vector<map::Id>& keyframes,
                                                            const KeyframeFeatures& keyframe_features,
                                                            const PointProjectionQuery& query,
                                                            const geometry::PinholeCamera& camera,
                                                            const PointProjectionParams& params) {
  const features::PointFeatures& frame = query.features;
  const std::vector<bool>& taken = query.taken;
  if (frame.size() == 0 || frame.descriptors.rows() == 0) return {};
  // The views whose descriptors a map point may be recognised by: those of the keyframes that kept features.
  std::map<map::Id, const features::PointFeatures*> views;
  for (const map::Id kf_id : keyframes)
    if (const features::PointFeatures* f = map.keyframe(kf_id) ? keyframe_features(kf_id) : nullptr;
        f && f->descriptors.cols() == frame.descriptors.cols())
      views.emplace(kf_id, f);
  const std::set<map::Id> already(query.tracked.begin(), query.tracked.end());
  std::set<map::Id> candidates;
  for (const auto& [kf_id, f] : views)
    for (const map::Id id : map.keyframe(kf_id)->point_ids)
      if (const map::MapPoint* p = id == map::kInvalidId ? nullptr : map.point(id); p && !p->bad && !already.count(id))
        candidates.insert(id);

  const Eigen::Isometry3d T_camera_world = query.T_world_camera.inverse();
  const double radius_squared = params.radius_px * params.radius_px;
  // A keypoint's distance to a map point: to the closest of the point's views (the light may have changed since
  // some of them).
  const auto distance_to = [&](std::size_t keypoint, const map::MapPoint& point) {
    float best = std::numeric_limits<float>::max();
    for (const auto& [kf_id, index] : point.observations) {
      const auto view = views.find(kf_id);
      if (view == views.end() || index < 0 || static_cast<std::size_t>(index) >= view->second->size()) continue;
      best = std::min(best, 1.0f - frame.descriptors.row(static_cast<Eigen::Index>(keypoint))
                                       .dot(view->second->descriptors.row(static_cast<Eigen::Index>(index))));
    }
    return best;
  };

  // Per keypoint, the best claim so far.
  std::vector<ProjectedPointMatch> claim(frame.size());
  for (const map::Id id : candidates) {
    const map::MapPoint& point = *map.point(id);
    const Eigen::Vector3d p_camera = T_camera_world * point.position;
    if (p_camera.z() <= 1e-3) continue;
    const Eigen::Vector2d pixel = camera.project(p_camera);
    if (!camera.in_image(pixel)) continue;
    float best = std::numeric_limits<float>::max(), second = best;
    int best_keypoint = -1;
    for (std::size_t i = 0; i < frame.size(); ++i) {
      if ((i < taken.size() && taken[i]) || (frame.keypoints[i].cast<double>() - pixel).squaredNorm() > radius_squared)
        continue;
      const float distance = distance_to(i, point);
      if (distance < best) {
        second = best;
        best = distance;
        best_keypoint = static_cast<int>(i);
      } else if (distance < second) {
        second = distance;
      }
    }
    if (best_keypoint < 0 || best > params.max_cosine_distance) continue;
    if (second < std::numeric_limits<float>::max() && best > params.max_ratio * second) continue;
    ProjectedPointMatch& current = claim[static_cast<std::size_t>(best_keypoint)];
    if (current.keypoint < 0 || best < current.descriptor_distance) current = {best_keypoint, id, best};
  }
  std::vector<ProjectedPointMatch> matches;
  for (const ProjectedPointMatch& m : claim)
    if (m.keypoint >= 0) matches.push_back(m);
  return matches;
}

}  // namespace vkvo::system
