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
#include "system/point_frontend.hpp"
#include "system/timing.hpp"
#include "system/vo_config.hpp"

namespace vkvo::system {

struct RunOptions {
  std::filesystem::path output_dir;  // trajectory.txt, keyframes.txt, map.ply, summary.json
  bool realtime = false;             // play the sequence back at its recorded rate
  bool progress = true;              // progress bar on a terminal, log lines otherwise
  const std::atomic<bool>* stop = nullptr;  // set (e.g. by SIGINT) to end the run cleanly after the current frame
  nlohmann::json extra_summary;      // merged into summary.json (device, models, ...)
};

struct RunResult {
  std::size_t frames = 0;            // frames processed
  std::size_t frames_skipped = 0;    // unreadable images
  std::size_t frames_tracked = 0;    // frames whose pose came from the optimisation (the rest: predicted)
  // Frames whose pose was predicted, as FrameInput::index: the position in the processed range, not in the dataset.
  std::vector<std::size_t> untracked_frames;
  // Untracked frames whose written pose was interpolated across the gap once tracking resumed (GapBridge).
  int frames_bridged = 0;
  bool last_frame_tracked = false;
  int keyframes = 0;
  int tracking_losses = 0;
  int segments = 0;
  std::size_t map_points = 0, map_lines = 0;
  double wall_seconds = 0;
  TimingReport timing;
  std::filesystem::path trajectory;  // TUM, cam0 poses (raw left camera), one line per processed frame; an
                                     // untracked frame's line waits until its gap closes (GapBridge)
  std::filesystem::path keyframes_file;
  std::filesystem::path summary;
};

// `feature_frontend` serves the feature stage, `stereo_frontend` the keyframes' right images (two instances so
// the stages do not share network buffers; they may share one Vulkan context).
RunResult run_vo(const io::StereoDataset& dataset, const VoConfig& config, PointFrontend& feature_frontend,
                 PointFrontend& stereo_frontend, const RunOptions& options);

}  // namespace vkvo::system
