#include "backend/params.hpp"

#include "io/config.hpp"

namespace vkvo::backend {

OptimizationParams load_optimization_params(const YAML::Node& s) {
  OptimizationParams p;
  io::read_param(s, "pixel_sigma", p.pixel_sigma);
  io::read_param(s, "mono_point_chi2", p.mono_point_chi2);
  io::read_param(s, "stereo_point_chi2", p.stereo_point_chi2);
  io::read_param(s, "mono_line_chi2", p.mono_line_chi2);
  io::read_param(s, "stereo_line_chi2", p.stereo_line_chi2);
  io::read_param(s, "line_weight", p.line_weight);
  io::read_param(s, "pose_with_lines", p.pose_with_lines);
  io::read_param(s, "pose_rounds", p.pose_rounds);
  io::read_param(s, "pose_iterations", p.pose_iterations);
  io::read_param(s, "min_pose_inliers", p.min_pose_inliers);
  io::read_param(s, "pnp_prior_min_inlier_ratio", p.pnp_prior_min_inlier_ratio);
  io::read_param(s, "pnp_min_points", p.pnp_min_points);
  io::read_param(s, "pnp_iterations", p.pnp_iterations);
  io::read_param(s, "pnp_confidence", p.pnp_confidence);
  io::read_param(s, "window_size", p.window_size);
  io::read_param(s, "min_covisible", p.min_covisible);
  io::read_param(s, "ba_iterations", p.ba_iterations);
  io::read_param(s, "ba_rounds", p.ba_rounds);
  io::read_param(s, "num_threads", p.num_threads);
  return p;
}

KeyframeParams load_keyframe_params(const YAML::Node& s) {
  KeyframeParams p;
  io::read_param(s, "max_translation", p.max_translation);
  io::read_param(s, "max_rotation", p.max_rotation);
  io::read_param(s, "max_tracked", p.max_tracked);
  io::read_param(s, "min_tracked", p.min_tracked);
  io::read_param(s, "max_frames", p.max_frames);
  return p;
}

}  // namespace vkvo::backend
