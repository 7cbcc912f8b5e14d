#pragma once
// The threaded VO (paper Fig. 2) on a dataset: this thread reads and queues the pairs, OdometryStream's two threads
// run the feature stage (the point task on the Vulkan device + matching against the last keyframe, falling back to
// the previous frame, in parallel with the line task on the CPU) and the optimisation stage (the Tracker), joined by
// bounded TBB queues. It is the VO a live camera gets (system/odometry_stream.hpp), plus the dataset reader and the
// outputs, written as they are produced.
#include <atomic>
#include <filesystem>
#include <functional>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/dataset.hpp"
#include "io/map_ply.hpp"
#include "system/point_frontend.hpp"
#include "system/stereo_odometry.hpp"
#include "system/timing.hpp"
#include "system/vo_config.hpp"

namespace vkvo::system {

// Follows a run as it goes (viz::VideoRecorder): every processed frame, in order, on the optimisation thread (so
// it must return quickly), then the final map once. A run that ends by an exception does not call finish.
class RunObserver {
 public:
  virtual ~RunObserver() = default;
  virtual void frame(const OdometryPose& pose) = 0;
  virtual void finish(const io::MapGeometry& map) = 0;
};

struct RunOptions {
  // trajectory.txt, frames.csv, keyframes.txt, keyframes_refined.txt, map.ply, summary.json
  std::filesystem::path output_dir;
  bool realtime = false;                    // play the sequence back at its recorded rate
  bool progress = true;                     // progress bar on a terminal, log lines otherwise
  const std::atomic<bool>* stop = nullptr;  // set (e.g. by SIGINT) to end the run cleanly after the current frame
  nlohmann::json extra_summary;             // merged into summary.json (device, models, ...)
  RunObserver* observer = nullptr;          // optional; must outlive the run
};

struct RunResult {
  std::size_t frames = 0;          // frames processed
  std::size_t frames_skipped = 0;  // unreadable images
  bool stopped_early = false;      // RunOptions::stop ended the run before the dataset's last frame
  std::size_t frames_tracked = 0;  // frames whose pose came from the optimisation (the rest: predicted)
  // Frames whose pose was predicted, as FrameInput::index: the position in the processed range, not in the dataset.
  std::vector<std::size_t> untracked_frames;
  // Untracked frames whose written pose was interpolated across the gap once tracking resumed (TrajectoryRecord).
  int frames_bridged = 0;
  std::size_t frames_uninitialised = 0;  // before the map first started: in frames.csv, not in the trajectory
  bool last_frame_tracked = false;
  int keyframes = 0;
  int tracking_losses = 0;
  int segments = 0;          // map segments left at the end
  int segments_started = 0;  // ... started during the run (the first included)
  int relocalisations = 0;   // frames found in the map again after a loss, merges included
  int merges = 0;            // young segments merged into older ones
  int segments_rebuilt = 0;  // segments started on lines, rebuilt once points sufficed (tracking.rebuild_thin_start)
  std::size_t map_points = 0, map_lines = 0;
  std::size_t map_mono_points = 0;  // map points that no keyframe matched in its right image (map.mono_points)
  std::size_t map_mono_lines = 0;   // ... map lines likewise (from two keyframes, or through two mapped points)
  double wall_seconds = 0;
  TimingReport timing;
  // TUM, cam0 poses (raw left camera), one line per processed frame from the first tracked one on; earlier lines
  // are rewritten when a gap closes or a segment merges (TrajectoryRecord).
  std::filesystem::path trajectory;
  std::filesystem::path frames_file;             // frames.csv: per frame index, timestamp, state, segment, inliers
  std::filesystem::path keyframes_file;          // keyframe poses as tracking made them (moved by merges)
  std::filesystem::path keyframes_refined_file;  // keyframe poses after the last bundle adjustment (AirVO's output)
  std::filesystem::path summary;
  // With ground truth beside the dataset: summary.json's "evaluation" (per-frame trajectory, split by frame state,
  // and the refined keyframes); null without.
  nlohmann::json evaluation;
  // summary.json's "inliers_per_tracked_frame": mean, median and min point and line inliers of the pose estimates.
  nlohmann::json inliers;
};

// `feature_frontend` serves the feature stage, `stereo_frontend` the keyframes' right images (two instances so
// the stages do not share network buffers; they may share one Vulkan context).
RunResult run_vo(const io::StereoDataset& dataset, const VoConfig& config, PointFrontend& feature_frontend,
                 PointFrontend& stereo_frontend, const RunOptions& options);

}  // namespace vkvo::system
