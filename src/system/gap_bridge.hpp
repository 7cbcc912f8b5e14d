#pragma once
// Poses of frames the VO could not track, bridged once tracking resumes.
//
// An untracked frame (black, blank, no matches) gets a pose predicted by the constant-velocity prior, which
// drifts within a few frames when the motion is not steady. When tracking resumes, the poses on both sides of
// the gap come from the optimisation, and interpolating between them in time is the better estimate of the
// frames in between. The bridge holds the untracked frames' poses back while the gap lasts and releases them
// interpolated when a tracked frame closes it. A gap longer than `max_held` frames releases its predictions as
// they come (a crash loses at most `max_held` poses; nothing is held for a camera left in the dark).
#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

namespace vkvo::system {

struct FramePose {
  std::int64_t timestamp_ns = 0;
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();
  bool tracked = false;   // from the optimisation; false: predicted
  bool bridged = false;   // set on release: interpolated across a closed gap
};

// x_world at time t between two poses: translation linear and rotation slerped with the same fraction.
Eigen::Isometry3d interpolate_pose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double fraction);

class GapBridge {
 public:
  // max_held = 0 disables bridging: every pose is released as it comes.
  explicit GapBridge(int max_held) : max_held_(max_held) {}

  // Takes the next frame's pose (frames in time order) and returns the poses ready to write, in order.
  std::vector<FramePose> push(const FramePose& pose);
  // The poses still held (end of the run): released as predicted.
  std::vector<FramePose> flush();

  int frames_bridged() const { return bridged_; }
  std::size_t held() const { return held_.size(); }

 private:
  int max_held_;
  std::optional<FramePose> last_tracked_;
  std::deque<FramePose> held_;
  bool overflowed_ = false;  // the current gap outgrew max_held: its poses are released unbridged
  int bridged_ = 0;
};

}  // namespace vkvo::system
