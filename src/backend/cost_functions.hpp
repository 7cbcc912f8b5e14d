#pragma once
// Ceres residuals of the back end (automatic differentiation; the templated functors live only in
// cost_functions.cpp so that one translation unit pays for their instantiation).
//
// Parameter blocks (all double):
//   pose:  [q_camera_world (Eigen order x, y, z, w), t_camera_world] = 7 doubles, make_pose_manifold() (6-DoF)
//   point: X_world[3]
//   line:  Pluecker (n, v)_world[6] with the 4-DoF orthonormal manifold (make_line_manifold)
// Residuals are whitened (divided by the pixel sigma), so |r|^2 is the chi-square statistic of the config.
#include <memory>
#include <optional>

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/camera.hpp"
#include "geometry/line3d.hpp"

namespace vkvo::backend {

// Mono point: (u, v), 2 residuals; stereo point (right_x >= 0): (u, v, u_right), 3 residuals (eq. 10).
struct PointMeasurement {
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  double right_x = -1;
  bool stereo() const { return right_x >= 0; }
};

// Mono line: distances of the two observed endpoints to the projected line, 2 residuals; stereo line: the same in
// the right image too, 4 residuals (eq. 9).
struct LineMeasurement {
  geometry::Segment2d left = geometry::Segment2d::Zero();
  std::optional<geometry::Segment2d> right;
  bool stereo() const { return right.has_value(); }
};

std::unique_ptr<ceres::CostFunction> make_point_cost(const geometry::StereoCamera& stereo,
                                                     const PointMeasurement& measurement, double pixel_sigma);
std::unique_ptr<ceres::CostFunction> make_line_cost(const geometry::StereoCamera& stereo,
                                                    const LineMeasurement& measurement, double pixel_sigma);
// Same residuals, numerically differentiated (central differences): the reference for the derivative tests.
std::unique_ptr<ceres::CostFunction> make_numeric_point_cost(const geometry::StereoCamera& stereo,
                                                             const PointMeasurement& measurement, double pixel_sigma);
std::unique_ptr<ceres::CostFunction> make_numeric_line_cost(const geometry::StereoCamera& stereo,
                                                            const LineMeasurement& measurement, double pixel_sigma);

// Huber loss with threshold sqrt(chi2) in whitened units, its cost scaled by `weight` (1: plain Huber).
std::unique_ptr<ceres::LossFunction> make_robust_loss(double chi2_threshold, double weight = 1.0);

// The orthonormal update of a Pluecker block: U <- U Exp(d[0:3]), W <- W Rot(d[3]); the result is rescaled to
// |v| = 1. Minus is its inverse for nearby lines of the same orientation.
std::unique_ptr<ceres::Manifold> make_line_manifold();

// SE(3) as quaternion x translation (ceres::ProductManifold of EigenQuaternionManifold and EuclideanManifold<3>).
// One 7-double block per pose keeps the Schur complement's camera blocks whole.
std::unique_ptr<ceres::Manifold> make_pose_manifold();

// Pose parameter block storage (T_camera_world) and conversions from / to T_world_camera.
struct PoseBlock {
  double x[7] = {0, 0, 0, 1, 0, 0, 0};  // qx qy qz qw tx ty tz
  double* data() { return x; }
  static PoseBlock from_T_world_camera(const Eigen::Isometry3d& T_world_camera);
  Eigen::Isometry3d T_world_camera() const;
};

}  // namespace vkvo::backend
