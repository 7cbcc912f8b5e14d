#include "system/vo_harness.hpp"

#include <cstdlib>

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
  io::DatasetOptions options;
  options.camera_overrides = config.camera;
  options.range = range;
  const auto dataset = io::open_dataset(dataset_dir, options);
  system::RunOptions run_options;
  run_options.output_dir = out_dir;
  run_options.progress = false;
  VoRun run;
  run.result = system::run_vo(*dataset, config, feature_frontend, stereo_frontend, run_options);
  run.trajectory = io::read_tum(run.result.trajectory);
  const auto groundtruth = io::read_dataset_groundtruth(*dataset);
  if (!groundtruth) throw std::runtime_error("dataset has no ground truth: " + dataset_dir.string());
  run.evaluation = eval::evaluate(run.trajectory, groundtruth->poses);
  spdlog::info("VO on {}: {} frames, {} keyframes, {} losses, {} segments, ATE RMSE {:.4f} m (max {:.4f}), "
               "{:.2f} s wall ({:.1f} frames/s)",
               dataset_dir.string(), run.result.frames, run.result.keyframes, run.result.tracking_losses,
               run.result.segments, run.evaluation.ate.translation_m.rmse, run.evaluation.ate.translation_m.max,
               run.result.wall_seconds, double(run.result.frames) / std::max(1e-9, run.result.wall_seconds));
  return run;
}

}  // namespace vkvo::test
