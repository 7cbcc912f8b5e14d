#pragma once
// The poses of a run's frames as they become final, and the files that show them: the trajectory (TUM, every
// frame), the keyframes' poses as tracking gave them (TUM) and the status file (frames.csv: index, timestamp,
// state, segment, keyframe, inliers, note).
//
// Every frame is written as soon as it is tracked, with its predicted pose when it is not, and flushed: a crash
// loses nothing already processed. Earlier poses change in two cases, and then both files are rewritten whole
// (each into a new file renamed over the old one, so a reader never sees half a file):
//   - a gap closes: the untracked frames between two tracked ones are interpolated with a motion that matches the
//     velocities measured at both ends (cubic Hermite in position and in the rotation's tangent space), and again
//     once the frame after the gap gives the end velocity;
//   - a young map segment merges into an older one: the poses of its frames move with it, and the gaps next to
//     it are interpolated anew.
// Frames before the map first started have no pose to give: they appear in frames.csv, not in the trajectory.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "system/tracker.hpp"

namespace vkvo::system {

enum class PoseState {
  tracked,
  relocalised,
  bridged,        // untracked, interpolated across a closed gap
  lost,           // untracked, the prediction (no tracked frame after it yet, or the gap was too long)
  uninitialised,  // before the map first started: no pose
};
const char* to_string(PoseState state);
bool is_untracked(PoseState state);  // bridged, lost, uninitialised

struct FrameRecord {
  std::size_t index = 0;
  std::int64_t timestamp_ns = 0;
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();
  PoseState state = PoseState::lost;
  int segment = 0;
  bool keyframe = false;
  int point_inliers = 0, line_inliers = 0;
  std::string note;
};

// Velocities in the world frame: d(position)/dt and the angular velocity omega with dR/dt = [omega]x R.
struct Velocity {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();
};

// The pose at `fraction` (0..1) of a motion of `duration` seconds from a to b whose velocities are va at a and
// vb at b: position p(s) = h00 pa + h10 T va + h01 pb + h11 T vb, rotation R(s) = Exp(phi(s)) Ra with phi the
// same Hermite curve from 0 to Log(Rb Ra^T) with tangents T omega_a, T omega_b. Exact at both ends; with the
// velocities of a straight, uniform motion it is the linear interpolation.
Eigen::Isometry3d hermite_pose(const Eigen::Isometry3d& a, const Velocity& va, const Eigen::Isometry3d& b,
                               const Velocity& vb, double duration, double fraction);
// Translation linear and rotation slerped with the same fraction (the motion model without velocities).
Eigen::Isometry3d interpolate_pose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double fraction);

class TrajectoryRecord {
 public:
  // Files are created (truncated) at once. `max_bridged` (> 0): gaps of at most this many frames are
  // interpolated, longer ones keep their predictions; 0: no gap is interpolated.
  struct Files {
    std::filesystem::path trajectory, keyframes, status;
  };
  TrajectoryRecord(Files files, int max_bridged);
  ~TrajectoryRecord();
  TrajectoryRecord(const TrajectoryRecord&) = delete;
  TrajectoryRecord& operator=(const TrajectoryRecord&) = delete;

  // The next frame (in order). `merge` (applied before the frame is added) moves the frames of a merged segment.
  void add(FrameRecord frame, const std::optional<SegmentMerge>& merge = std::nullopt);

  const std::vector<FrameRecord>& frames() const { return frames_; }
  int frames_bridged() const;
  int rewrites() const { return rewrites_; }

 private:
  // Interpolates every closed gap whose end velocities can be measured; true when a pose changed.
  bool bridge_gaps();
  std::optional<Velocity> velocity_at(std::size_t frame, int direction) const;
  void append(const FrameRecord& frame);
  void rewrite();

  // One output file, appended to and flushed line by line.
  struct Output {
    std::filesystem::path path;
    std::FILE* file = nullptr;
  };
  static std::string trajectory_line(const FrameRecord& frame);  // empty for a frame without a pose
  static std::string keyframe_line(const FrameRecord& frame);    // empty for a frame that is no keyframe
  static std::string status_line(const FrameRecord& frame);

  int max_bridged_;
  std::vector<FrameRecord> frames_;
  Output trajectory_, keyframes_, status_;
  int rewrites_ = 0;
};

}  // namespace vkvo::system
