#include "backend/local_ba.hpp"

#include <cmath>
#include <map>
#include <memory>
#include <set>

#include <ceres/loss_function.h>
#include <ceres/manifold.h>
#include <ceres/ordered_groups.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include "backend/cost_functions.hpp"

namespace vkvo::backend {

namespace {

using map::Id;

struct Observation {
  ceres::ResidualBlockId block = nullptr;
  Id landmark = map::kInvalidId;
  Id keyframe = map::kInvalidId;
  bool is_line = false;
  double chi2_threshold = 0;
  bool outlier = false;
};

// The window's variables, in storage that stays put while Ceres holds pointers into it.
struct Variables {
  std::map<Id, PoseBlock> poses;
  std::map<Id, Eigen::Vector3d> points;
  std::map<Id, Eigen::Matrix<double, 6, 1>> lines;
};

double unrobust_chi2(ceres::Problem& problem, ceres::ResidualBlockId block) {
  double cost = 0;
  if (!problem.EvaluateResidualBlock(block, false, &cost, nullptr, nullptr))
    return std::numeric_limits<double>::infinity();
  return 2.0 * cost;  // Ceres cost = 1/2 |r|^2
}

}  // namespace

LocalBAResult local_bundle_adjustment(map::Map& map, Id keyframe, const geometry::StereoCamera& stereo,
                                      const OptimizationParams& params) {
  LocalBAResult result;
  result.window = map.local_window(keyframe, params.window_size, params.min_covisible);
  const std::set<Id> in_window(result.window.begin(), result.window.end());

  Variables vars;
  for (Id kf_id : result.window) {
    const map::KeyFrame& kf = *map.keyframe(kf_id);
    vars.poses[kf_id] = PoseBlock::from_T_world_camera(kf.T_world_camera);
    for (Id p : kf.point_ids)
      if (const map::MapPoint* mp = map.point(p); mp && !mp->bad) vars.points.emplace(p, mp->position);
    for (Id l : kf.line_ids)
      if (const map::MapLine* ml = map.line(l); ml && !ml->bad) vars.lines.emplace(l, ml->line.normalized().vector());
  }
  std::set<Id> fixed;
  auto note_observers = [&](const auto& observations) {
    for (const auto& obs : observations)
      if (!in_window.count(obs.first)) fixed.insert(obs.first);
  };
  for (const auto& [id, X] : vars.points) note_observers(map.point(id)->observations);
  for (const auto& [id, L] : vars.lines) note_observers(map.line(id)->observations);
  if (fixed.empty()) fixed.insert(*in_window.begin());  // gauge: hold the oldest window keyframe
  for (Id kf_id : fixed) {
    vars.poses[kf_id] = PoseBlock::from_T_world_camera(map.keyframe(kf_id)->T_world_camera);
    result.fixed.push_back(kf_id);
  }
  result.num_points = static_cast<int>(vars.points.size());
  result.num_lines = static_cast<int>(vars.lines.size());

  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  const std::unique_ptr<ceres::Manifold> pose_manifold = make_pose_manifold();
  const std::unique_ptr<ceres::Manifold> line_manifold = make_line_manifold();
  const auto mono_point_loss = make_robust_loss(params.mono_point_chi2);
  const auto stereo_point_loss = make_robust_loss(params.stereo_point_chi2);
  const auto mono_line_loss = make_robust_loss(params.mono_line_chi2, params.line_weight);
  const auto stereo_line_loss = make_robust_loss(params.stereo_line_chi2, params.line_weight);
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();

  for (auto& [id, pose] : vars.poses) {
    problem.AddParameterBlock(pose.data(), 7, pose_manifold.get());
    ordering->AddElementToGroup(pose.data(), 1);
    if (fixed.count(id)) problem.SetParameterBlockConstant(pose.data());
  }

  std::vector<Observation> observations;
  for (auto& [id, X] : vars.points) {
    problem.AddParameterBlock(X.data(), 3);
    ordering->AddElementToGroup(X.data(), 0);
    for (const auto& [kf_id, index] : map.point(id)->observations) {
      const map::KeyFrame& kf = *map.keyframe(kf_id);
      PoseBlock& pose = vars.poses.at(kf_id);
      Observation obs{nullptr, id, kf_id, false, 0, false};
      if ((kf.T_world_camera.inverse() * X).z() <= 1e-6) {  // behind the camera: not usable, drop it
        obs.outlier = true;
        observations.push_back(obs);
        continue;
      }
      const PointMeasurement m{kf.keypoints[index], kf.right_x[index]};
      obs.chi2_threshold = m.stereo() ? params.stereo_point_chi2 : params.mono_point_chi2;
      obs.block =
          problem.AddResidualBlock(make_point_cost(stereo, m, params.pixel_sigma).release(),
                                   m.stereo() ? stereo_point_loss.get() : mono_point_loss.get(), pose.data(), X.data());
      observations.push_back(obs);
      ++result.point_observations;
    }
  }
  for (auto& [id, L] : vars.lines) {
    problem.AddParameterBlock(L.data(), 6, line_manifold.get());
    ordering->AddElementToGroup(L.data(), 0);
    for (const auto& [kf_id, index] : map.line(id)->observations) {
      const map::KeyFrame& kf = *map.keyframe(kf_id);
      const LineMeasurement m{kf.lines[index].left, kf.lines[index].right};
      PoseBlock& pose = vars.poses.at(kf_id);
      Observation obs{nullptr, id, kf_id, true, m.stereo() ? params.stereo_line_chi2 : params.mono_line_chi2, false};
      obs.block =
          problem.AddResidualBlock(make_line_cost(stereo, m, params.pixel_sigma).release(),
                                   m.stereo() ? stereo_line_loss.get() : mono_line_loss.get(), pose.data(), L.data());
      observations.push_back(obs);
      ++result.line_observations;
    }
  }
  if (result.point_observations + result.line_observations == 0) return result;

  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_SCHUR;
  options.linear_solver_ordering = ordering;
  options.max_num_iterations = params.ba_iterations;
  options.num_threads = params.num_threads;
  options.logging_type = ceres::SILENT;
  for (int round = 0; round < std::max(1, params.ba_rounds); ++round) {
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    if (round == 0) result.initial_cost = summary.initial_cost;
    result.final_cost = summary.final_cost;
    result.solved = summary.IsSolutionUsable();
    // Outliers leave the problem before the next round and the map after the last.
    int removed = 0;
    for (auto& obs : observations) {
      if (obs.outlier || unrobust_chi2(problem, obs.block) <= obs.chi2_threshold) continue;
      obs.outlier = true;
      if (round + 1 < params.ba_rounds) problem.RemoveResidualBlock(obs.block);
      ++removed;
    }
    if (removed == 0) break;  // another round would solve the same problem again
  }
  if (!result.solved) return result;

  for (Id kf_id : result.window) map.keyframe(kf_id)->T_world_camera = vars.poses.at(kf_id).T_world_camera();
  for (const auto& [id, X] : vars.points) map.point(id)->position = X;
  for (const auto& [id, L] : vars.lines) map.line(id)->line = geometry::PlueckerLine::from_vector(L).normalized();
  for (const auto& obs : observations) {
    if (!obs.outlier) continue;
    if (obs.is_line) {
      map.erase_line_observation(obs.landmark, obs.keyframe);
      ++result.line_outliers;
    } else {
      map.erase_point_observation(obs.landmark, obs.keyframe);
      ++result.point_outliers;
    }
  }
  return result;
}

}  // namespace vkvo::backend
