#include "system/mono_points.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "geometry/triangulation.hpp"

namespace vkvo::system {
namespace {

// The point's reprojection error in the camera, or nullopt when it lies nearer than `min_depth` (or behind it).
std::optional<double> reprojection_error(const geometry::PinholeCamera& camera, const Eigen::Isometry3d& T_world_camera,
                                         const Eigen::Vector3d& point_world, const Eigen::Vector2d& pixel,
                                         double min_depth) {
  const Eigen::Vector3d p = T_world_camera.inverse() * point_world;
  if (p.z() < min_depth) return std::nullopt;
  return (camera.project(p) - pixel).norm();
}

}  // namespace

NewMonoPoints add_mono_points(map::Map& map, map::Id kf, map::Id reference, const std::vector<int>& reference_partner,
                              const geometry::PinholeCamera& camera, const MonoPointParams& params) {
  NewMonoPoints out;
  const map::KeyFrame* here = map.keyframe(kf);
  const map::KeyFrame* there = reference == kf ? nullptr : map.keyframe(reference);
  if (!here || !there) return out;
  const double min_cos_parallax = std::cos(params.min_parallax_deg * M_PI / 180.0);
  const Eigen::Vector3d centre_here = here->T_world_camera.translation();
  const Eigen::Vector3d centre_there = there->T_world_camera.translation();
  const std::size_t n = std::min(reference_partner.size(), here->keypoints.size());
  for (std::size_t i = 0; i < n; ++i) {
    const int j = reference_partner[i];
    if (j < 0 || static_cast<std::size_t>(j) >= there->keypoints.size()) continue;
    const auto ju = static_cast<std::size_t>(j);
    if (here->point_ids[i] != map::kInvalidId || here->is_stereo(static_cast<int>(i)) ||
        there->point_ids[ju] != map::kInvalidId)
      continue;
    ++out.candidates;
    const auto X = geometry::triangulate_two_view(camera, there->T_world_camera, there->keypoints[ju],
                                                  here->T_world_camera, here->keypoints[i]);
    if (!X) continue;
    const Eigen::Vector3d ray_here = (*X - centre_here).normalized(), ray_there = (*X - centre_there).normalized();
    if (ray_here.dot(ray_there) > min_cos_parallax) continue;
    const auto error_here = reprojection_error(camera, here->T_world_camera, *X, here->keypoints[i], params.min_depth);
    const auto error_there =
        reprojection_error(camera, there->T_world_camera, *X, there->keypoints[ju], params.min_depth);
    if (!error_here || !error_there || *error_here > params.max_reprojection_px ||
        *error_there > params.max_reprojection_px)
      continue;
    const map::Id id = map.add_point(*X);
    map.add_point_observation(id, reference, j);
    map.add_point_observation(id, kf, static_cast<int>(i));
    ++out.added;
  }
  return out;
}

}  // namespace vkvo::system
