#pragma once
// Parameters of the back end with the reference configuration's defaults (method-notes "Keyframes and
// optimisation"), and their YAML loaders (missing key -> default, wrong type -> std::runtime_error).
#include <yaml-cpp/yaml.h>

namespace vkvo::backend {

// Chi-square style thresholds are on the whitened squared residual |r|^2 / sigma^2. They set both the Huber
// threshold (delta = sqrt(chi2) in whitened units) and the outlier test after each solve.
// YAML keys: pixel_sigma, mono_point_chi2, stereo_point_chi2, mono_line_chi2, stereo_line_chi2, line_weight,
// pose_with_lines,
// pose_rounds, pose_iterations, min_pose_inliers, pnp_min_points, pnp_iterations, pnp_confidence,
// pnp_prior_min_inlier_ratio, window_size, min_covisible, ba_iterations, ba_rounds, num_threads.
struct OptimizationParams {
  double pixel_sigma = 0.8;
  double mono_point_chi2 = 50.0;
  double stereo_point_chi2 = 75.0;
  double mono_line_chi2 = 50.0;
  double stereo_line_chi2 = 75.0;
  // Weight of a line residual's robust cost against a point's (the paper: 1; AirVO's code: 0.1), in pose
  // estimation and local BA alike. Outlier tests stay on the unweighted chi2.
  double line_weight = 1.0;
  // true: lines take part in the initial pose estimation (the paper); false: the pose comes from points alone
  // and the lines are only classified against it before entering the BA (AirVO's code).
  bool pose_with_lines = true;

  // Initial pose estimation (motion only): rounds of solve + outlier reclassification.
  int pose_rounds = 4;
  int pose_iterations = 10;  // per round
  int min_pose_inliers = 10;
  // PnP-RANSAC start when fewer than this fraction of the point matches agree with the motion prior.
  double pnp_prior_min_inlier_ratio = 0.5;
  int pnp_min_points = 10;
  int pnp_iterations = 100;
  double pnp_confidence = 0.99;

  // Local bundle adjustment.
  int window_size = 10;    // keyframes optimised (the newest and its most recent co-visible ones)
  int min_covisible = 1;   // shared landmarks for a keyframe to count as co-visible
  int ba_iterations = 10;  // per round
  int ba_rounds = 2;       // solve, drop outliers, solve again

  int num_threads = 1;
};
OptimizationParams load_optimization_params(const YAML::Node& section);

// Keyframe decision (paper sec. "Keyframe Selection"). YAML keys: max_translation, max_rotation, max_tracked,
// min_tracked, max_frames.
struct KeyframeParams {
  double max_translation = 0.5;  // m, to the last keyframe
  double max_rotation = 0.52;    // rad, to the last keyframe
  int max_tracked = 80;          // N1: fewer tracked map points than this (but at least N2) -> keyframe
  int min_tracked = 10;          // N2: below this the frame counts as a tracking failure
  int max_frames = 300;          // frames since the last keyframe
};
KeyframeParams load_keyframe_params(const YAML::Node& section);

}  // namespace vkvo::backend
