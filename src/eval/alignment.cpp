#include "eval/alignment.hpp"

#include <stdexcept>

#include <fmt/format.h>
#include <Eigen/Geometry>

namespace vkvo::eval {

AlignmentMode parse_alignment_mode(const std::string& name) {
  if (name == "none") return AlignmentMode::none;
  if (name == "se3") return AlignmentMode::se3;
  if (name == "sim3") return AlignmentMode::sim3;
  throw std::runtime_error(fmt::format("unknown alignment '{}' (expected none, se3 or sim3)", name));
}

const char* to_string(AlignmentMode mode) {
  switch (mode) {
    case AlignmentMode::none: return "none";
    case AlignmentMode::se3: return "se3";
    case AlignmentMode::sim3: return "sim3";
  }
  return "unknown";
}

Eigen::Isometry3d Similarity::apply(const Eigen::Isometry3d& pose) const {
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.linear() = rotation * pose.linear();
  result.translation() = apply(Eigen::Vector3d(pose.translation()));
  return result;
}

Similarity align_positions(const std::vector<Eigen::Vector3d>& estimate,
                           const std::vector<Eigen::Vector3d>& groundtruth, AlignmentMode mode) {
  if (estimate.size() != groundtruth.size())
    throw std::invalid_argument("align_positions: estimate and ground truth differ in length");
  if (mode == AlignmentMode::none) return {};
  if (estimate.size() < 3)
    throw std::runtime_error(
        fmt::format("{} alignment needs at least 3 associated poses, got {}", to_string(mode), estimate.size()));
  Eigen::Matrix3Xd src(3, estimate.size()), dst(3, groundtruth.size());
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    src.col(static_cast<Eigen::Index>(i)) = estimate[i];
    dst.col(static_cast<Eigen::Index>(i)) = groundtruth[i];
  }
  if (mode == AlignmentMode::sim3) {
    const double spread = (src.colwise() - src.rowwise().mean()).squaredNorm();
    if (!(spread > 1e-18)) throw std::runtime_error("sim3 alignment: the estimated positions do not move");
  }
  const Eigen::Matrix4d T = Eigen::umeyama(src, dst, mode == AlignmentMode::sim3);
  Similarity similarity;
  similarity.scale = mode == AlignmentMode::sim3 ? std::cbrt(T.topLeftCorner<3, 3>().determinant()) : 1.0;
  similarity.rotation = T.topLeftCorner<3, 3>() / similarity.scale;
  similarity.translation = T.topRightCorner<3, 1>();
  return similarity;
}

Similarity align_first_pose(const Eigen::Isometry3d& estimate0, const Eigen::Isometry3d& groundtruth0, double scale) {
  Similarity similarity;
  similarity.scale = scale;
  similarity.rotation = groundtruth0.linear() * estimate0.linear().transpose();
  similarity.translation = groundtruth0.translation() - scale * similarity.rotation * estimate0.translation();
  return similarity;
}

std::vector<Eigen::Vector3d> positions(const std::vector<Eigen::Isometry3d>& poses) {
  std::vector<Eigen::Vector3d> result;
  result.reserve(poses.size());
  for (const auto& pose : poses) result.push_back(pose.translation());
  return result;
}

std::vector<Eigen::Isometry3d> transform_poses(const Similarity& similarity,
                                               const std::vector<Eigen::Isometry3d>& poses) {
  std::vector<Eigen::Isometry3d> result;
  result.reserve(poses.size());
  for (const auto& pose : poses) result.push_back(similarity.apply(pose));
  return result;
}

}  // namespace vkvo::eval
