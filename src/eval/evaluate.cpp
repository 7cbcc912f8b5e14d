#include "eval/evaluate.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include <fmt/format.h>

#include "eval/association.hpp"
#include "io/config.hpp"

namespace vkvo::eval {

namespace {
std::string time_range(const io::Trajectory& trajectory) {
  if (trajectory.empty()) return "empty";
  const auto [first, last] =
      std::minmax_element(trajectory.begin(), trajectory.end(), [](const auto& a, const auto& b) { return a.t < b.t; });
  return fmt::format("{:.3f} .. {:.3f} s ({} poses)", first->t, last->t, trajectory.size());
}
}  // namespace

EvalOptions eval_options_for(const io::GroundTruth& groundtruth) {
  EvalOptions options;
  options.positions_only = !groundtruth.has_orientation;
  return options;
}

EvalOptions load_eval_options(const YAML::Node& section) {
  EvalOptions options;
  const auto align = io::param<std::string>(section, "align", to_string(options.alignment));
  try {
    options.alignment = parse_alignment_mode(align);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(fmt::format("config key 'align': {}", e.what()));
  }
  io::read_param(section, "max_dt_s", options.max_dt_s);
  io::read_param(section, "rpe_lengths_m", options.rpe.lengths_m);
  const long step = io::param<long>(section, "rpe_step", 1);
  if (step < 1) throw std::runtime_error("config key 'rpe_step': must be >= 1");
  options.rpe.step = static_cast<std::size_t>(step);
  return options;
}

EvaluationResult evaluate(const io::Trajectory& estimate, const io::Trajectory& groundtruth,
                          const EvalOptions& options) {
  EvaluationResult result;
  result.estimate_poses = estimate.size();
  result.groundtruth_poses = groundtruth.size();
  result.alignment = options.alignment;
  result.positions_only = options.positions_only;
  const AssociatedPoses poses = associate(estimate, groundtruth, options.max_dt_s);
  result.associated_poses = poses.size();
  if (poses.size() < 3)
    throw std::runtime_error(
        fmt::format("only {} poses associate within {:.3f} s: estimate {}, ground truth {} (same clock? same units?)",
                    poses.size(), options.max_dt_s, time_range(estimate), time_range(groundtruth)));
  result.duration_s = poses.t.back() - poses.t.front();

  result.ate = compute_ate(poses, options.alignment, options.positions_only);
  const auto aligned = transform_poses(result.ate.alignment, poses.estimate);
  RpeOptions rpe = options.rpe;
  rpe.positions_only = rpe.positions_only || options.positions_only;
  result.rpe = compute_rpe(aligned, poses.groundtruth, rpe);
  result.drift = compute_drift(poses, result.ate.alignment.scale,
                               options.positions_only ? std::optional(result.ate.alignment.rotation) : std::nullopt);
  result.aligned_estimate_positions = positions(aligned);
  result.groundtruth_positions = positions(poses.groundtruth);
  return result;
}

StateEvaluation evaluate_by_state(const io::Trajectory& estimate, const std::vector<io::FrameStatus>& status,
                                  const io::Trajectory& groundtruth, const EvalOptions& options) {
  // A TUM timestamp (a double of seconds since the epoch) keeps about 0.2 us: match the nearest line within 1 ms.
  std::map<std::int64_t, const io::FrameStatus*> by_time;
  for (const auto& s : status) by_time[s.timestamp_ns] = &s;
  const auto status_at = [&](double t) -> const io::FrameStatus* {
    const auto t_ns = static_cast<std::int64_t>(std::llround(t * 1e9));
    const auto after = by_time.lower_bound(t_ns);
    const io::FrameStatus* best = nullptr;
    std::int64_t best_dt = 1'000'000;
    const auto consider = [&](auto it) {
      if (const std::int64_t dt = std::llabs(it->first - t_ns); dt <= best_dt) best = it->second, best_dt = dt;
    };
    if (after != by_time.end()) consider(after);
    if (after != by_time.begin()) consider(std::prev(after));
    return best;
  };
  const AssociatedPoses poses = associate(estimate, groundtruth, options.max_dt_s);
  StateEvaluation result;
  AssociatedPoses measured;
  std::vector<std::string> states(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const io::FrameStatus* line = status_at(poses.t[i]);
    if (!line) {
      ++result.without_status;
      continue;
    }
    states[i] = line->state;
    if (states[i] == "tracked" || states[i] == "relocalised") {
      measured.t.push_back(poses.t[i]);
      measured.estimate.push_back(poses.estimate[i]);
      measured.groundtruth.push_back(poses.groundtruth[i]);
    }
  }
  if (measured.size() < 3)
    throw std::runtime_error(
        fmt::format("only {} tracked or relocalised poses associate with the ground truth", measured.size()));
  const Similarity alignment = compute_ate(measured, options.alignment, true).alignment;
  std::vector<double> measured_errors, bridged_errors, lost_errors;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const double error =
        (alignment.apply(Eigen::Vector3d(poses.estimate[i].translation())) - poses.groundtruth[i].translation()).norm();
    if (states[i] == "tracked" || states[i] == "relocalised")
      measured_errors.push_back(error);
    else if (states[i] == "bridged")
      bridged_errors.push_back(error);
    else if (states[i] == "lost")
      lost_errors.push_back(error);
  }
  result.measured = compute_stats(measured_errors);
  result.bridged = compute_stats(bridged_errors);
  result.lost = compute_stats(lost_errors);
  return result;
}

