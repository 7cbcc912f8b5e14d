#include "eval/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace vkvo::eval {

ErrorStats compute_stats(std::vector<double> values) {
  ErrorStats stats;
  stats.count = values.size();
  if (values.empty()) return stats;
  const double n = static_cast<double>(values.size());
  double sum = 0, sum_sq = 0;
  for (double v : values) sum += v, sum_sq += v * v;
  stats.mean = sum / n;
  stats.rmse = std::sqrt(sum_sq / n);
  stats.std = std::sqrt(std::max(0.0, sum_sq / n - stats.mean * stats.mean));
  std::sort(values.begin(), values.end());
  stats.min = values.front();
  stats.max = values.back();
  const std::size_t mid = values.size() / 2;
  stats.median = values.size() % 2 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
  return stats;
}

double path_length(const std::vector<Eigen::Isometry3d>& poses) {
  double length = 0;
  for (std::size_t k = 1; k < poses.size(); ++k) length += (poses[k].translation() - poses[k - 1].translation()).norm();
  return length;
}

double rotation_angle_deg(const Eigen::Matrix3d& R) {
  // atan2(|axis * sin|, cos) stays accurate at small angles, where acos((tr-1)/2) loses half the digits.
  const Eigen::Vector3d sin_axis(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  const double cos_angle = 0.5 * (R.trace() - 1.0);
  return std::atan2(0.5 * sin_axis.norm(), cos_angle) * 180.0 / M_PI;
}

AteResult compute_ate(const AssociatedPoses& poses, AlignmentMode mode, bool positions_only) {
  AteResult result;
  result.alignment = align_positions(positions(poses.estimate), positions(poses.groundtruth), mode);
  std::vector<double> rotation_errors;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Eigen::Isometry3d aligned = result.alignment.apply(poses.estimate[i]);
    result.translation_errors.push_back((poses.groundtruth[i].translation() - aligned.translation()).norm());
    if (!positions_only)
      rotation_errors.push_back(rotation_angle_deg(poses.groundtruth[i].linear().transpose() * aligned.linear()));
  }
  result.translation_m = compute_stats(result.translation_errors);
  result.rotation_deg = compute_stats(std::move(rotation_errors));
  return result;
}

RpeResult compute_rpe(const std::vector<Eigen::Isometry3d>& estimate, const std::vector<Eigen::Isometry3d>& groundtruth,
                      const RpeOptions& options) {
  if (estimate.size() != groundtruth.size()) throw std::invalid_argument("compute_rpe: length mismatch");
  if (options.step == 0) throw std::invalid_argument("compute_rpe: step must be at least 1");
  // Cumulative ground-truth distance along the path.
  std::vector<double> distance(groundtruth.size(), 0.0);
  for (std::size_t k = 1; k < groundtruth.size(); ++k)
    distance[k] = distance[k - 1] + (groundtruth[k].translation() - groundtruth[k - 1].translation()).norm();
  const double total = distance.empty() ? 0.0 : distance.back();

  std::vector<double> lengths = options.lengths_m;
  if (lengths.empty())
    for (double fraction : options.length_fractions) lengths.push_back(fraction * total);

  RpeResult result;
  double sum_t = 0, sum_r = 0;
  for (double length : lengths) {
    RpeSegment segment;
    segment.length_m = length;
    if (length > 0) {
      double segment_t = 0, segment_r = 0;
      std::size_t j = 0;
      for (std::size_t i = 0; i < groundtruth.size(); i += options.step) {
        j = std::max(j, i);
        while (j < groundtruth.size() && distance[j] - distance[i] < length) ++j;  // j only moves forward
        if (j == groundtruth.size()) break;
        if (options.positions_only) {
          const Eigen::Vector3d displacement_gt = groundtruth[j].translation() - groundtruth[i].translation();
          const Eigen::Vector3d displacement_est = estimate[j].translation() - estimate[i].translation();
          segment_t += (displacement_est - displacement_gt).norm() / length;
        } else {
          const Eigen::Isometry3d delta_gt = groundtruth[i].inverse() * groundtruth[j];
          const Eigen::Isometry3d delta_est = estimate[i].inverse() * estimate[j];
          const Eigen::Isometry3d error = delta_est.inverse() * delta_gt;
          segment_t += error.translation().norm() / length;
          segment_r += rotation_angle_deg(error.linear()) / length;
        }
        ++segment.count;
      }
      if (segment.count > 0) {
        segment.translation_percent = 100.0 * segment_t / static_cast<double>(segment.count);
        segment.rotation_deg_per_m = segment_r / static_cast<double>(segment.count);
      }
      sum_t += 100.0 * segment_t;
      sum_r += segment_r;
      result.count += segment.count;
    }
    result.segments.push_back(segment);
  }
  if (result.count > 0) {
    result.translation_percent = sum_t / static_cast<double>(result.count);
    result.rotation_deg_per_m = sum_r / static_cast<double>(result.count);
  }
  return result;
}

DriftResult compute_drift(const AssociatedPoses& poses, double scale, const std::optional<Eigen::Matrix3d>& rotation) {
  DriftResult drift;
  if (poses.size() < 2) return drift;
  Similarity anchor;
  if (rotation) {
    anchor.scale = scale;
    anchor.rotation = *rotation;
    anchor.translation =
        poses.groundtruth.front().translation() - scale * *rotation * poses.estimate.front().translation();
  } else {
    anchor = align_first_pose(poses.estimate.front(), poses.groundtruth.front(), scale);
  }
  drift.final_error_m =
      (anchor.apply(Eigen::Vector3d(poses.estimate.back().translation())) - poses.groundtruth.back().translation())
          .norm();
  drift.path_length_m = path_length(poses.groundtruth);
  drift.percent = drift.path_length_m > 0 ? 100.0 * drift.final_error_m / drift.path_length_m : 0.0;
  return drift;
}

}  // namespace vkvo::eval
