#include "backend/local_ba.hpp"

#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <vector>

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

// The window's variables, in storage that stays put while Ceres holds pointers into it. Ceres orders the blocks
// of an elimination group by their addresses, so each group lives in one buffer in id order: every run then
// eliminates in the same order and gives the same result to the bit, whatever the heap's layout.
class Variables {
 public:
  Variables(const std::set<Id>& poses, const std::set<Id>& points, const std::set<Id>& lines)
      : poses_(poses.size()), landmarks_(3 * points.size() + 6 * lines.size()) {
    for (Id id : poses) pose_slot_.emplace(id, pose_slot_.size());
    for (Id id : points) point_slot_.emplace(id, point_slot_.size());
    for (Id id : lines) line_slot_.emplace(id, line_slot_.size());
  }
  PoseBlock& pose(Id id) { return poses_[pose_slot_.at(id)]; }
  double* point(Id id) { return landmarks_.data() + 3 * point_slot_.at(id); }
  double* line(Id id) { return landmarks_.data() + 3 * point_slot_.size() + 6 * line_slot_.at(id); }

 private:
  std::map<Id, std::size_t> pose_slot_, point_slot_, line_slot_;
  std::vector<PoseBlock> poses_;
  std::vector<double> landmarks_;  // points (3 values each), then lines (6 each): both in elimination group 0
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

  std::set<Id> point_ids, line_ids;
  for (Id kf_id : result.window) {
    const map::KeyFrame& kf = *map.keyframe(kf_id);
    for (Id p : kf.point_ids)
      if (const map::MapPoint* mp = map.point(p); mp && !mp->bad) point_ids.insert(p);
    for (Id l : kf.line_ids)
      if (const map::MapLine* ml = map.line(l); ml && !ml->bad) line_ids.insert(l);
  }
  std::set<Id> fixed;
  auto note_observers = [&](const auto& observations) {
    for (const auto& obs : observations)
      if (!in_window.count(obs.first)) fixed.insert(obs.first);
  };
  for (Id id : point_ids) note_observers(map.point(id)->observations);
  for (Id id : line_ids) note_observers(map.line(id)->observations);
  if (fixed.empty()) fixed.insert(*in_window.begin());  // gauge: hold the oldest window keyframe
  std::set<Id> pose_ids = in_window;
  pose_ids.insert(fixed.begin(), fixed.end());
  result.fixed.assign(fixed.begin(), fixed.end());

  Variables vars(pose_ids, point_ids, line_ids);
  for (Id kf_id : pose_ids) vars.pose(kf_id) = PoseBlock::from_T_world_camera(map.keyframe(kf_id)->T_world_camera);
  for (Id id : point_ids) Eigen::Map<Eigen::Vector3d>(vars.point(id)) = map.point(id)->position;
  for (Id id : line_ids)
    Eigen::Map<Eigen::Matrix<double, 6, 1>>(vars.line(id)) = map.line(id)->line.normalized().vector();
  result.num_points = static_cast<int>(point_ids.size());
  result.num_lines = static_cast<int>(line_ids.size());

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

  for (const Id id : pose_ids) {
    double* pose = vars.pose(id).data();
    problem.AddParameterBlock(pose, 7, pose_manifold.get());
    ordering->AddElementToGroup(pose, 1);
    if (fixed.count(id)) problem.SetParameterBlockConstant(pose);
  }

  std::vector<Observation> observations;
  for (const Id id : point_ids) {
    double* point = vars.point(id);
    const Eigen::Map<const Eigen::Vector3d> X(point);
    problem.AddParameterBlock(point, 3);
    ordering->AddElementToGroup(point, 0);
    for (const auto& [kf_id, index] : map.point(id)->observations) {
      const map::KeyFrame& kf = *map.keyframe(kf_id);
      PoseBlock& pose = vars.pose(kf_id);
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
                                   m.stereo() ? stereo_point_loss.get() : mono_point_loss.get(), pose.data(), point);
      observations.push_back(obs);
      ++result.point_observations;
    }
  }
  for (const Id id : line_ids) {
    double* line = vars.line(id);
    problem.AddParameterBlock(line, 6, line_manifold.get());
    ordering->AddElementToGroup(line, 0);
    for (const auto& [kf_id, index] : map.line(id)->observations) {
      const map::KeyFrame& kf = *map.keyframe(kf_id);
      const LineMeasurement m{kf.lines[index].left, kf.lines[index].right};
      PoseBlock& pose = vars.pose(kf_id);
      Observation obs{nullptr, id, kf_id, true, m.stereo() ? params.stereo_line_chi2 : params.mono_line_chi2, false};
      obs.block =
          problem.AddResidualBlock(make_line_cost(stereo, m, params.pixel_sigma).release(),
                                   m.stereo() ? stereo_line_loss.get() : mono_line_loss.get(), pose.data(), line);
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

  for (Id kf_id : result.window) map.keyframe(kf_id)->T_world_camera = vars.pose(kf_id).T_world_camera();
  for (const Id id : point_ids) map.point(id)->position = Eigen::Map<Eigen::Vector3d>(vars.point(id));
  for (const Id id : line_ids)
    map.line(id)->line =
        geometry::PlueckerLine::from_vector(Eigen::Map<Eigen::Matrix<double, 6, 1>>(vars.line(id))).normalized();
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
