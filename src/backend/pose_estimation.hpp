#pragma once
// Initial pose estimation (IPE): motion-only optimisation of the current frame against matched map points and map
// lines (Ceres, Huber losses), with iterative outlier rejection and a PnP-RANSAC start when the motion prior
// disagrees with the matches.
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "backend/cost_functions.hpp"
#include "backend/params.hpp"
#include "geometry/camera.hpp"
#include "geometry/line3d.hpp"

namespace vkvo::backend {

struct PointMatch {
  Eigen::Vector3d position_world = Eigen::Vector3d::Zero();
  PointMeasurement measurement;  // left pixel, right x or -1
};

struct LineMatch {
  geometry::PlueckerLine line_world;
  LineMeasurement measurement;  // left segment, optional right segment
};

struct PoseEstimate {
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();
  std::vector<bool> point_inliers;  // per PointMatch
  std::vector<bool> line_inliers;   // per LineMatch
  int num_point_inliers = 0;
  int num_line_inliers = 0;
  bool used_pnp = false;  // the PnP-RANSAC pose replaced the prior as the start
  bool success = false;   // num_point_inliers + num_line_inliers >= min_pose_inliers
};

// PnP + RANSAC on the point matches' left pixels (OpenCV, EPnP minimal sets), with a reprojection threshold of
// pixel_sigma * sqrt(mono_point_chi2) pixels.
struct PnpSolution {
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();
  std::vector<bool> inliers;  // per PointMatch
  int num_inliers = 0;
};
// nullopt when there are fewer than 4 matches or RANSAC finds no model.
std::optional<PnpSolution> solve_pnp_ransac(const geometry::PinholeCamera& camera,
                                            const std::vector<PointMatch>& points, const OptimizationParams& params,
                                            int iterations);

PoseEstimate estimate_pose(const geometry::StereoCamera& stereo, const Eigen::Isometry3d& T_world_camera_prior,
                           const std::vector<PointMatch>& points, const std::vector<LineMatch>& lines,
                           const OptimizationParams& params);

}  // namespace vkvo::backend
