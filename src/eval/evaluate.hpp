#pragma once
// One call that associates, aligns and measures an estimate against ground truth, plus its JSON and table forms.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "eval/alignment.hpp"
#include "eval/metrics.hpp"
#include "io/frame_status.hpp"
#include "io/trajectory.hpp"

namespace vkvo::eval {

struct EvalOptions {
  AlignmentMode alignment = AlignmentMode::se3;
  double max_dt_s = 0.02;  // association tolerance
  RpeOptions rpe;
  // A trajectory gives positions only (io::GroundTruth::has_orientation false, or an estimate in that format): no
  // rotation errors, RPE on displacements, drift anchored at the first position (see metrics.hpp).
  bool positions_only = false;
};

// Reads an `eval:` config section: align (none|se3|sim3, "se3"), max_dt_s (0.02), rpe_lengths_m ([] = 10..50 %
// of the path length), rpe_step (1). Wrong types or an unknown alignment throw naming the key.
EvalOptions load_eval_options(const YAML::Node& section);
// The default options for measuring against `groundtruth`: positions only when it gives no orientation.
EvalOptions eval_options_for(const io::GroundTruth& groundtruth);

struct EvaluationResult {
  std::size_t estimate_poses = 0;
  std::size_t groundtruth_poses = 0;
  std::size_t associated_poses = 0;
  double duration_s = 0;  // first to last associated timestamp
  AlignmentMode alignment = AlignmentMode::se3;
  bool positions_only = false;
  AteResult ate;      // ate.alignment is the transform applied to the estimate
  RpeResult rpe;      // on the aligned estimate (so a sim3 scale is accounted for)
  DriftResult drift;  // anchored at the first pose, with the sim3 scale when aligning sim3
  std::vector<Eigen::Vector3d> aligned_estimate_positions;  // for plots
  std::vector<Eigen::Vector3d> groundtruth_positions;
};

// Throws std::runtime_error when fewer than 3 poses associate (the message gives both time ranges).
EvaluationResult evaluate(const io::Trajectory& estimate, const io::Trajectory& groundtruth,
                          const EvalOptions& options = {});

// A run's position errors split by how each pose came about (io::FrameStatus::state, matched by timestamp): the
// estimate is aligned on its tracked and relocalised poses only (what the VO measured), then the bridged poses
// (interpolated across a gap) and the lost ones (predicted) are measured under that alignment, so that a gap's
// guesses cannot pull the fit.
struct StateEvaluation {
  ErrorStats measured;  // tracked + relocalised
  ErrorStats bridged;
  ErrorStats lost;
  std::size_t without_status = 0;  // associated poses with no status line at their timestamp (left out)
};
// Throws std::runtime_error when fewer than 3 measured poses associate.
StateEvaluation evaluate_by_state(const io::Trajectory& estimate, const std::vector<io::FrameStatus>& status,
                                  const io::Trajectory& groundtruth, const EvalOptions& options = {});

nlohmann::json to_json(const ErrorStats& stats);
nlohmann::json to_json(const StateEvaluation& result);
nlohmann::json to_json(const EvaluationResult& result);
// A fixed-width text table for the terminal.
std::string format_table(const EvaluationResult& result);

// An estimate file against a ground-truth file (`vkvo eval`, Python's vkvo.evaluate): the ground truth read with
// `groundtruth_options` (its kitti_times also time a KITTI-format estimate), the estimate in whatever format it
// is, and `options.positions_only` set where either file gives positions only. Throws naming the file at fault.
struct FileEvaluation {
  std::filesystem::path estimate_file, groundtruth_file;
  io::GroundTruth groundtruth;
  io::TrajectoryFormat estimate_format = io::TrajectoryFormat::automatic;
  EvaluationResult result;
  // With the run's frames.csv (`frames`, or found beside the estimate): the errors per frame state.
  std::optional<std::filesystem::path> frames_file;
  std::optional<StateEvaluation> by_state;
};
FileEvaluation evaluate_files(const std::filesystem::path& estimate, const std::filesystem::path& groundtruth,
                              const io::GroundTruthOptions& groundtruth_options, EvalOptions options,
                              const std::optional<std::filesystem::path>& frames = std::nullopt);
// to_json(evaluation.result) with the two files and how the ground truth was read (`vkvo eval --json`).
nlohmann::json to_json(const FileEvaluation& evaluation);

}  // namespace vkvo::eval
