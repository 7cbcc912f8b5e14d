#include "system/pipeline.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <thread>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include "eval/evaluate.hpp"
#include "eval/metrics.hpp"
#include "io/atomic_file.hpp"
#include "io/frame_status.hpp"
#include "io/map_ply.hpp"
#include "io/run_summary.hpp"
#include "io/trajectory.hpp"
#include "system/odometry_stream.hpp"
#include "system/stereo_odometry.hpp"
#include "system/trajectory_record.hpp"

namespace vkvo::system {
namespace {

class Progress {
 public:
  Progress(std::size_t total, bool enabled) : total_(total), enabled_(enabled), tty_(isatty(fileno(stderr)) != 0) {}
  void update(std::size_t done, int keyframes, const OdometryPose& r) {
    if (!enabled_) return;
    const double fps = double(done) / std::max(1e-9, watch_.ms() * 1e-3);
    const auto text =
        fmt::format("[{:>5}/{}] {:5.1f} frames/s | keyframes {:>4} | tracked points {:>4} lines {:>3}{}", done, total_,
                    fps, keyframes, r.tracked_points, r.tracked_lines, r.tracked ? "" : " | LOST");
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

// The keyframes' poses after the last bundle adjustment, at their frames' exact timestamps.
void write_refined_keyframes(const std::filesystem::path& file, const StereoOdometry& odometry,
                             const TrajectoryRecord& record) {
  std::map<std::size_t, std::int64_t> timestamp_of;
  for (const FrameRecord& f : record.frames()) timestamp_of[f.index] = f.timestamp_ns;
  io::TumTrajectoryWriter writer(file);
  for (const auto& [frame, pose] : odometry.refined_keyframes())
    if (const auto it = timestamp_of.find(frame); it != timestamp_of.end()) writer.write_ns(it->second, pose);
}

// What the pose estimates stood on, over the frames whose pose came from them (tracked or relocalised): how many
// points and lines were inliers, so that a run shows where lines carried weight (issue 40's measure).
nlohmann::json inlier_statistics(const std::vector<FrameRecord>& frames) {
  std::vector<int> points, lines;
  for (const FrameRecord& f : frames) {
    if (f.state != PoseState::tracked && f.state != PoseState::relocalised) continue;
    points.push_back(f.point_inliers);
    lines.push_back(f.line_inliers);
  }
  const auto describe = [](const std::vector<int>& values) {
    const eval::ErrorStats stats = eval::compute_stats({values.begin(), values.end()});  // zeros when empty
    return nlohmann::json{{"mean", stats.mean}, {"median", stats.median}, {"min", static_cast<int>(stats.min)}};
  };
  const auto with_lines = std::count_if(lines.begin(), lines.end(), [](int n) { return n > 0; });
  return {{"frames", points.size()},
          {"points", describe(points)},
          {"lines", describe(lines)},
          {"frames_with_line_inliers", with_lines}};
}

// ATE and the rest of the per-frame trajectory (whole, and split by frame state) and of the refined keyframes,
// against the ground truth found with the dataset; null when there is none or the run left too few poses.
nlohmann::json evaluate_outputs(const io::StereoDataset& dataset, const RunResult& result) {
  const auto groundtruth = io::read_dataset_groundtruth(dataset);
  if (!groundtruth) return nullptr;
  const eval::EvalOptions options = eval::eval_options_for(*groundtruth);
  nlohmann::json out = {{"groundtruth", dataset.groundtruth_path()->string()}};
  const auto attempt = [&](const char* key, const auto& evaluate) {
    try {
      out[key] = evaluate();
    } catch (const std::exception& e) {
      spdlog::warn("evaluation of the {} skipped: {}", key, e.what());
    }
  };
  attempt("trajectory",
          [&] { return eval::to_json(eval::evaluate(io::read_tum(result.trajectory), groundtruth->poses, options)); });
  attempt("trajectory_by_state", [&] {
    return eval::to_json(eval::evaluate_by_state(
        io::read_tum(result.trajectory), io::read_frame_status(result.frames_file), groundtruth->poses, options));
  });
  attempt("keyframes_refined", [&] {
    return eval::to_json(eval::evaluate(io::read_tum(result.keyframes_refined_file), groundtruth->poses, options));
  });
  return out;
}

// Landmarks that no keyframe observing them paired in its right image: the mono multi-view points
// (system/mono_points.hpp), and the lines triangulated from two keyframes (system/keyframe_lines.hpp) or through
// two mapped points on them (system/stereo_keyframe.hpp).
template <typename Landmarks, typename SeenInStereo>
std::size_t count_without_stereo(const map::Map& map, const Landmarks& landmarks, SeenInStereo seen_in_stereo) {
  std::size_t count = 0;
  for (const auto& [id, landmark] : landmarks) {
    bool stereo = false;
    for (const auto& [kf, index] : landmark.observations)
      if (const map::KeyFrame* keyframe = map.keyframe(kf); keyframe && seen_in_stereo(*keyframe, index)) stereo = true;
    count += !stereo;
  }
  return count;
}

}  // namespace

RunResult run_vo(const io::StereoDataset& dataset, const VoConfig& config, PointFrontend& feature_frontend,
                 PointFrontend& stereo_frontend, const RunOptions& options) {
  io::create_output_folder(options.output_dir);
  RunResult result;
  result.trajectory = options.output_dir / "trajectory.txt";
  result.keyframes_file = options.output_dir / "keyframes.txt";
  result.summary = options.output_dir / "summary.json";
  result.frames_file = options.output_dir / "frames.csv";
  result.keyframes_refined_file = options.output_dir / "keyframes_refined.txt";

  StereoOdometry odometry(config, dataset.calibration(), feature_frontend, stereo_frontend);
  TrajectoryRecord record({result.trajectory, result.keyframes_file, result.frames_file},
                          config.tracking.bridge_max_frames);

  Progress progress(dataset.size(), options.progress);
  const auto start = std::chrono::steady_clock::now();
  const double first_timestamp = dataset.empty() ? 0.0 : dataset.frame(0).timestamp_s;
  std::atomic<std::size_t> unreadable = 0;  // pairs skipped before the stages (image missing, corrupt, wrong size)
  Stopwatch since_last_output;
  const OdometryStream* stream_counts = nullptr;  // set before the first push: the pairs its stages failed on

  // On the optimisation thread, for every frame the stages got through.
  auto on_pose = [&](const OdometryPose& r) {
    const PoseState state = r.state == FrameState::relocalised ? PoseState::relocalised
                            : r.tracked                        ? PoseState::tracked
                                                               : PoseState::lost;
    const int bridged_before = record.frames_bridged();
    record.add({.index = r.frame_index,
                .timestamp_ns = r.timestamp_ns,
                .T_world_camera = r.T_world_camera,
                .state = state,
                .segment = r.segment,
                .keyframe = r.keyframe,
                .point_inliers = r.tracked_points,
                .line_inliers = r.tracked_lines,
                .note = r.note},
               r.merge);
    if (const int bridged = record.frames_bridged(); bridged > bridged_before)
      spdlog::info("tracking resumed: {} untracked frame(s) interpolated between the poses around the gap",
                   bridged - bridged_before);
    ++result.frames;
    if (r.tracked)
      ++result.frames_tracked;
    else
      result.untracked_frames.push_back(r.frame_index);
    result.last_frame_tracked = r.tracked;
    result.timing.add(Module::Frame, since_last_output.ms());
    since_last_output = Stopwatch();
    progress.update(result.frames + unreadable + stream_counts->failed(), odometry.keyframes(), r);
    if (options.observer) options.observer->frame(r);
  };

  {
    // The reader is this thread; the stream's threads run the feature and the optimisation stage.
    OdometryStream stream(
        odometry, on_pose,
        {.queue_capacity = static_cast<std::size_t>(config.tracking.queue_capacity), .when_full = QueueFull::block});
    stream_counts = &stream;
    std::size_t next = 0;
    for (; next < dataset.size() && !(options.stop && options.stop->load()); ++next) {
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
    result.stopped_early = next < dataset.size();
    stream.finish();
    result.frames_skipped = unreadable + stream.failed();
  }
  result.frames_bridged = record.frames_bridged();
  result.frames_uninitialised =
      static_cast<std::size_t>(std::count_if(record.frames().begin(), record.frames().end(),
                                             [](const FrameRecord& f) { return f.state == PoseState::uninitialised; }));
  std::vector<Eigen::Vector3d> centres;
  for (const FrameRecord& f : record.frames())
    if (f.state != PoseState::uninitialised) centres.push_back(f.T_world_camera.translation());
  result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  result.timing.merge(odometry.timing());  // the modules' samples; the run's own are the Frame ones
  const auto& map = odometry.map();
  result.keyframes = odometry.keyframes();
  result.tracking_losses = odometry.tracking_losses();
  result.segments = odometry.segments();
  result.segments_started = odometry.segments_started();
  result.relocalisations = odometry.relocalisations();
  result.merges = odometry.merges();
  result.segments_rebuilt = odometry.segments_rebuilt();
  result.map_points = map.points().size();
  result.map_lines = map.lines().size();
  result.map_mono_points = count_without_stereo(
      map, map.points(), [](const map::KeyFrame& kf, int keypoint) { return kf.is_stereo(keypoint); });
  result.map_mono_lines = count_without_stereo(map, map.lines(), [](const map::KeyFrame& kf, int line) {
    return kf.lines[static_cast<std::size_t>(line)].right.has_value();
  });
  const io::MapGeometry geometry = map_geometry(map, centres);
  io::write_map_ply(options.output_dir / "map.ply", geometry);
  if (options.observer) options.observer->finish(geometry);
  write_refined_keyframes(result.keyframes_refined_file, odometry, record);
  result.evaluation = evaluate_outputs(dataset, result);
  result.inliers = inlier_statistics(record.frames());

  nlohmann::json summary = options.extra_summary;
  summary["dataset"] = io::describe_dataset(dataset);
  summary["config"] = config.origin.string();
  summary["frames"] = result.frames;
  summary["frames_in_dataset"] = dataset.size();
  summary["stopped_early"] = result.stopped_early;
  summary["frames_skipped"] = result.frames_skipped;
  summary["frames_tracked"] = result.frames_tracked;
  summary["frames_bridged"] = result.frames_bridged;
  summary["keyframes"] = result.keyframes;
  summary["tracking_losses"] = result.tracking_losses;
  summary["map_segments"] = result.segments;
  summary["map_segments_started"] = result.segments_started;
  summary["relocalisations"] = result.relocalisations;
  summary["segment_merges"] = result.merges;
  summary["map_segments_rebuilt"] = result.segments_rebuilt;
  summary["frames_uninitialised"] = result.frames_uninitialised;
  const auto& reloc = odometry.relocalisation_stats();
  summary["relocalisation"] = {{"attempts", reloc.attempts},
                               {"candidates_matched", reloc.candidates_matched},
                               {"successes", reloc.successes},
                               {"successes_by_appearance", reloc.successes_by_source[0]},
                               {"successes_by_position", reloc.successes_by_source[1]},
                               {"successes_by_recency", reloc.successes_by_source[2]}};
  summary["map"] = {{"points", result.map_points},
                    {"mono_points", result.map_mono_points},
                    {"lines", result.map_lines},
                    {"mono_lines", result.map_mono_lines}};
  summary["lines_enabled"] = config.tracking.use_lines;
  summary["inliers_per_tracked_frame"] = result.inliers;
  summary["timing"] = result.timing.to_json(result.frames, result.wall_seconds);
  if (!result.evaluation.is_null()) summary["evaluation"] = result.evaluation;
  summary["outputs"] = {{"trajectory", result.trajectory.string()},
                        {"frames", result.frames_file.string()},
                        {"keyframes", result.keyframes_file.string()},
                        {"keyframes_refined", result.keyframes_refined_file.string()},
                        {"map", (options.output_dir / "map.ply").string()}};
  io::write_json_file(result.summary, summary);
  return result;
}

}  // namespace vkvo::system
