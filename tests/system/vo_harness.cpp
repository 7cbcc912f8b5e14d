#include "system/vo_harness.hpp"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include "io/dataset.hpp"
#include "io/trajectory.hpp"

namespace vkvo::test {

VoRun run_vo_with_opencv_frontend(const std::filesystem::path& dataset_dir, const system::VoConfig& config,
                                  const OpencvFrontendParams& frontend, const std::filesystem::path& out_dir) {
  OpencvFrontend feature_frontend(frontend), stereo_frontend(frontend);
  return run_vo_on(dataset_dir, config, feature_frontend, stereo_frontend, out_dir);
}

VoRun run_vo_on(const std::filesystem::path& dataset_dir, const system::VoConfig& config,
                system::PointFrontend& feature_frontend, system::PointFrontend& stereo_frontend,
                const std::filesystem::path& out_dir, const io::FrameRange& range) {
  const char* verbose = std::getenv("VKVO_TEST_VERBOSE");
  if (verbose && *verbose && *verbose != '0') spdlog::set_level(spdlog::level::debug);
  io::DatasetOptions options = config.dataset;
  options.range = range;
  const auto dataset = io::open_dataset(dataset_dir, options);
  system::RunOptions run_options;
  run_options.output_dir = out_dir;
  run_options.progress = false;
  VoRun run;
  run.result = system::run_vo(*dataset, config, feature_frontend, stereo_frontend, run_options);
  run.trajectory = io::read_tum(run.result.trajectory);
  auto groundtruth = io::read_dataset_groundtruth(*dataset);
  if (!groundtruth) throw std::runtime_error("dataset has no ground truth: " + dataset_dir.string());
  run.groundtruth = std::move(groundtruth->poses);
  run.evaluation = eval::evaluate(run.trajectory, run.groundtruth);
  spdlog::info(
      "VO on {}: {} frames, {} keyframes, {} losses, {} segments, ATE RMSE {:.4f} m (max {:.4f}), "
      "{:.2f} s wall ({:.1f} frames/s)",
      dataset_dir.string(), run.result.frames, run.result.keyframes, run.result.tracking_losses, run.result.segments,
      run.evaluation.ate.translation_m.rmse, run.evaluation.ate.translation_m.max, run.result.wall_seconds,
      double(run.result.frames) / std::max(1e-9, run.result.wall_seconds));
  return run;
}

eval::EvaluationResult evaluate_tracked_frames(const VoRun& run) {
  // Trajectory line i is frame i only when no frame was skipped.
  if (run.result.frames_skipped != 0 || run.trajectory.size() != run.result.frames)
    throw std::runtime_error("evaluate_tracked_frames: the run skipped frames");
  const auto& untracked = run.result.untracked_frames;
  io::Trajectory tracked;
  for (std::size_t i = 0; i < run.trajectory.size(); ++i)
    if (std::find(untracked.begin(), untracked.end(), i) == untracked.end()) tracked.push_back(run.trajectory[i]);
  return eval::evaluate(tracked, run.groundtruth);
}

io::MapGeometry read_map_ply(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error("read_map_ply: cannot open " + file.string());
  std::size_t vertices = 0;
  for (std::string line; std::getline(in, line) && line != "end_header";)
    if (line.rfind("element vertex ", 0) == 0) vertices = std::stoul(line.substr(15));
  io::MapGeometry map;
  std::vector<Eigen::Vector3d> line_ends;
  for (std::size_t v = 0; v < vertices; ++v) {
    Eigen::Vector3d p;
    int red = 0, green = 0, blue = 0;
    if (!(in >> p.x() >> p.y() >> p.z() >> red >> green >> blue))
      throw std::runtime_error("read_map_ply: truncated vertex list in " + file.string());
    if (red == 200)
      map.points.push_back(p);  // light grey: map points
    else if (red == 255)
      line_ends.push_back(p);  // red: line endpoints, in pairs
    else
      map.trajectory.push_back(p);  // green: camera path
  }
  for (std::size_t e = 0; e + 1 < line_ends.size(); e += 2) map.lines.emplace_back(line_ends[e], line_ends[e + 1]);
  return map;
}

void expect_every_frame_tracked(const VoRun& run, std::size_t frames) {
  EXPECT_EQ(run.result.frames, frames);
  EXPECT_EQ(run.result.frames_skipped, 0u);
  EXPECT_EQ(run.result.frames_tracked, frames);
  EXPECT_EQ(run.result.tracking_losses, 0);
  EXPECT_EQ(run.result.segments, 1);
  EXPECT_EQ(run.evaluation.associated_poses, frames);
}

}  // namespace vkvo::test
