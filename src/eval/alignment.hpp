#pragma once
// Trajectory alignment: the similarity (or rigid) transform that best maps estimated positions onto ground truth.
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace vkvo::eval {

enum class AlignmentMode {
  none,  // compare in the estimate's own frame
  se3,   // rotation + translation (stereo: metric scale is observable)
  sim3,  // rotation + translation + scale (monocular-style comparison; reports the scale)
};
AlignmentMode parse_alignment_mode(const std::string& name);  // "none" | "se3" | "sim3"; throws otherwise
const char* to_string(AlignmentMode mode);

// x_gt ~= scale * R * x_est + t
struct Similarity {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double scale = 1.0;

  Eigen::Vector3d apply(const Eigen::Vector3d& point) const { return scale * rotation * point + translation; }
  // Moves a pose with the similarity: the orientation is rotated, the position mapped (the scale affects only
  // positions, so the result is still a rigid pose).
  Eigen::Isometry3d apply(const Eigen::Isometry3d& pose) const;
};

// Least-squares alignment of corresponding positions (Umeyama 1991, via Eigen::umeyama). Needs at least 3
// correspondences for se3/sim3 and non-coincident estimate positions for sim3; throws std::runtime_error otherwise.
Similarity align_positions(const std::vector<Eigen::Vector3d>& estimate,
                           const std::vector<Eigen::Vector3d>& groundtruth, AlignmentMode mode);

// The transform that maps the first estimate pose exactly onto the first ground-truth pose (scale given).
Similarity align_first_pose(const Eigen::Isometry3d& estimate0, const Eigen::Isometry3d& groundtruth0,
                            double scale = 1.0);

std::vector<Eigen::Vector3d> positions(const std::vector<Eigen::Isometry3d>& poses);
std::vector<Eigen::Isometry3d> transform_poses(const Similarity& similarity,
                                               const std::vector<Eigen::Isometry3d>& poses);

}  // namespace vkvo::eval
