#pragma once
// Trajectory error metrics: absolute trajectory error (ATE), relative pose error over distances (RPE, KITTI
// style) and end-point drift.
#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "eval/alignment.hpp"
#include "eval/association.hpp"

namespace vkvo::eval {

struct ErrorStats {
  std::size_t count = 0;
  double rmse = 0, mean = 0, median = 0, std = 0, min = 0, max = 0;
};
ErrorStats compute_stats(std::vector<double> values);

// Sum of the distances between consecutive positions.
double path_length(const std::vector<Eigen::Isometry3d>& poses);
// Rotation angle of R in degrees, robust near 0 and 180.
double rotation_angle_deg(const Eigen::Matrix3d& R);

struct AteResult {
  Similarity alignment;      // applied to the estimate before measuring
  ErrorStats translation_m;  // |p_gt - p_est_aligned|
  ErrorStats rotation_deg;   // angle(R_gt^T R_est_aligned); count 0 when positions only
  std::vector<double> translation_errors;
};
// Aligns (mode) and measures. Throws when alignment is impossible (see align_positions). `positions_only`: a
// trajectory has no orientation, so no rotation errors.
AteResult compute_ate(const AssociatedPoses& poses, AlignmentMode mode, bool positions_only = false);

struct RpeOptions {
  // Segment lengths in metres. When empty, `length_fractions` of the ground-truth path length are used (KITTI
  // uses fixed 100..800 m, far longer than short clips).
  std::vector<double> lengths_m;
  std::vector<double> length_fractions{0.1, 0.2, 0.3, 0.4, 0.5};
  std::size_t step = 1;  // start a segment at every `step`-th pose (KITTI: 10)
  // A trajectory has no orientation: t_err = |(p_est_j - p_est_i) - (p_gt_j - p_gt_i)| (world frame, aligned
  // estimate), no rotation error.
  bool positions_only = false;
};

struct RpeSegment {
  double length_m = 0;
  std::size_t count = 0;           // number of segments of this length
  double translation_percent = 0;  // mean of |t_err| / length * 100
  double rotation_deg_per_m = 0;   // mean of angle(R_err) / length (0 when positions only)
};

struct RpeResult {
  std::vector<RpeSegment> segments;
  std::size_t count = 0;           // all segments
  double translation_percent = 0;  // mean over all segments of all lengths (KITTI's averaging)
  double rotation_deg_per_m = 0;
};
// KITTI's definition on (already aligned) poses: for a start i and length L, j is the first pose whose ground-truth
// path distance from i reaches L; E = (est_i^-1 est_j)^-1 (gt_i^-1 gt_j); t_err = |trans(E)| / L,
// r_err = angle(E) / L (positions only: see RpeOptions). Lengths that no segment spans are reported with count 0.
RpeResult compute_rpe(const std::vector<Eigen::Isometry3d>& estimate, const std::vector<Eigen::Isometry3d>& groundtruth,
                      const RpeOptions& options = {});

// End-point drift: the estimate is anchored to the first ground-truth pose (align_first_pose, with `scale`), then
// drift = |p_est_last - p_gt_last| / ground-truth path length. Reported in metres and percent. Without orientations
// (positions only) there is no first pose to anchor to: the estimate is turned by `rotation` (the ATE alignment's)
// and anchored at the first position.
struct DriftResult {
  double final_error_m = 0;
  double path_length_m = 0;
  double percent = 0;
};
DriftResult compute_drift(const AssociatedPoses& poses, double scale = 1.0,
                          const std::optional<Eigen::Matrix3d>& rotation = std::nullopt);

}  // namespace vkvo::eval
