#include "eval/evaluate.hpp"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "eval/association.hpp"
#include "io/config.hpp"

namespace vkvo::eval {

namespace {
std::string time_range(const io::Trajectory& trajectory) {
  if (trajectory.empty()) return "empty";
  const auto [first, last] = std::minmax_element(trajectory.begin(), trajectory.end(),
                                                 [](const auto& a, const auto& b) { return a.t < b.t; });
  return fmt::format("{:.3f} .. {:.3f} s ({} poses)", first->t, last->t, trajectory.size());
}
}  // namespace

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

EvaluationResult evaluate(const io::Trajectory& estimate, const io::Trajectory& groundtruth, const EvalOptions& options) {
  EvaluationResult result;
  result.estimate_poses = estimate.size();
  result.groundtruth_poses = groundtruth.size();
  result.alignment = options.alignment;
  result.positions_only = options.positions_only;
  const AssociatedPoses poses = associate(estimate, groundtruth, options.max_dt_s);
  result.associated_poses = poses.size();
  if (poses.size() < 3)
    throw std::runtime_error(fmt::format(
        "only {} poses associate within {:.3f} s: estimate {}, ground truth {} (same clock? same units?)",
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
      {"poses", {{"estimate", result.estimate_poses}, {"groundtruth", result.groundtruth_poses},
                 {"associated", result.associated_poses}, {"duration_s", result.duration_s},
                 {"positions_only", result.positions_only}}},
      {"alignment", {{"mode", to_string(result.alignment)}, {"scale", a.scale},
                     {"translation", {a.translation.x(), a.translation.y(), a.translation.z()}},
                     {"rotation_column_major", rotation}}},
      {"ate_translation_m", to_json(result.ate.translation_m)},
      {"ate_rotation_deg", rotation_or_null(to_json(result.ate.rotation_deg))},
      {"rpe", {{"definition",
                result.positions_only
                    ? "positions only: mean over segments of |d_est - d_gt|/L, d the displacement over the segment, "
                      "aligned estimate"
                    : "KITTI-style: mean over segments of |t_err|/L and angle(R_err)/L, aligned estimate"},
               {"count", result.rpe.count},
               {"translation_percent", result.rpe.translation_percent},
               {"rotation_deg_per_m", rotation_or_null(result.rpe.rotation_deg_per_m)},
               {"segments", segments}}},
      {"drift", {{"definition", result.positions_only ? "|p_est_last - p_gt_last| / gt path length, estimate turned "
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
  if (r.positions_only) out += fmt::format("{:<22}{:>10}\n", "ATE rot [deg]", "n/a");
  else row("ATE rot [deg]", r.ate.rotation_deg);
  out += fmt::format("\n{:<22}{:>10}{:>14}{:>14}\n", "RPE segment [m]", "count", "trans [%]", "rot [deg/m]");
  const auto rpe_row = [&](const std::string& name, std::size_t count, double translation, double rotation) {
    out += fmt::format("{:<22}{:>10}{:>14.3f}{:>14}\n", name, count, translation,
                       r.positions_only ? std::string("n/a") : fmt::format("{:.4f}", rotation));
  };
  for (const auto& s : r.rpe.segments)
    rpe_row(fmt::format("{:.3f}", s.length_m), s.count, s.translation_percent, s.rotation_deg_per_m);
  rpe_row("all", r.rpe.count, r.rpe.translation_percent, r.rpe.rotation_deg_per_m);
  out += fmt::format("\ndrift: {:.4f} m over {:.3f} m = {:.3f} % (final position error after anchoring the first "
                     "{}, / ground-truth path length)\n",
                     r.drift.final_error_m, r.drift.path_length_m, r.drift.percent,
                     r.positions_only ? "position" : "pose");
  return out;
}

}  // namespace vkvo::eval
