#pragma once
// The robustness benchmark: one sequence run clean and under a fixed set of photometric events (made with
// synth::perturb_sequence, so everything but the affected pixels is the original), each run evaluated against the
// sequence's ground truth. It answers what vkvo promises: does the VO stay on one map, and how much accuracy does
// each event cost. Run through `vkvo robustness`; the frontends are shared between the runs, so with a
// system::CachedFrontend the network runs only on the images an event changed.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "eval/evaluate.hpp"
#include "io/trajectory.hpp"
#include "system/point_frontend.hpp"
#include "system/vo_config.hpp"
#include "tools/synth/illumination.hpp"

namespace vkvo::robustness {

struct Scenario {
  std::string name;  // short, for tables and folder names
  std::string description;
  std::vector<synth::IlluminationEvent> events;  // none: the clean run
  double noise_sigma = 0;                        // Gaussian read noise (DN) on the affected frames
  // Frames with no usable light (0-based, inclusive), when the scenario has such a stretch: its frames are the
  // ones expected to be lost, reported apart.
  std::optional<std::pair<int, int>> dark;
};

// The fixed set for a sequence of `frames` frames at `rate_hz`, centred on its middle: clean; lights off for 0.5,
// 1 and 2 s at 0 % and at 3 % of the light with 2 DN of noise; a slow dimming to 10 % (from a quarter to half of
// the sequence, then staying there); the same dimming to 15 % with 2 DN of read noise (dark noisy); gamma flicker
// (0.5 / 2.0 on alternate frames) over the middle half; the right camera at 40 % exposure throughout; an exposure
// step to 35 % for both cameras from the middle on. Lights-off stretches longer than a third of the sequence are
// left out.
std::vector<Scenario> standard_scenarios(int frames, double rate_hz);
// The scenarios whose names are listed (all when `names` is empty); throws naming an unknown one.
std::vector<Scenario> select_scenarios(const std::vector<Scenario>& all, const std::vector<std::string>& names);

struct ScenarioResult {
  std::string scenario;
  bool lines = true;
  std::size_t frames = 0, frames_untracked = 0, frames_bridged = 0;
  int segments = 0, relocalisations = 0, merges = 0;
  double ate_m = 0;            // every frame
  double ate_measured_m = 0;   // tracked and relocalised frames (aligned on them)
  double ate_gap_m = 0;        // bridged frames, under that alignment (0 when none)
  double ate_keyframes_m = 0;  // refined keyframes
  double frames_per_second = 0;
  double point_inliers_median = 0, line_inliers_median = 0;  // per tracked frame: what the poses stood on
  // With ablate_lines: the ATE over the frames both the run with lines and the one without estimated, and their
  // count (a run that starts a map earlier or loses fewer frames is otherwise measured over other frames).
  double ate_paired_m = 0;
  std::size_t frames_paired = 0;
  std::string error;  // the run or its evaluation failed: what happened
};
// ScenarioResult::error of a run that never started a map: a measured outcome (the event defeated the VO), not a
// failure of the benchmark.
inline constexpr const char* kNoFrameTracked = "no frame tracked";

// Two runs of one sequence over the timestamps both estimated, each aligned to the ground truth on those alone.
struct PairedAte {
  double first_m = 0, second_m = 0;
  std::size_t frames = 0;
};
// Throws std::runtime_error when fewer than 3 common timestamps associate with the ground truth.
PairedAte paired_ate(const io::Trajectory& first, const io::Trajectory& second, const io::Trajectory& groundtruth,
                     const eval::EvalOptions& options);

struct BenchmarkOptions {
  std::filesystem::path out_dir;
  bool ablate_lines = false;    // every scenario also without lines
  bool keep_sequences = false;  // keep the perturbed copies (they are large)
};

// The sequence folder a dataset path names (the one holding mav0, or KITTI's image folders): the readers accept a
// wrapper folder around it, the perturbed copies are made of the sequence itself.
std::filesystem::path sequence_folder(const std::filesystem::path& dataset);

// Runs every scenario (the first should be the clean one: ratios are to it) and writes out_dir/<scenario>[-nolines]/
// (the run's outputs), robustness.md (the table), robustness.json and robustness.png (top views of each run against
// the ground truth).
std::vector<ScenarioResult> run_benchmark(const std::filesystem::path& dataset, const system::VoConfig& config,
                                          const std::vector<Scenario>& scenarios,
                                          system::PointFrontend& feature_frontend,
                                          system::PointFrontend& stereo_frontend, const BenchmarkOptions& options);

// The Markdown table: per scenario ATE, ratio to the clean run, ATE of the tracked frames and of the gap, untracked
// frames, segments at the end, relocalisations (and with ablate_lines, the ATE without lines and the lines' gain,
// measured over the frames both runs estimated).
std::string format_table(const std::vector<ScenarioResult>& results);
nlohmann::json to_json(const std::vector<ScenarioResult>& results);

}  // namespace vkvo::robustness
