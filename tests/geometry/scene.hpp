#pragma once
// Synthetic scenes for the geometry tests: a rectified stereo camera, random poses, points and lines, and the
// comparison of two 3D lines.
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/camera.hpp"
#include "geometry/line3d.hpp"

namespace vkvo::test {

inline geometry::StereoCamera test_stereo_camera() {
  geometry::StereoCamera s;
  s.camera = {458.0, 451.0, 367.5, 248.0, 752, 480};  // fx != fy on purpose: catches swapped K_L entries
  s.baseline = 0.11;
  return s;
}

inline Eigen::Isometry3d random_pose(std::mt19937& rng, double translation, double rotation) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d axis = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
  T.linear() = Eigen::AngleAxisd(rotation * u(rng), axis).toRotationMatrix();
  T.translation() = translation * Eigen::Vector3d(u(rng), u(rng), u(rng));
  return T;
}

// A point in front of the camera T_world_camera, at depth in [zmin, zmax], projecting inside the image.
inline Eigen::Vector3d random_visible_point(std::mt19937& rng, const geometry::PinholeCamera& cam,
                                            const Eigen::Isometry3d& T_world_camera, double zmin, double zmax) {
  std::uniform_real_distribution<double> ux(20.0, cam.width - 20.0), uy(20.0, cam.height - 20.0), uz(zmin, zmax);
  const Eigen::Vector2d px(ux(rng), uy(rng));
  return T_world_camera * (uz(rng) * cam.backproject(px));
}

// The segment A-B as the camera at T_world_camera sees it (both ends in front of it).
inline geometry::Segment2d observe_segment(const geometry::PinholeCamera& cam, const Eigen::Isometry3d& T_world_camera,
                                           const Eigen::Vector3d& A, const Eigen::Vector3d& B) {
  const Eigen::Vector2d a = cam.project(T_world_camera.inverse() * A), b = cam.project(T_world_camera.inverse() * B);
  return {a.x(), a.y(), b.x(), b.y()};
}

// Same line: directions parallel (either sign) and n/|v| equal up to that sign.
inline void expect_same_line(const geometry::PlueckerLine& a, const geometry::PlueckerLine& b, double tol) {
  const geometry::PlueckerLine an = a.normalized(), bn = b.normalized();
  const double sign = an.v.dot(bn.v) > 0 ? 1.0 : -1.0;
  EXPECT_LT((an.v - sign * bn.v).norm(), tol);
  EXPECT_LT((an.n - sign * bn.n).norm(), tol);
}

}  // namespace vkvo::test
