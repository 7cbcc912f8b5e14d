#include "system/pipeline.hpp"

#include <chrono>
#include <cstdio>
#include <memory>
#include <thread>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_pipeline.h>
#include <unistd.h>

#include "features/lines/line_detector.hpp"
#include "geometry/camera.hpp"
#include "io/map_ply.hpp"
#include "io/run_summary.hpp"
#include "io/trajectory.hpp"
#include "system/gap_bridge.hpp"
#include "system/tracker.hpp"

namespace vkvo::system {
namespace {

using FramePtr = std::shared_ptr<FrameInput>;

// The point task: left-image network, then matches against the last keyframe, or against the previous frame
// when the keyframe gives fewer than `min_num_match`.
void run_point_task(FrameInput& in, PointFrontend& frontend, const MatchReference& reference,
                    const std::shared_ptr<const features::PointFeatures>& previous, int min_num_match) {
  const Stopwatch pe;
  in.points = frontend.detect(in.left);
  in.pe_ms = pe.ms();
  const Stopwatch pm;
  if (reference.features) {
    in.matches = frontend.match(in.points, *reference.features);
    in.reference_keyframe = reference.keyframe;
  }
  if (previous && static_cast<int>(in.matches.count()) < min_num_match) {
    auto to_previous = frontend.match(in.points, *previous);
    if (to_previous.count() > in.matches.count()) {
      in.matches = std::move(to_previous);
      in.reference_keyframe = map::kInvalidId;
      in.matched_previous_frame = true;
    }
  }
  in.pm_ms = pm.ms();
}

class Progress {
 public:
  Progress(std::size_t total, bool enabled) : total_(total), enabled_(enabled), tty_(isatty(fileno(stderr)) != 0) {}
  void update(std::size_t done, int keyframes, const TrackResult& r) {
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

  const geometry::StereoRig rig(dataset.calibration());
  // World frame = the original (unrectified) left camera of the first frame; poses are written for that camera.
  const Eigen::Isometry3d T_rawleft_rect = rig.T_rawleft_rectified();
  const Eigen::Isometry3d T_rect_rawleft = T_rawleft_rect.inverse();
  Tracker tracker(config, rig.stereo(), stereo_frontend, T_rawleft_rect);
  const features::LineDetector line_detector(config.lines.detector);
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
  std::size_t next = 0;
  std::shared_ptr<const features::PointFeatures> previous;
  Stopwatch since_last_output;

  auto read = [&](tbb::flow_control& control) -> FramePtr {
    if (next >= dataset.size() || (options.stop && options.stop->load())) {
      control.stop();
      return nullptr;
    }
    auto in = std::make_shared<FrameInput>();
    const auto& frame = dataset.frame(next);
    in->index = next;
    in->sequence_index = frame.sequence_index;
    in->timestamp_ns = frame.timestamp_ns;
    in->timestamp_s = frame.timestamp_s;
    if (options.realtime) {
      const auto due = start + std::chrono::duration<double>(frame.timestamp_s - first_timestamp);
      std::this_thread::sleep_until(due);
    }
    try {
      const auto images = dataset.load(next);
      rig.rectify(images.left, images.right, in->left, in->right);
    } catch (const std::exception& e) {
      spdlog::error("frame {} skipped: {}", next, e.what());
      in->read_failed = true;
    }
    ++next;
    return in;
  };

  auto features = [&](FramePtr in) -> FramePtr {
    if (in->read_failed) return in;
    try {
      const MatchReference reference = tracker.reference();
      tbb::parallel_invoke(
          [&] { run_point_task(*in, feature_frontend, reference, previous, config.tracking.min_num_match); },
          [&] {
            if (!config.tracking.use_lines) return;
            const Stopwatch le;
            in->lines = line_detector.detect(in->left);
            in->le_ms = le.ms();
          });
      previous = std::make_shared<const features::PointFeatures>(in->points);
    } catch (const std::exception& e) {
      spdlog::error("frame {}: feature stage failed: {}", in->index, e.what());
      in->read_failed = true;
    }
    return in;
  };

  auto optimise = [&](FramePtr in) {
    if (in->read_failed) {
      ++result.frames_skipped;
      return;
    }
    result.timing.add(Module::PE, in->pe_ms);
    if (in->le_ms > 0) result.timing.add(Module::LE, in->le_ms);
    if (in->pm_ms > 0) result.timing.add(Module::PM, in->pm_ms);
    TrackResult r;
    try {
      r = tracker.track(*in, result.timing);
    } catch (const std::exception& e) {
      spdlog::error("frame {}: optimisation stage failed: {}", in->index, e.what());
      ++result.frames_skipped;
      return;
    }
    const Eigen::Isometry3d T_world_cam0 = r.T_world_camera * T_rect_rawleft;
    write_poses(gap_bridge.push({.timestamp_ns = in->timestamp_ns, .T_world_camera = T_world_cam0, .tracked = r.tracked}));
    if (r.keyframe) keyframes.write_ns(in->timestamp_ns, T_world_cam0);
    ++result.frames;
    if (r.tracked)
      ++result.frames_tracked;
    else
      result.untracked_frames.push_back(in->index);
    result.last_frame_tracked = r.tracked;
    result.timing.add(Module::Frame, since_last_output.ms());
    since_last_output = Stopwatch();
    progress.update(result.frames + result.frames_skipped, tracker.keyframes(), r);
  };

  tbb::parallel_pipeline(static_cast<std::size_t>(config.tracking.queue_capacity) + 1,
                         tbb::make_filter<void, FramePtr>(tbb::filter_mode::serial_in_order, read) &
                             tbb::make_filter<FramePtr, FramePtr>(tbb::filter_mode::serial_in_order, features) &
                             tbb::make_filter<FramePtr, void>(tbb::filter_mode::serial_in_order, optimise));
  write_poses(gap_bridge.flush());  // a gap still open at the end keeps its predicted poses
  result.frames_bridged = gap_bridge.frames_bridged();
  result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const auto& map = tracker.map();
  result.keyframes = tracker.keyframes();
  result.tracking_losses = tracker.tracking_losses();
  result.segments = tracker.segments();
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
