#pragma once
// The VO for live input: a camera driver (or a ROS callback, or a dataset reader) hands in raw stereo pairs one
// at a time and gets the camera pose back. It owns the stages of the paper's Fig. 2 for one stream:
//   prepare          - check and rectify the pair;
//   extract_features - the feature stage: the point task (network on the Vulkan device, matching against the last
//                      keyframe or else the previous frame) in parallel with the line task (CPU);
//   optimise         - the optimisation stage (Tracker): association, line matching, initial pose, keyframes, BA.
// track() runs the three in turn. A caller that wants the two stages to overlap, as run_vo does, runs
// extract_features of frame k+1 on one thread while optimise of frame k runs on another: each stage's calls must
// be serial among themselves and in frame order, and the two may run concurrently.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "features/lines/line_detector.hpp"
#include "geometry/camera.hpp"
#include "io/calibration.hpp"
#include "system/frame_input.hpp"
#include "system/frame_observations.hpp"
#include "system/point_frontend.hpp"
#include "system/timing.hpp"
#include "system/tracker.hpp"
#include "system/vo_config.hpp"

namespace vkvo::system {

struct OdometryPose {
  std::size_t frame_index = 0;  // the pair's number in the caller's stream (prepare's `index`)
  std::int64_t timestamp_ns = 0;
  // The raw (unrectified) left camera, cam0, in the world frame: cam0 at the first frame.
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();
  bool tracked = false;                 // false: predicted at the last velocity (the frame could not be tracked)
  FrameState state = FrameState::lost;  // tracked, relocalised or lost (= !tracked)
  bool keyframe = false;
  bool new_segment = false;  // the map (re)started here, after a tracking loss or at the first frame
  int segment = 0;           // the map segment whose world frame the pose is in
  // Set when this frame merged its segment into an older one: every earlier pose of segment `from` maps into the
  // world by merge->T_into_from (a caller keeping poses updates them; run_vo rewrites its files).
  std::optional<SegmentMerge> merge;
  int tracked_points = 0, tracked_lines = 0;
  std::string note;  // why no keyframe was made, or what relocalisation did
  // The frame's rectified left image and the roles of its keypoints and lines (shared: copying a pose is cheap).
  std::shared_ptr<const FrameObservations> observations;
};

class StereoOdometry {
 public:
  // `feature_frontend` serves the feature stage, `stereo_frontend` the keyframes' right images: two instances so
  // that the stages, which may run concurrently, do not share network buffers (they may share a Vulkan context).
  // Both must outlive this object.
  StereoOdometry(const VoConfig& config, const io::StereoCalibration& calibration, PointFrontend& feature_frontend,
                 PointFrontend& stereo_frontend);

  // One raw stereo pair (8-bit grey or BGR, the calibration's size) at `timestamp_ns`. Throws std::invalid_argument
  // for images it cannot use (empty, wrong size or type) without changing any state.
  OdometryPose track(const cv::Mat& left, const cv::Mat& right, std::int64_t timestamp_ns);

  // The stages (see the top of this file). `index` is the frame's position in the caller's stream (logs).
  FrameInput prepare(const cv::Mat& left, const cv::Mat& right, std::int64_t timestamp_ns, std::size_t index) const;
  void extract_features(FrameInput& frame);
  OdometryPose optimise(const FrameInput& frame);

  const geometry::StereoRig& rig() const { return rig_; }
  // The map, the timing and the counts below belong to the optimisation stage: read them on its thread (e.g. in
  // OdometryStream's callback) or while no frame is being optimised.
  const map::Map& map() const { return tracker_.map(); }
  // PE, LE, PM from the feature stage and LM, IPE, BA from the optimisation stage, one sample per frame that ran
  // the module (filled by optimise).
  const TimingReport& timing() const { return timing_; }
  int keyframes() const { return tracker_.keyframes(); }
  int tracking_losses() const { return tracker_.tracking_losses(); }
  int segments() const { return tracker_.segments(); }  // map segments now (after merges)
  int segments_started() const { return tracker_.segments_started(); }
  int relocalisations() const { return tracker_.relocalisations(); }
  int merges() const { return tracker_.merges(); }
  int segments_rebuilt() const { return tracker_.segments_rebuilt(); }
  const RelocalisationStats& relocalisation_stats() const { return tracker_.relocalisation_stats(); }
  // The map's keyframes as (frame index, raw left camera pose), in the state the last bundle adjustment left them.
  std::vector<std::pair<std::size_t, Eigen::Isometry3d>> refined_keyframes() const;

 private:
  VoConfig config_;
  geometry::StereoRig rig_;
  Eigen::Isometry3d T_rect_rawleft_;
  PointFrontend* feature_frontend_;
  Tracker tracker_;
  features::LineDetector line_detector_;
  std::shared_ptr<const features::PointFeatures> previous_;  // the feature stage's last frame
  TimingReport timing_;
  std::size_t next_index_ = 0;  // the index track() gives its next pair
};

}  // namespace vkvo::system
