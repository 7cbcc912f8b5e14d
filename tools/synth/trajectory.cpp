#include "tools/synth/trajectory.hpp"

#include <cmath>
#include <random>

namespace vkvo::synth {
namespace {
constexpr double kPi = 3.14159265358979323846;
double rad(double deg) { return deg * kPi / 180.0; }
}  // namespace

SmoothTrajectory::SmoothTrajectory(const TrajectoryParams& params, uint64_t seed) : params_(params) {
  std::mt19937_64 rng(seed);
  for (double& p : offsets_) p = 2 * kPi * static_cast<double>(rng() % 100000) / 100000.0;
  // ds/dt = speed / |dp/ds|, integrated with RK4 over an hour (180k steps, a few ms).
  constexpr double kHorizon = 3600.0;
  const auto steps = static_cast<size_t>(kHorizon / kTableStep);
  phase_table_.resize(steps + 1);
  double s = 0.0;
  phase_table_[0] = s;
  for (size_t i = 1; i <= steps; ++i) {
    const double h = kTableStep;
    const double k1 = phase_rate(s), k2 = phase_rate(s + 0.5 * h * k1), k3 = phase_rate(s + 0.5 * h * k2),
                 k4 = phase_rate(s + h * k3);
    s += h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
    phase_table_[i] = s;
  }
}

double SmoothTrajectory::phase_rate(double s) const {
  const double h = 1e-5;
  const double ds_length = (position_at_phase(s + h) - position_at_phase(s - h)).norm() / (2 * h);
  return ds_length > 1e-9 ? params_.speed / ds_length : 0.0;
}

double SmoothTrajectory::phase(double t) const {
  if (t <= 0) return phase_rate(0) * t;
  const double x = t / kTableStep;
  const auto i = static_cast<size_t>(x);
  if (i + 1 >= phase_table_.size()) {
    const double mean_rate = phase_table_.back() / ((phase_table_.size() - 1) * kTableStep);
    return phase_table_.back() + mean_rate * (t - (phase_table_.size() - 1) * kTableStep);
  }
  // Cubic Hermite between nodes with the exact slopes: C1 in time, error O(step^4).
  const double u = x - static_cast<double>(i);
  const double s0 = phase_table_[i], s1 = phase_table_[i + 1];
  const double m0 = phase_rate(s0) * kTableStep, m1 = phase_rate(s1) * kTableStep;
  const double u2 = u * u, u3 = u2 * u;
  return (2 * u3 - 3 * u2 + 1) * s0 + (u3 - 2 * u2 + u) * m0 + (-2 * u3 + 3 * u2) * s1 + (u3 - u2) * m1;
}

Eigen::Vector3d SmoothTrajectory::position_at_phase(double s) const {
  const Eigen::Vector3d& r = params_.radius;
  // An ellipse, wobbling by 15% of its size at incommensurate rates so that consecutive laps differ.
  return params_.center + Eigen::Vector3d(r.x() * (std::cos(s) + 0.15 * std::sin(2.3 * s + offsets_[0])),
                                          r.y() * (std::sin(s) + 0.15 * std::sin(1.7 * s + offsets_[1])),
                                          r.z() * std::sin(1.3 * s + offsets_[2]));
}

Eigen::Isometry3d SmoothTrajectory::pose(double t) const {
  const double yaw = rad(params_.start_yaw_deg + params_.yaw_rate_deg * t) +
                     rad(params_.yaw_sway_deg) * std::sin(2 * kPi * 0.09 * t + offsets_[3]);
  const double pitch =
      rad(params_.pitch_deg) + rad(params_.pitch_sway_deg) * std::sin(2 * kPi * 0.13 * t + offsets_[4]);
  const double roll = rad(params_.roll_sway_deg) * std::sin(2 * kPi * 0.21 * t + offsets_[5]);
  // Camera looking along world +x with zero angles: camera x = -world y, camera y = -world z, camera z = world x.
  Eigen::Matrix3d level;
  level << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * level *
                            Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()).toRotationMatrix() *
                            Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = position(t);
  return T;
}

Eigen::Vector3d SmoothTrajectory::velocity(double t) const {
  const double h = 1e-4;  // central difference of an analytic path: error O(h^2) ~ 1e-9 m/s
  return (position(t + h) - position(t - h)) / (2 * h);
}

}  // namespace vkvo::synth
