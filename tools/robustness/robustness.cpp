#include "tools/robustness/robustness.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "eval/evaluate.hpp"
#include "eval/plot.hpp"
#include "io/dataset.hpp"
#include "io/frame_status.hpp"
#include "io/run_summary.hpp"
#include "system/pipeline.hpp"
#include "tools/synth/perturb.hpp"

namespace vkvo::robustness {
namespace {

namespace fs = std::filesystem;
using synth::EventKind;

synth::IlluminationEvent event(EventKind kind, int first, int last, double gain) {
  synth::IlluminationEvent e = synth::make_event(kind, first, last);
  e.gain = gain;
  return e;
}

// rmse of one block of the evaluation JSON, 0 when absent or empty.
double rmse_of(const nlohmann::json& evaluation, const char* part, const char* stats) {
  if (!evaluation.contains(part) || !evaluation[part].contains(stats)) return 0.0;
  const auto& s = evaluation[part][stats];
  return s["count"].get<std::size_t>() > 0 ? s["rmse"].get<double>() : 0.0;
}

// The poses of `trajectory` whose timestamps `other` has too (both sorted by time, as the runs write them).
io::Trajectory at_common_times(const io::Trajectory& trajectory, const io::Trajectory& other) {
  constexpr double kSameTime = 1e-6;  // s: both runs read the timestamps from the same files
  io::Trajectory common;
  auto it = other.begin();
  for (const auto& pose : trajectory) {
    while (it != other.end() && it->t < pose.t - kSameTime) ++it;
    if (it != other.end() && std::abs(it->t - pose.t) <= kSameTime) common.push_back(pose);
  }
  return common;
}

struct Plotted {
  std::string title;
  std::vector<Eigen::Vector3d> estimate, groundtruth;
};

void write_plot(const fs::path& png, const std::vector<Plotted>& runs) {
  if (runs.empty()) return;
  constexpr int kTileWidth = 500, kTileHeight = 400, kColumns = 4;
  const int rows = (static_cast<int>(runs.size()) + kColumns - 1) / kColumns;
  const int columns = std::min<int>(kColumns, static_cast<int>(runs.size()));
  cv::Mat canvas(rows * kTileHeight, columns * kTileWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  for (std::size_t i = 0; i < runs.size(); ++i) {
    eval::PlotOptions options;
    options.width = kTileWidth;
    options.height = kTileHeight;
    options.title = runs[i].title;
    const cv::Mat tile = eval::render_trajectory_plot(runs[i].estimate, runs[i].groundtruth, options);
    const int r = static_cast<int>(i) / kColumns, c = static_cast<int>(i) % kColumns;
    tile.copyTo(canvas(cv::Rect(c * kTileWidth, r * kTileHeight, kTileWidth, kTileHeight)));
  }
  if (!cv::imwrite(png.string(), canvas)) throw std::runtime_error(fmt::format("cannot write {}", png.string()));
}

}  // namespace

std::vector<Scenario> standard_scenarios(int frames, double rate_hz) {
  if (frames < 4 || !(rate_hz > 0))
    throw std::invalid_argument(
        fmt::format("robustness: a sequence of {} frames at {} Hz is too short", frames, rate_hz));
  std::vector<Scenario> out;
  out.push_back({"clean", "the sequence as recorded", {}, 0.0, std::nullopt});
  const int middle = frames / 2;
  for (const double level : {0.0, 0.03}) {
    for (const double seconds : {0.5, 1.0, 2.0}) {
      const int length = std::max(1, static_cast<int>(std::lround(seconds * rate_hz)));
      if (length > frames / 3) continue;
      const int first = middle - length / 2, last = first + length - 1;
      Scenario s;
      s.name = fmt::format("off {}s {}%", seconds, static_cast<int>(std::lround(level * 100)));
      s.description = fmt::format("lights off for {} s (frames {}-{}) at {} % of the light{}", seconds, first, last,
                                  level * 100, level > 0 ? " with 2 DN of noise" : "");
      s.events = {event(EventKind::lights_off, first, last, level)};
      s.noise_sigma = level > 0 ? 2.0 : 0.0;
      s.dark = std::pair{first, last};
      out.push_back(std::move(s));
    }
  }
  out.push_back(
      {"dim 10%",
       fmt::format("light dimming slowly to 10 % over frames {}-{}, then staying there", frames / 4, frames / 2),
       {event(EventKind::dimming, frames / 4, frames / 2, 0.1)},
       0.0,
       std::nullopt});
  // Real darkness is not a scaled image: at a sixth of the light the sensor's read noise stays, so the signal to
  // noise ratio falls (EuRoC's ~80 DN scenes become ~13 DN against 2 DN of noise) and keypoints thin out.
  out.push_back({"dark noisy",
                 fmt::format("light dimming to 15 % over frames {}-{}, then staying there, with 2 DN of noise",
                             frames / 4, frames / 2),
                 {event(EventKind::dimming, frames / 4, frames / 2, 0.15)},
                 2.0,
                 std::nullopt});
  out.push_back({"gamma flicker",
                 fmt::format("tone curve v^0.5 / v^2 on alternate frames {}-{}", frames / 4, 3 * frames / 4),
                 {event(EventKind::gamma_flicker, frames / 4, 3 * frames / 4, 0.5)},
                 0.0,
                 std::nullopt});
  auto right = event(EventKind::stereo_exposure, 0, -1, 0.4);
  right.cameras = synth::CameraMask::right;
  out.push_back({"right darker", "the right camera at 40 % exposure throughout", {right}, 0.0, std::nullopt});
  auto step = event(EventKind::stereo_exposure, middle, -1, 0.35);
  step.cameras = synth::CameraMask::both;
  out.push_back({"exposure step",
                 fmt::format("both cameras at 35 % exposure from frame {} on", middle),
                 {step},
                 0.0,
                 std::nullopt});
  return out;
}

std::vector<Scenario> select_scenarios(const std::vector<Scenario>& all, const std::vector<std::string>& names) {
  if (names.empty()) return all;
  std::vector<Scenario> out;
  for (const std::string& name : names) {
    const auto it = std::find_if(all.begin(), all.end(), [&](const Scenario& s) { return s.name == name; });
    if (it == all.end()) {
      std::string known;
      for (const auto& s : all) known += (known.empty() ? "'" : ", '") + s.name + "'";
      throw std::invalid_argument(fmt::format("robustness: no scenario '{}' (scenarios: {})", name, known));
    }
    out.push_back(*it);
  }
  return out;
}

fs::path sequence_folder(const fs::path& dataset) {
  if (const auto root = io::EurocDataset::find_root(dataset))
    return root->filename() == "mav0" ? root->parent_path() : *root;
  if (const auto root = io::KittiDataset::find_root(dataset)) return *root;
  return dataset;
}

PairedAte paired_ate(const io::Trajectory& first, const io::Trajectory& second, const io::Trajectory& groundtruth,
                     const eval::EvalOptions& options) {
  const io::Trajectory first_common = at_common_times(first, second);
  const io::Trajectory second_common = at_common_times(second, first);
  const auto a = eval::evaluate(first_common, groundtruth, options);
  const auto b = eval::evaluate(second_common, groundtruth, options);
  return {.first_m = a.ate.translation_m.rmse, .second_m = b.ate.translation_m.rmse, .frames = a.associated_poses};
}

std::vector<ScenarioResult> run_benchmark(const fs::path& given_dataset, const system::VoConfig& config,
                                          const std::vector<Scenario>& scenarios,
                                          system::PointFrontend& feature_frontend,
                                          system::PointFrontend& stereo_frontend, const BenchmarkOptions& options) {
  fs::create_directories(options.out_dir);
  const fs::path dataset = sequence_folder(given_dataset);
  const fs::path sequences = options.out_dir / "sequences";
  std::vector<ScenarioResult> results;
  std::vector<Plotted> plots;
  for (const Scenario& scenario : scenarios) {
    fs::path input = dataset;
    if (!scenario.events.empty()) {
      // The copy sits where the readers look for the ground truth of the original (EuRoC: <parent>/groundtruth).
      input = sequences / dataset.filename();
      fs::remove_all(input);
      fs::create_directories(sequences);
      if (const fs::path groundtruth = dataset.parent_path() / "groundtruth";
          fs::is_directory(groundtruth) && !fs::exists(sequences / "groundtruth"))
        fs::copy(groundtruth, sequences / "groundtruth", fs::copy_options::recursive);
      spdlog::info("robustness: {}: {}", scenario.name, scenario.description);
      synth::perturb_sequence(dataset, input, scenario.events, {.noise_sigma = scenario.noise_sigma});
    }
    std::vector<io::Trajectory> trajectories;  // of this scenario's runs that succeeded, with lines first
    std::optional<io::GroundTruth> groundtruth;
    const std::size_t first_result = results.size();
    for (const bool lines : options.ablate_lines ? std::vector<bool>{true, false} : std::vector<bool>{true}) {
      system::VoConfig run_config = config;
      run_config.tracking.use_lines = config.tracking.use_lines && lines;
      ScenarioResult r;
      r.scenario = scenario.name;
      r.lines = lines;
      std::string folder = scenario.name;
      std::replace_if(
          folder.begin(), folder.end(), [](char c) { return c == ' ' || c == '%' || c == '/'; }, '_');
      system::RunOptions run_options;
      run_options.output_dir = options.out_dir / (lines ? folder : folder + "-nolines");
      run_options.progress = false;
      try {
        const auto opened = io::open_dataset(input, run_config.dataset);
        const system::RunResult run =
            system::run_vo(*opened, run_config, feature_frontend, stereo_frontend, run_options);
        r.frames = run.frames;
        r.frames_untracked = run.frames - run.frames_tracked;
        // A run that never started a map has no trajectory to measure: failed, not "ATE 0".
        if (run.frames_tracked == 0) throw std::runtime_error(kNoFrameTracked);
        r.frames_bridged = static_cast<std::size_t>(run.frames_bridged);
        r.segments = run.segments;
        r.relocalisations = run.relocalisations;
        r.merges = run.merges;
        r.frames_per_second = run.wall_seconds > 0 ? static_cast<double>(run.frames) / run.wall_seconds : 0.0;
        r.point_inliers_median = run.inliers["points"]["median"].get<double>();
        r.line_inliers_median = run.inliers["lines"]["median"].get<double>();
        if (run.evaluation.is_null()) throw std::runtime_error("no ground truth found with the sequence");
        r.ate_m = rmse_of(run.evaluation, "trajectory", "ate_translation_m");
        r.ate_measured_m = rmse_of(run.evaluation, "trajectory_by_state", "measured_translation_m");
        r.ate_gap_m = rmse_of(run.evaluation, "trajectory_by_state", "bridged_translation_m");
        r.ate_keyframes_m = rmse_of(run.evaluation, "keyframes_refined", "ate_translation_m");
        if (!groundtruth) groundtruth = io::read_dataset_groundtruth(*opened);
        if (!groundtruth) throw std::runtime_error("no ground truth found with the sequence");
        io::Trajectory trajectory = io::read_tum(run.trajectory);
        if (lines) {
          const auto evaluation = eval::evaluate(trajectory, groundtruth->poses, eval::eval_options_for(*groundtruth));
          plots.push_back({fmt::format("{}: ATE {:.3f} m, {} seg.", scenario.name, r.ate_m, r.segments),
                           evaluation.aligned_estimate_positions, evaluation.groundtruth_positions});
        }
        trajectories.push_back(std::move(trajectory));
      } catch (const std::exception& e) {
        r.error = e.what();
        spdlog::error("robustness: {}{}: {}", scenario.name, lines ? "" : " (no lines)", e.what());
      }
      spdlog::info("robustness: {}{}: ATE {:.4f} m, {} untracked, {} segment(s), {} relocalisation(s)", scenario.name,
                   lines ? "" : " (no lines)", r.ate_m, r.frames_untracked, r.segments, r.relocalisations);
      results.push_back(std::move(r));
    }
    if (trajectories.size() == 2) {
      try {
        const PairedAte paired =
            paired_ate(trajectories[0], trajectories[1], groundtruth->poses, eval::eval_options_for(*groundtruth));
        results[first_result].ate_paired_m = paired.first_m;
        results[first_result + 1].ate_paired_m = paired.second_m;
        results[first_result].frames_paired = results[first_result + 1].frames_paired = paired.frames;
      } catch (const std::exception& e) {
        spdlog::warn("robustness: {}: no paired ATE with and without lines: {}", scenario.name, e.what());
      }
    }
    if (!scenario.events.empty() && !options.keep_sequences) fs::remove_all(input);
  }
  io::write_json_file(options.out_dir / "robustness.json", to_json(results));
  std::ofstream(options.out_dir / "robustness.md") << format_table(results);
  write_plot(options.out_dir / "robustness.png", plots);
  return results;
}

std::string format_table(const std::vector<ScenarioResult>& results) {
  const auto find = [&](const std::string& scenario, bool lines) -> const ScenarioResult* {
    for (const auto& r : results)
      if (r.scenario == scenario && r.lines == lines) return &r;
    return nullptr;
  };
  const ScenarioResult* clean = find("clean", true);
  const bool ablation = std::any_of(results.begin(), results.end(), [](const auto& r) { return !r.lines; });
  std::string table =
      "| scenario | ATE m | x clean | ATE tracked m | ATE gap m | untracked | segments | relocalised | inliers points "
      "/ lines |";
  table +=
      ablation ? " ATE w/o lines m | frames both estimated | ATE there with / w/o lines m | lines' gain |\n" : "\n";
  table +=
      ablation ? "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n" : "|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : results) {
    if (!r.lines) continue;
    if (!r.error.empty()) {
      table += fmt::format("| {} | failed: {} |{}\n", r.scenario, r.error,
                           ablation ? " | | | | | | | | | | |" : " | | | | | | |");
      continue;
    }
    const std::string ratio = clean && clean->ate_m > 0 ? fmt::format("{:.2f}", r.ate_m / clean->ate_m) : "-";
    const std::string gap = r.frames_bridged > 0 ? fmt::format("{:.4f}", r.ate_gap_m) : "-";
    table += fmt::format("| {} | {:.4f} | {} | {:.4f} | {} | {} | {} | {} | {:.0f} / {:.0f} |", r.scenario, r.ate_m,
                         ratio, r.ate_measured_m, gap, r.frames_untracked, r.segments, r.relocalisations,
                         r.point_inliers_median, r.line_inliers_median);
    if (ablation) {
      // The gain is measured where both runs estimated poses (falling back on the whole runs).
      const ScenarioResult* without = find(r.scenario, false);
      if (without && without->error.empty() && without->ate_m > 0) {
        const bool paired = r.frames_paired > 0 && without->ate_paired_m > 0;
        const double with_ate = paired ? r.ate_paired_m : r.ate_m;
        const double without_ate = paired ? without->ate_paired_m : without->ate_m;
        table += fmt::format(" {:.4f} | {} | {} | {:+.0f} % |", without->ate_m,
                             paired ? fmt::format("{}", r.frames_paired) : "-",
                             paired ? fmt::format("{:.4f} / {:.4f}", with_ate, without_ate) : "-",
                             100.0 * (without_ate - with_ate) / without_ate);
      } else {
        table += " - | - | - | - |";
      }
    }
    table += "\n";
  }
  return table;
}

nlohmann::json to_json(const std::vector<ScenarioResult>& results) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& r : results)
    out.push_back({{"scenario", r.scenario},
                   {"lines", r.lines},
                   {"frames", r.frames},
                   {"frames_untracked", r.frames_untracked},
                   {"frames_bridged", r.frames_bridged},
                   {"segments", r.segments},
                   {"relocalisations", r.relocalisations},
                   {"merges", r.merges},
                   {"ate_m", r.ate_m},
                   {"ate_tracked_m", r.ate_measured_m},
                   {"ate_gap_m", r.ate_gap_m},
                   {"ate_keyframes_refined_m", r.ate_keyframes_m},
                   {"frames_per_second", r.frames_per_second},
                   {"point_inliers_median", r.point_inliers_median},
                   {"line_inliers_median", r.line_inliers_median},
                   {"ate_paired_m", r.ate_paired_m},
                   {"frames_paired", r.frames_paired},
                   {"error", r.error}});
  return out;
}

}  // namespace vkvo::robustness
