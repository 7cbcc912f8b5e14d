#pragma once
// Pairs estimated and ground-truth poses by timestamp.
#include <cstddef>
#include <vector>

#include <Eigen/Geometry>

#include "io/trajectory.hpp"

namespace vkvo::eval {

struct AssociatedPoses {
  std::vector<double> t;                       // estimate timestamps (s)
  std::vector<Eigen::Isometry3d> estimate;     // pose i of the estimate ...
  std::vector<Eigen::Isometry3d> groundtruth;  // ... and the ground-truth pose nearest in time
  std::size_t size() const { return t.size(); }
};

// For every estimate pose, the ground-truth pose nearest in time when |dt| <= max_dt_s. A ground-truth pose is
// used at most once (the closest estimate keeps it), so duplicated stamps cannot weight the error. Neither input
// needs to be sorted; the result is in estimate time order.
AssociatedPoses associate(const io::Trajectory& estimate, const io::Trajectory& groundtruth, double max_dt_s = 0.02);

}  // namespace vkvo::eval
