#pragma once
// One call that associates, aligns and measures an estimate against ground truth, plus its JSON and table forms.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "eval/alignment.hpp"
#include "eval/metrics.hpp"
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

struct EvaluationResult {
  std::size_t estimate_poses = 0;
  std::size_t groundtruth_poses = 0;
  std::size_t associated_poses = 0;
  double duration_s = 0;                // first to last associated timestamp
  AlignmentMode alignment = AlignmentMode::se3;
  bool positions_only = false;
  AteResult ate;                         // ate.alignment is the transform applied to the estimate
  RpeResult rpe;                         // on the aligned estimate (so a sim3 scale is accounted for)
  DriftResult drift;                     // anchored at the first pose, with the sim3 scale when aligning sim3
  std::vector<Eigen::Vector3d> aligned_estimate_positions;  // for plots
  std::vector<Eigen::Vector3d> groundtruth_positions;
};

// Throws std::runtime_error when fewer than 3 poses associate (the message gives both time ranges).
EvaluationResult evaluate(const io::Trajectory& estimate, const io::Trajectory& groundtruth,
                          const EvalOptions& options = {});

nlohmann::json to_json(const ErrorStats& stats);
nlohmann::json to_json(const EvaluationResult& result);
// A fixed-width text table for the terminal.
std::string format_table(const EvaluationResult& result);

}  // namespace vkvo::eval
