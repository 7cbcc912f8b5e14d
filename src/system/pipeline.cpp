#include "system/pipeline.hpp"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <memory>
#include <thread>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include "io/map_ply.hpp"
#include "io/run_summary.hpp"
#include "io/trajectory.hpp"
#include "system/gap_bridge.hpp"
#include "system/odometry_stream.hpp"
#include "system/stereo_odometry.hpp"

namespace vkvo::system {
namespace {

class Progress {
 public:
  Progress(std::size_t total, bool enabled) : total_(total), enabled_(enabled), tty_(isatty(fileno(stderr)) != 0) {}
  void update(std::size_t done, int keyframes, const OdometryPose& r) {
    if (!enabled_) return;
    const double fps = double(done) / std::max(1e-9, watch_.ms() * 1e-3);
    const auto text = fmt::format("[{:>5}/{}] {:5.1f} frames/s | keyframes {:>4} | tracked points {:>4} lines {:>3}{}",
                                  done, total_, fps, keyframes, r.tracked_points, r.tracked_lines,
                                  r.tracked ? "" : " | LOST");
    if (tty_) {
      std::fprintf(stderr, "\r%s", text.c_str());
      std::fflush(stderr);
    } else if (done % 10 == 0 || done == total_) {
      spdlog::info("{}", text);
    }
  }
  ~Progress() {
    if (enabled_ && tty_) std::fprintf(stderr, "\n");
  }

 private:
  std::size_t total_;
  bool enabled_, tty_;
  Stopwatch watch_;
};

io::MapGeometry map_geometry(const map::Map& map, const std::vector<Eigen::Vector3d>& centres) {
  io::MapGeometry g;
  for (const auto& [id, p] : map.points())
    if (!p.bad) g.points.push_back(p.position);
  for (const auto& [id, l] : map.lines())
    if (!l.bad && l.endpoints) g.lines.push_back(*l.endpoints);
  g.trajectory = centres;
  return g;
}

}  // namespace

RunResult run_vo(const io::StereoDataset& dataset, const VoConfig& config, PointFrontend& feature_frontend,
                 PointFrontend& stereo_frontend, const RunOptions& options) {
  std::filesystem::create_directories(options.output_dir);
  RunResult result;
  result.trajectory = options.output_dir / "trajectory.txt";
  result.keyframes_file = options.output_dir / "keyframes.txt";
  result.summary = options.output_dir / "summary.json";

  StereoOdometry odometry(config, dataset.calibration(), feature_frontend, stereo_frontend);
  io::TumTrajectoryWriter trajectory(result.trajectory);
  io::TumTrajectoryWriter keyframes(result.keyframes_file);
  std::vector<Eigen::Vector3d> centres;
  GapBridge gap_bridge(config.tracking.bridge_max_frames);
  auto write_poses = [&](const std::vector<FramePose>& poses) {
    for (const FramePose& pose : poses) {
      trajectory.write_ns(pose.timestamp_ns, pose.T_world_camera);
      centres.push_back(pose.T_world_camera.translation());
    }
    if (poses.size() > 1 && poses.front().bridged)
      spdlog::info("tracking resumed: {} untracked frame(s) interpolated between the poses around the gap",
                   poses.size() - 1);
  };

  Progress progress(dataset.size(), options.progress);
  const auto start = std::chrono::steady_clock::now();
  const double first_timestamp = dataset.empty() ? 0.0 : dataset.frame(0).timestamp_s;
  std::atomic<std::size_t> unreadable = 0;  // pairs skipped before the stages (image missing, corrupt, wrong size)
  Stopwatch since_last_output;
  const OdometryStream* stream_counts = nullptr;  // set before the first push: the pairs its stages failed on

  // On the optimisation thread, for every frame the stages got through.
  auto on_pose = [&](const OdometryPose& r) {
    write_poses(gap_bridge.push({.timestamp_ns = r.timestamp_ns, .T_world_camera = r.T_world_camera, .tracked = r.tracked}));
    if (r.keyframe) keyframes.write_ns(r.timestamp_ns, r.T_world_camera);
    ++result.frames;
    if (r.tracked)
      ++result.frames_tracked;
    else
      result.untracked_frames.push_back(r.frame_index);
    result.last_frame_tracked = r.tracked;
    result.timing.add(Module::Frame, since_last_output.ms());
    since_last_output = Stopwatch();
    progress.update(result.frames + unreadable + stream_counts->failed(), odometry.keyframes(), r);
  };

  {
    // The reader is this thread; the stream's threads run the feature and the optimisation stage.
    OdometryStream stream(odometry, on_pose,
                          {.queue_capacity = static_cast<std::size_t>(config.tracking.queue_capacity),
                           .when_full = QueueFull::block});
    stream_counts = &stream;
    for (std::size_t next = 0; next < dataset.size() && !(options.stop && options.stop->load()); ++next) {
      const auto& frame = dataset.frame(next);
      if (options.realtime) {
        const auto due = start + std::chrono::duration<double>(frame.timestamp_s - first_timestamp);
        std::this_thread::sleep_until(due);
      }
      try {
        const auto images = dataset.load(next);
        stream.push(images.left, images.right, frame.timestamp_ns, next);
      } catch (const std::exception& e) {
        spdlog::error("frame {} skipped: {}", next, e.what());
        ++unreadable;
      }
    }
    stream.finish();
    result.frames_skipped = unreadable + stream.failed();
  }
  write_poses(gap_bridge.flush());  // a gap still open at the end keeps its predicted poses
  result.frames_bridged = gap_bridge.frames_bridged();
  result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  result.timing.merge(odometry.timing());  // the modules' samples; the run's own are the Frame ones
  const auto& map = odometry.map();
  result.keyframes = odometry.keyframes();
  result.tracking_losses = odometry.tracking_losses();
  result.segments = odometry.segments();
  result.map_points = map.points().size();
  result.map_lines = map.lines().size();
  io::write_map_ply(options.output_dir / "map.ply", map_geometry(map, centres));

  nlohmann::json summary = options.extra_summary;
  summary["dataset"] = io::describe_dataset(dataset);
  summary["config"] = config.origin.string();
  summary["frames"] = result.frames;
  summary["frames_skipped"] = result.frames_skipped;
  summary["frames_tracked"] = result.frames_tracked;
  summary["frames_bridged"] = result.frames_bridged;
  summary["keyframes"] = result.keyframes;
  summary["tracking_losses"] = result.tracking_losses;
  summary["map_segments"] = result.segments;
  summary["map"] = {{"points", result.map_points}, {"lines", result.map_lines}};
  summary["lines_enabled"] = config.tracking.use_lines;
  summary["timing"] = result.timing.to_json(result.frames, result.wall_seconds);
  summary["outputs"] = {{"trajectory", result.trajectory.string()}, {"keyframes", result.keyframes_file.string()},
                        {"map", (options.output_dir / "map.ply").string()}};
  io::write_json_file(result.summary, summary);
  return result;
}

}  // namespace vkvo::system
