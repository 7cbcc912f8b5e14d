#include "backend/params.hpp"

#include "geometry/yaml_param.hpp"

namespace vkvo::backend {

using geometry::read_optional;

OptimizationParams load_optimization_params(const YAML::Node& s) {
  OptimizationParams p;
  read_optional(s, "pixel_sigma", p.pixel_sigma);
  read_optional(s, "mono_point_chi2", p.mono_point_chi2);
  read_optional(s, "stereo_point_chi2", p.stereo_point_chi2);
  read_optional(s, "mono_line_chi2", p.mono_line_chi2);
  read_optional(s, "stereo_line_chi2", p.stereo_line_chi2);
  read_optional(s, "pose_rounds", p.pose_rounds);
  read_optional(s, "pose_iterations", p.pose_iterations);
  read_optional(s, "min_pose_inliers", p.min_pose_inliers);
  read_optional(s, "pnp_prior_min_inlier_ratio", p.pnp_prior_min_inlier_ratio);
  read_optional(s, "pnp_min_points", p.pnp_min_points);
  read_optional(s, "pnp_iterations", p.pnp_iterations);
  read_optional(s, "pnp_confidence", p.pnp_confidence);
  read_optional(s, "window_size", p.window_size);
  read_optional(s, "min_covisible", p.min_covisible);
  read_optional(s, "ba_iterations", p.ba_iterations);
  read_optional(s, "ba_rounds", p.ba_rounds);
  read_optional(s, "num_threads", p.num_threads);
  return p;
}

KeyframeParams load_keyframe_params(const YAML::Node& s) {
  KeyframeParams p;
  read_optional(s, "max_translation", p.max_translation);
  read_optional(s, "max_rotation", p.max_rotation);
  read_optional(s, "max_tracked", p.max_tracked);
  read_optional(s, "min_tracked", p.min_tracked);
  read_optional(s, "max_frames", p.max_frames);
  return p;
}

}  // namespace vkvo::backend
