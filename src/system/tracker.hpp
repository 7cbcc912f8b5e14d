#pragma once
// The optimisation stage of the VO (paper Fig. 2, right): point-line association and line matching against the
// reference, initial pose estimation, the keyframe decision, and for new keyframes the right-image features,
// stereo matching, triangulation and local bundle adjustment. Tracking loss starts a new map segment at the
// predicted pose, so the trajectory stays continuous and the run never stops on a hard frame.
#include <memory>
#include <mutex>
#include <optional>

#include <Eigen/Geometry>

#include "features/lines/line_detector.hpp"
#include "features/lines/point_line_association.hpp"
#include "geometry/camera.hpp"
#include "map/map.hpp"
#include "system/frame_input.hpp"
#include "system/point_frontend.hpp"
#include "system/timing.hpp"
#include "system/vo_config.hpp"

namespace vkvo::system {

struct TrackResult {
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();  // rectified left camera
  bool tracked = false;        // pose from the optimisation (false: predicted)
  bool keyframe = false;
  bool new_segment = false;    // (re-)initialisation: a new map segment starts here
  int tracked_points = 0, tracked_lines = 0;
  int matches = 0;             // point matches to the reference
  bool rematched = false;      // the feature stage's reference was stale: matched again to the last keyframe
};

// The keyframe the feature stage matches new frames against.
struct MatchReference {
  map::Id keyframe = map::kInvalidId;
  std::shared_ptr<const features::PointFeatures> features;
};

class Tracker {
 public:
  // `stereo_frontend` runs the right-image network and the stereo matching of keyframes; `rig` gives the
  // rectified stereo camera; `T_world_first` is the pose the first keyframe gets.
  Tracker(const VoConfig& config, const geometry::StereoCamera& stereo, PointFrontend& stereo_frontend,
          const Eigen::Isometry3d& T_world_first = Eigen::Isometry3d::Identity());

  TrackResult track(const FrameInput& frame, TimingReport& timing);

  // Thread-safe: the feature stage reads it while this stage runs.
  MatchReference reference() const;

  const map::Map& map() const { return map_; }
  int keyframes() const { return static_cast<int>(map_.keyframes().size()); }
  int segments() const { return segments_; }
  int tracking_losses() const { return losses_; }

 private:
  struct Tracked {
    map::Frame frame;
    features::PointLineAssociation association;
    // The keyframe the frame's points were matched against and, per line of the frame, its partner line there
    // (-1: none). Unset when the reference was the previous frame or lines are off.
    map::Id reference_keyframe = map::kInvalidId;
    std::vector<int> reference_line_partner;
  };

  Tracked make_frame(const FrameInput& input, const Eigen::Isometry3d& pose, TimingReport& timing) const;
  // Right-image features + stereo triangulation, then the keyframe with its new landmarks and a local BA.
  // With `new_segment`, refuses frames with too few keypoints/stereo matches (returns false).
  bool add_keyframe(const FrameInput& input, Tracked& tracked, bool new_segment, TimingReport& timing);
  Eigen::Isometry3d predicted_pose() const;
  void publish_reference(map::Id keyframe, const features::PointFeatures& features);

  VoConfig config_;
  geometry::StereoCamera stereo_;
  PointFrontend* frontend_;
  features::LineDetector right_line_detector_;
  Eigen::Isometry3d T_world_first_;

  map::Map map_;
  bool initialised_ = false;
  std::optional<Tracked> last_frame_;
  Eigen::Isometry3d T_world_last_ = Eigen::Isometry3d::Identity();
  // The constant-velocity prior: the motion (T_last^-1 T_current) between the last two well-tracked frames. It is
  // kept through untracked frames, so a dark stretch is bridged by extrapolation rather than by standing still.
  std::optional<Eigen::Isometry3d> velocity_;
  int tracked_previous_ = 0;
  int frames_since_keyframe_ = 0;
  int segments_ = 0, losses_ = 0;

  mutable std::mutex reference_mutex_;
  MatchReference reference_;
};

}  // namespace vkvo::system
