#include "system/gap_bridge.hpp"

#include <algorithm>

namespace vkvo::system {

Eigen::Isometry3d interpolate_pose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double fraction) {
  const Eigen::Quaterniond qa(a.rotation()), qb(b.rotation());
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = qa.slerp(fraction, qb).normalized().toRotationMatrix();
  pose.translation() = (1.0 - fraction) * a.translation() + fraction * b.translation();
  return pose;
}

std::vector<FramePose> GapBridge::push(const FramePose& pose) {
  std::vector<FramePose> ready;
  if (!pose.tracked) {
    // Before the first tracked frame there is nothing to interpolate from; past max_held the gap is released.
    if (max_held_ <= 0 || !last_tracked_ || overflowed_) return {pose};
    held_.push_back(pose);
    if (static_cast<int>(held_.size()) > max_held_) {
      overflowed_ = true;
      return flush();
    }
    return {};
  }
  if (!held_.empty()) {
    const double t0 = static_cast<double>(last_tracked_->timestamp_ns);
    const double span = static_cast<double>(pose.timestamp_ns) - t0;
    for (FramePose held : held_) {
      const double fraction = span > 0 ? std::clamp((static_cast<double>(held.timestamp_ns) - t0) / span, 0.0, 1.0)
                                       : 0.0;
      held.T_world_camera = interpolate_pose(last_tracked_->T_world_camera, pose.T_world_camera, fraction);
      held.bridged = true;
      ready.push_back(held);
      ++bridged_;
    }
    held_.clear();
  }
  overflowed_ = false;
  last_tracked_ = pose;
  ready.push_back(pose);
  return ready;
}

std::vector<FramePose> GapBridge::flush() {
  std::vector<FramePose> ready(held_.begin(), held_.end());
  held_.clear();
  return ready;
}

}  // namespace vkvo::system
