#pragma once
// Local bundle adjustment over a window of co-visible keyframes: keyframe poses (SE(3) as quaternion + translation),
// map points (3-DoF) and map lines (Pluecker blocks with the 4-DoF orthonormal manifold), monocular and stereo point
// and line residuals, Huber losses; keyframes outside the window that observe the same landmarks are held fixed.
// Derivatives: automatic (see cost_functions.hpp), checked against numeric differentiation in the tests.
#include <vector>

#include "backend/params.hpp"
#include "geometry/camera.hpp"
#include "map/map.hpp"

namespace vkvo::backend {

struct LocalBAResult {
  std::vector<map::Id> window;  // optimised keyframes (the first is the one asked for)
  std::vector<map::Id> fixed;   // keyframes that constrain the landmarks but stay where they are
  int num_points = 0, num_lines = 0;
  int point_observations = 0, line_observations = 0;  // residuals in the problem
  int point_outliers = 0, line_outliers = 0;          // observations erased from the map afterwards
  double initial_cost = 0, final_cost = 0;            // Ceres costs (robustified) of the first / last solve
  bool solved = false;
};

// Optimises the window around `keyframe` in place: writes poses, points and lines back to the map and erases the
// observations that remain outliers (chi2 above the thresholds) or lie behind their camera. Bad landmarks are left
// for Map::cull. When no keyframe outside the window observes the landmarks, the oldest window keyframe is fixed to
// remove the gauge freedom.
LocalBAResult local_bundle_adjustment(map::Map& map, map::Id keyframe, const geometry::StereoCamera& stereo,
                                      const OptimizationParams& params);

}  // namespace vkvo::backend
