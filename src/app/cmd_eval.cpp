// `vkvo eval`: compares an estimated trajectory with ground truth (ATE, RPE, drift), optional plot and JSON.
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "app/command.hpp"
#include "eval/evaluate.hpp"
#include "eval/plot.hpp"
#include "io/run_summary.hpp"
#include "io/trajectory.hpp"

namespace {

struct EvalCommandOptions {
  std::string estimate;
  std::string groundtruth;
  std::string align = "se3";
  double max_dt = 0.02;
  std::string plot;
  std::string json;
  std::string gt_frame = "auto";
  std::string gt_orientation = "auto";
  std::string body_to_camera;
  std::string kitti_times;
  std::vector<double> rpe_lengths;
  std::size_t rpe_step = 1;
  std::string frames;  // frames.csv of the run (default: beside the estimate, when there)
};

// The command line's names of the ground-truth choices. CLI11 checks the option against the names (its message
// names the option, the value and the choices), so the lookups in run_eval always find them.
const std::map<std::string, vkvo::io::PoseFrame> kFrameNames{{"auto", vkvo::io::PoseFrame::automatic},
                                                             {"body", vkvo::io::PoseFrame::body},
                                                             {"camera", vkvo::io::PoseFrame::camera}};
const std::map<std::string, vkvo::io::GroundTruthOrientation> kOrientationNames{
    {"auto", vkvo::io::GroundTruthOrientation::automatic},
    {"as-written", vkvo::io::GroundTruthOrientation::as_written},
    {"inverse", vkvo::io::GroundTruthOrientation::inverse},
    {"none", vkvo::io::GroundTruthOrientation::none}};

template <typename Choice>
std::vector<std::string> names_of(const std::map<std::string, Choice>& names) {
  std::vector<std::string> keys;
  for (const auto& entry : names) keys.push_back(entry.first);
  return keys;
}

int run_eval(const EvalCommandOptions& opts) {
  using namespace vkvo;
  io::GroundTruthOptions gt_options;
  gt_options.frame = kFrameNames.at(opts.gt_frame);
  if (!opts.body_to_camera.empty()) {
    gt_options.sensor_yaml = opts.body_to_camera;
    if (gt_options.frame == io::PoseFrame::automatic) gt_options.frame = io::PoseFrame::body;
  }
  if (!opts.kitti_times.empty()) gt_options.kitti_times = opts.kitti_times;
  gt_options.orientation = kOrientationNames.at(opts.gt_orientation);
  eval::EvalOptions options;
  options.alignment = eval::parse_alignment_mode(opts.align);
  options.max_dt_s = opts.max_dt;
  options.rpe.lengths_m = opts.rpe_lengths;
  options.rpe.step = opts.rpe_step;
  const eval::FileEvaluation evaluation =
      eval::evaluate_files(opts.estimate, opts.groundtruth, gt_options, options,
                           opts.frames.empty() ? std::nullopt : std::optional<std::filesystem::path>(opts.frames));
  const io::GroundTruth& gt = evaluation.groundtruth;
  const eval::EvaluationResult& result = evaluation.result;

  fmt::print("estimate:     {}\nground truth: {} ({}; {} frame)\n\n", opts.estimate, opts.groundtruth, gt.note,
             gt.frame == io::PoseFrame::body ? "body" : "camera");
  fmt::print("{}", eval::format_table(result));

  if (const auto& by_state = evaluation.by_state) {
    const auto row = [](const char* what, const eval::ErrorStats& s) {
      return s.count ? fmt::format("  {:<22} {:>6} {:>10.4f} {:>10.4f}\n", what, s.count, s.rmse, s.max)
                     : fmt::format("  {:<22} {:>6} {:>10} {:>10}\n", what, 0, "-", "-");
    };
    fmt::print(
        "\nby frame state ({}; aligned on the tracked and relocalised poses):\n  {:<22} {:>6} {:>10} {:>10}\n"
        "{}{}{}",
        evaluation.frames_file->string(), "", "poses", "RMSE m", "max m",
        row("tracked + relocalised", by_state->measured), row("bridged (gap)", by_state->bridged),
        row("lost (predicted)", by_state->lost));
  }

  if (!opts.plot.empty()) {
    eval::PlotOptions plot;
    plot.title = fmt::format("{}  ATE {:.3f} m ({} aligned)", std::filesystem::path(opts.estimate).filename().string(),
                             result.ate.translation_m.rmse, eval::to_string(options.alignment));
    eval::write_trajectory_plot(opts.plot, result.aligned_estimate_positions, result.groundtruth_positions, plot);
    spdlog::info("plot written to {}", opts.plot);
  }
  if (!opts.json.empty()) {
    io::write_json_file(opts.json, eval::to_json(evaluation));
    spdlog::info("report written to {}", opts.json);
  }
  return 0;
}

vkvo::app::CommandRegistration registration{
    {"eval", "compare a trajectory with ground truth: ATE, RPE, drift, plot", [](CLI::App& sub) {
       auto opts = std::make_shared<EvalCommandOptions>();
       sub.add_option("--estimate", opts->estimate, "estimated trajectory (TUM, EuRoC CSV, KITTI poses or positions)")
           ->required()
           ->check(CLI::ExistingFile);
       sub.add_option("--groundtruth", opts->groundtruth,
                      "ground truth: TUM, EuRoC CSV (state_groundtruth_estimate0 or EuRoC_left_cam), KITTI poses, "
                      "or positions only ('t x y z' / 'timestamp_ns,x,y,z': no rotation errors)")
           ->required()
           ->check(CLI::ExistingFile);
       sub.add_option("--align", opts->align, "alignment before measuring")
           ->check(CLI::IsMember({"none", "se3", "sim3"}))
           ->capture_default_str();
       sub.add_option("--max-dt", opts->max_dt, "association tolerance in seconds")->capture_default_str();
       sub.add_option("--plot", opts->plot, "write a top-view PNG of both trajectories");
       sub.add_option("--json", opts->json, "write the report as JSON");
       sub.add_option("--gt-frame", opts->gt_frame,
                      "frame of the ground-truth poses: auto (17-column EuRoC CSV = body), body or camera")
           ->check(CLI::IsMember(names_of(kFrameNames)))
           ->capture_default_str();
       sub.add_option("--body-to-camera", opts->body_to_camera,
                      "cam0 sensor.yaml whose T_BS converts body ground truth to the camera (default: "
                      "<gt dir>/../cam0/sensor.yaml when present)")
           ->check(CLI::ExistingFile);
       sub.add_option("--gt-orientation", opts->gt_orientation,
                      "ground-truth rotations: auto (as written; inverted for ORB-SLAM3's EuRoC_left_cam files, "
                      "which give world-to-camera rotations), as-written, inverse, none (positions only)")
           ->check(CLI::IsMember(names_of(kOrientationNames)))
           ->capture_default_str();
       sub.add_option("--kitti-times", opts->kitti_times, "KITTI times.txt for poses files (default: found or 10 Hz)")
           ->check(CLI::ExistingFile);
       sub.add_option("--rpe-lengths", opts->rpe_lengths,
                      "RPE segment lengths in metres (default: 10,20,..,50 % of the path length)");
       sub.add_option("--frames", opts->frames,
                      "the run's frames.csv: errors also per frame state (default: frames.csv beside the estimate)")
           ->check(CLI::ExistingFile);
       sub.add_option("--rpe-step", opts->rpe_step, "start an RPE segment every N poses")->capture_default_str();
       return std::function<int()>([opts] { return run_eval(*opts); });
     }}};

}  // namespace