nlohmann::json to_json(const StateEvaluation& result) {
  return {{"alignment", "fitted on the tracked and relocalised poses"},
          {"measured_translation_m", to_json(result.measured)},
          {"bridged_translation_m", to_json(result.bridged)},
          {"lost_translation_m", to_json(result.lost)},
          {"poses_without_status", result.without_status}};
}

nlohmann::json to_json(const ErrorStats& stats) {
  return {{"count", stats.count}, {"rmse", stats.rmse}, {"mean", stats.mean}, {"median", stats.median},
          {"std", stats.std},     {"min", stats.min},   {"max", stats.max}};
}

nlohmann::json to_json(const EvaluationResult& result) {
  // Rotation errors are null where a trajectory gives positions only.
  const auto rotation_or_null = [&](const nlohmann::json& value) {
    return result.positions_only ? nlohmann::json(nullptr) : value;
  };
  nlohmann::json segments = nlohmann::json::array();
  for (const auto& segment : result.rpe.segments)
    segments.push_back({{"length_m", segment.length_m},
                        {"count", segment.count},
                        {"translation_percent", segment.translation_percent},
                        {"rotation_deg_per_m", rotation_or_null(segment.rotation_deg_per_m)}});
  const auto& a = result.ate.alignment;
  std::vector<double> rotation(a.rotation.data(), a.rotation.data() + 9);  // column-major
  return {
      {"poses",
       {{"estimate", result.estimate_poses},
        {"groundtruth", result.groundtruth_poses},
        {"associated", result.associated_poses},
        {"duration_s", result.duration_s},
        {"positions_only", result.positions_only}}},
      {"alignment",
       {{"mode", to_string(result.alignment)},
        {"scale", a.scale},
        {"translation", {a.translation.x(), a.translation.y(), a.translation.z()}},
        {"rotation_column_major", rotation}}},
      {"ate_translation_m", to_json(result.ate.translation_m)},
      {"ate_rotation_deg", rotation_or_null(to_json(result.ate.rotation_deg))},
      {"rpe",
       {{"definition",
         result.positions_only
             ? "positions only: mean over segments of |d_est - d_gt|/L, d the displacement over the segment, "
               "aligned estimate"
             : "KITTI-style: mean over segments of |t_err|/L and angle(R_err)/L, aligned estimate"},
        {"count", result.rpe.count},
        {"translation_percent", result.rpe.translation_percent},
        {"rotation_deg_per_m", rotation_or_null(result.rpe.rotation_deg_per_m)},
        {"segments", segments}}},
      {"drift",
       {{"definition", result.positions_only ? "|p_est_last - p_gt_last| / gt path length, estimate turned "
                                               "by the ATE rotation and anchored at the first position"
                                             : "|p_est_last - p_gt_last| / gt path length, estimate "
                                               "anchored at the first pose"},
        {"final_error_m", result.drift.final_error_m},
        {"path_length_m", result.drift.path_length_m},
        {"percent", result.drift.percent}}},
  };
}

