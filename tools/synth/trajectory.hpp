#pragma once
// A smooth 6-DoF camera trajectory inside the room: the position runs around a perturbed ellipse at constant
// speed (arc-length parametrised), the heading turns steadily with a superimposed sway, pitch and roll oscillate.
// Everything is a smooth function of time, evaluated exactly at any t >= 0 (the arc-length table covers an
// hour; beyond it the path continues at the mean rate).
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vkvo::synth {

struct TrajectoryParams {
  Eigen::Vector3d center{0.0, 0.0, 1.5};  // of the ellipse, metres (world: z up)
  Eigen::Vector3d radius{1.4, 1.0, 0.2};  // semi-axes in x and y, height oscillation in z
  double speed = 0.5;                     // mean speed, m/s
  double yaw_rate_deg = 12.0;             // steady turn, deg/s
  double yaw_sway_deg = 20.0;             // amplitude of the heading sway
  double pitch_deg = -8.0;                // mean pitch (negative: looking down)
  double pitch_sway_deg = 8.0;
  double roll_sway_deg = 4.0;
  double start_yaw_deg = 0.0;  // heading at t = 0 (0: looking along world +x)
};

class SmoothTrajectory {
 public:
  // `seed` varies the phases of the oscillations.
  SmoothTrajectory(const TrajectoryParams& params, uint64_t seed);

  Eigen::Isometry3d pose(double t) const;    // T_world_camera (camera: x right, y down, z forward)
  Eigen::Vector3d velocity(double t) const;  // world frame, m/s

 private:
  Eigen::Vector3d position_at_phase(double s) const;  // the path as a function of the ellipse angle
  double phase_rate(double s) const;                  // ds/dt that moves at params.speed at phase s
  double phase(double t) const;                       // s(t): arc-length parametrisation, from the table
  Eigen::Vector3d position(double t) const { return position_at_phase(phase(t)); }

  TrajectoryParams params_;
  double offsets_[6] = {};
  // s(t) at t = i * kTableStep, integrated with RK4; cubic Hermite in between (slopes from phase_rate).
  static constexpr double kTableStep = 0.02;
  std::vector<double> phase_table_;
};

}  // namespace vkvo::synth
