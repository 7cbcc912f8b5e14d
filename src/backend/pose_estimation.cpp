#include "backend/pose_estimation.hpp"

#include <cmath>
#include <limits>
#include <memory>

#include <ceres/loss_function.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <opencv2/calib3d.hpp>

namespace vkvo::backend {

namespace {

// The observations with their cost functions and (constant) landmark blocks, reused across rounds.
struct Residual {
  std::unique_ptr<ceres::CostFunction> cost;
  std::unique_ptr<ceres::LossFunction> loss;
  double* landmark = nullptr;
  double chi2_threshold = 0;
};

// Whitened squared residual, +inf where the residual cannot be evaluated (point behind the camera).
double chi2(const Residual& r, PoseBlock& pose) {
  double* blocks[2] = {pose.data(), r.landmark};
  double res[4];
  if (!r.cost->Evaluate(blocks, res, nullptr)) return std::numeric_limits<double>::infinity();
  double sum = 0;
  for (int i = 0; i < r.cost->num_residuals(); ++i) sum += res[i] * res[i];
  return sum;
}

int classify(std::vector<Residual>& residuals, PoseBlock& pose, std::vector<bool>& inliers) {
  int count = 0;
  inliers.resize(residuals.size());
  for (size_t i = 0; i < residuals.size(); ++i) {
    inliers[i] = chi2(residuals[i], pose) <= residuals[i].chi2_threshold;
    count += inliers[i];
  }
  return count;
}

}  // namespace

std::optional<PnpSolution> solve_pnp_ransac(const geometry::PinholeCamera& camera,
                                            const std::vector<PointMatch>& points, const OptimizationParams& params,
                                            int iterations) {
  if (points.size() < 4) return std::nullopt;
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (const auto& p : points) {
    object.emplace_back(p.position_world.x(), p.position_world.y(), p.position_world.z());
    image.emplace_back(p.measurement.pixel.x(), p.measurement.pixel.y());
  }
  const cv::Mat K = (cv::Mat_<double>(3, 3) << camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  cv::Mat rvec, tvec;
  std::vector<int> inlier_indices;
  const double threshold_px = params.pixel_sigma * std::sqrt(params.mono_point_chi2);
  if (!cv::solvePnPRansac(object, image, K, cv::noArray(), rvec, tvec, false, iterations,
                          static_cast<float>(threshold_px), params.pnp_confidence, inlier_indices, cv::SOLVEPNP_EPNP))
    return std::nullopt;
  cv::Mat R;
  cv::Rodrigues(rvec, R);
  Eigen::Isometry3d T_cw = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) T_cw.linear()(r, c) = R.at<double>(r, c);
    T_cw.translation()[r] = tvec.at<double>(r);
  }
  PnpSolution solution;
  solution.T_world_camera = T_cw.inverse();
  solution.inliers.assign(points.size(), false);
  for (int i : inlier_indices) solution.inliers[static_cast<std::size_t>(i)] = true;
  solution.num_inliers = static_cast<int>(inlier_indices.size());
  return solution;
}

PoseEstimate estimate_pose(const geometry::StereoCamera& stereo, const Eigen::Isometry3d& T_world_camera_prior,
                           const std::vector<PointMatch>& points, const std::vector<LineMatch>& lines,
                           const OptimizationParams& params) {
  // Landmarks are constant: copies give Ceres mutable storage without touching the caller's data.
  std::vector<Eigen::Vector3d> point_blocks;
  std::vector<Eigen::Matrix<double, 6, 1>> line_blocks;
  point_blocks.reserve(points.size());
  line_blocks.reserve(lines.size());
  std::vector<Residual> point_res, line_res;
  for (const auto& p : points) {
    point_blocks.push_back(p.position_world);
    point_res.push_back({make_point_cost(stereo, p.measurement, params.pixel_sigma), nullptr,
                         point_blocks.back().data(),
                         p.measurement.stereo() ? params.stereo_point_chi2 : params.mono_point_chi2});
  }
  for (const auto& l : lines) {
    line_blocks.push_back(l.line_world.normalized().vector());
    line_res.push_back({make_line_cost(stereo, l.measurement, params.pixel_sigma), nullptr, line_blocks.back().data(),
                        l.measurement.stereo() ? params.stereo_line_chi2 : params.mono_line_chi2});
  }
  for (auto& r : point_res) r.loss = make_robust_loss(r.chi2_threshold);
  for (auto& r : line_res) r.loss = make_robust_loss(r.chi2_threshold, params.line_weight);

  PoseEstimate out;
  PoseBlock pose = PoseBlock::from_T_world_camera(T_world_camera_prior);
  int prior_inliers = classify(point_res, pose, out.point_inliers);
  if (static_cast<int>(points.size()) >= params.pnp_min_points &&
      prior_inliers < params.pnp_prior_min_inlier_ratio * static_cast<double>(points.size())) {
    if (const auto pnp = solve_pnp_ransac(stereo.camera, points, params, params.pnp_iterations)) {
      PoseBlock candidate = PoseBlock::from_T_world_camera(pnp->T_world_camera);
      std::vector<bool> flags;
      if (classify(point_res, candidate, flags) > prior_inliers) {
        pose = candidate;
        out.used_pnp = true;
        out.point_inliers = flags;
      }
    }
  }
  classify(line_res, pose, out.line_inliers);
  // First round: every evaluable observation (the robust loss absorbs outliers); later rounds: current inliers.
  for (size_t i = 0; i < point_res.size(); ++i) out.point_inliers[i] = std::isfinite(chi2(point_res[i], pose));

  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  const std::unique_ptr<ceres::Manifold> pose_manifold = make_pose_manifold();
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = params.pose_iterations;
  solver_options.num_threads = params.num_threads;
  solver_options.logging_type = ceres::SILENT;

  for (int round = 0; round < params.pose_rounds; ++round) {
    ceres::Problem problem(problem_options);
    problem.AddParameterBlock(pose.data(), 7, pose_manifold.get());
    int used = 0;
    auto add = [&](std::vector<Residual>& residuals, const std::vector<bool>& inliers) {
      for (size_t i = 0; i < residuals.size(); ++i) {
        if (!inliers[i]) continue;
        problem.AddResidualBlock(residuals[i].cost.get(), residuals[i].loss.get(), pose.data(), residuals[i].landmark);
        problem.SetParameterBlockConstant(residuals[i].landmark);
        ++used;
      }
    };
    add(point_res, out.point_inliers);
    if (params.pose_with_lines) add(line_res, out.line_inliers);
    if (used < 3) break;  // nothing to estimate from
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, &problem, &summary);
    out.num_point_inliers = classify(point_res, pose, out.point_inliers);
    out.num_line_inliers = classify(line_res, pose, out.line_inliers);
  }
  out.num_point_inliers = classify(point_res, pose, out.point_inliers);
  out.num_line_inliers = classify(line_res, pose, out.line_inliers);
  out.T_world_camera = pose.T_world_camera();
  out.success = out.num_point_inliers + out.num_line_inliers >= params.min_pose_inliers;
  return out;
}

}  // namespace vkvo::backend