std::string format_table(const EvaluationResult& r) {
  std::string out;
  out += fmt::format("poses: {} estimate, {} ground truth, {} associated over {:.2f} s; alignment {}", r.estimate_poses,
                     r.groundtruth_poses, r.associated_poses, r.duration_s, to_string(r.alignment));
  if (r.alignment == AlignmentMode::sim3) out += fmt::format(" (scale {:.4f})", r.ate.alignment.scale);
  out += "\n\n";
  out += fmt::format("{:<22}{:>10}{:>10}{:>10}{:>10}{:>10}\n", "metric", "rmse", "mean", "median", "std", "max");
  const auto row = [&](const char* name, const ErrorStats& s) {
    out += fmt::format("{:<22}{:>10.4f}{:>10.4f}{:>10.4f}{:>10.4f}{:>10.4f}\n", name, s.rmse, s.mean, s.median, s.std,
                       s.max);
  };
  row("ATE trans [m]", r.ate.translation_m);
  if (r.positions_only)
    out += fmt::format("{:<22}{:>10}\n", "ATE rot [deg]", "n/a");
  else
    row("ATE rot [deg]", r.ate.rotation_deg);
  out += fmt::format("\n{:<22}{:>10}{:>14}{:>14}\n", "RPE segment [m]", "count", "trans [%]", "rot [deg/m]");
  const auto rpe_row = [&](const std::string& name, std::size_t count, double translation, double rotation) {
    out += fmt::format("{:<22}{:>10}{:>14.3f}{:>14}\n", name, count, translation,
                       r.positions_only ? std::string("n/a") : fmt::format("{:.4f}", rotation));
  };
  for (const auto& s : r.rpe.segments)
    rpe_row(fmt::format("{:.3f}", s.length_m), s.count, s.translation_percent, s.rotation_deg_per_m);
  rpe_row("all", r.rpe.count, r.rpe.translation_percent, r.rpe.rotation_deg_per_m);
  out += fmt::format(
      "\ndrift: {:.4f} m over {:.3f} m = {:.3f} % (final position error after anchoring the first "
      "{}, / ground-truth path length)\n",
      r.drift.final_error_m, r.drift.path_length_m, r.drift.percent, r.positions_only ? "position" : "pose");
  return out;
}

FileEvaluation evaluate_files(const std::filesystem::path& estimate, const std::filesystem::path& groundtruth,
                              const io::GroundTruthOptions& groundtruth_options, EvalOptions options,
                              const std::optional<std::filesystem::path>& frames) {
  FileEvaluation evaluation{.estimate_file = estimate, .groundtruth_file = groundtruth};
  evaluation.groundtruth = io::read_groundtruth(groundtruth, groundtruth_options);
  std::vector<double> estimate_times;  // a KITTI-format estimate shares the ground truth's clock
  if (groundtruth_options.kitti_times) estimate_times = io::read_kitti_times(*groundtruth_options.kitti_times);
  evaluation.estimate_format = io::detect_trajectory_format(estimate);
  const io::Trajectory estimated = io::read_trajectory(estimate, evaluation.estimate_format, estimate_times);
  options.positions_only =
      !evaluation.groundtruth.has_orientation || evaluation.estimate_format == io::TrajectoryFormat::positions;
  evaluation.result = evaluate(estimated, evaluation.groundtruth.poses, options);
  // A vkvo run's status file splits the errors by how each pose came about.
  evaluation.frames_file = frames;
  if (const auto beside = estimate.parent_path() / "frames.csv"; !frames && std::filesystem::exists(beside))
    evaluation.frames_file = beside;
  if (evaluation.frames_file)
    evaluation.by_state = evaluate_by_state(estimated, io::read_frame_status(*evaluation.frames_file),
                                            evaluation.groundtruth.poses, options);
  return evaluation;
}

nlohmann::json to_json(const FileEvaluation& evaluation) {
  const io::GroundTruth& gt = evaluation.groundtruth;
  nlohmann::json document = to_json(evaluation.result);
  document["estimate"] = evaluation.estimate_file.string();
  document["groundtruth"] = {{"path", evaluation.groundtruth_file.string()},
                             {"format", io::to_string(gt.format)},
                             {"frame", gt.frame == io::PoseFrame::body ? "body" : "camera"},
                             {"body_to_camera_applied", gt.body_to_camera_applied},
                             {"note", gt.note}};
  if (evaluation.by_state) {
    document["by_state"] = to_json(*evaluation.by_state);
    document["by_state"]["frames"] = evaluation.frames_file->string();
  }
  return document;
}

}  // namespace vkvo::eval
