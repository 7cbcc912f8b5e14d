// Evaluation on the shared ground truth (label `data`): known perturbations of real trajectories.
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "eval/association.hpp"
#include "eval/evaluate.hpp"
#include "io/dataset.hpp"
#include "io/trajectory.hpp"

using namespace vkvo;

TEST(EvalData, KittiScaleErrorShowsInRpeAndSim3) {
  VKVO_REQUIRE_DATA(file, "datasets/kitti_seq01_f000-050/KITTI_sequence_2/poses.txt");
  const auto gt = io::read_groundtruth(file).poses;
  // Estimate in another frame with 2% too long translations: x_est = 1.02 * S^-1 x_gt.
  Eigen::Isometry3d S = Eigen::Isometry3d::Identity();
  S.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  S.translation() = Eigen::Vector3d(10, -4, 2);
  io::Trajectory est;
  for (const auto& p : gt) {
    Eigen::Isometry3d pose = S.inverse() * p.pose;
    pose.translation() *= 1.02;
    est.push_back({p.t, pose});
  }
  const auto se3 = eval::evaluate(est, gt, {eval::AlignmentMode::se3, 0.02, {}});
  // Relative translations are 2% long; segments end at the first pose past L, so |chord| / L is a little above 1
  // (1 m steps on 5-25 m segments) and below 1 only by the curve's chord/arc ratio (< 0.5% here).
  EXPECT_NEAR(se3.rpe.translation_percent, 2.0, 0.1);
  EXPECT_LT(se3.rpe.rotation_deg_per_m, 1e-6);
  EXPECT_GT(se3.ate.translation_m.rmse, 0.1);  // 2% of a 50 m path cannot be aligned away rigidly

  const auto sim3 = eval::evaluate(est, gt, {eval::AlignmentMode::sim3, 0.02, {}});
  EXPECT_NEAR(sim3.ate.alignment.scale, 1.0 / 1.02, 1e-9);
  EXPECT_LT(sim3.ate.translation_m.rmse, 1e-6);
  EXPECT_LT(sim3.rpe.translation_percent, 1e-5);
  EXPECT_NEAR(sim3.drift.path_length_m, 51.8, 0.1);
  EXPECT_LT(sim3.drift.percent, 1e-5);
}

TEST(EvalData, EurocFrameTimestampsAssociateWithLeftCamGroundTruth) {
  VKVO_REQUIRE_DATA(dir, "datasets/euroc_mh01_subset");
  const auto dataset = io::open_dataset(dir);
  ASSERT_TRUE(dataset->groundtruth_path().has_value());
  const auto gt = io::read_groundtruth(*dataset->groundtruth_path()).poses;
  // An "estimate" at every camera frame: the nearest ground-truth pose moved by a rigid transform.
  io::Trajectory at_frames;
  for (const auto& frame : dataset->frames()) at_frames.push_back({frame.timestamp_s, Eigen::Isometry3d::Identity()});
  const auto pairs = eval::associate(at_frames, gt, 0.001);
  ASSERT_EQ(pairs.size(), 130u);  // the GT file has one row per camera frame, same stamps
  Eigen::Isometry3d S = Eigen::Isometry3d::Identity();
  S.linear() = Eigen::AngleAxisd(-1.1, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  S.translation() = Eigen::Vector3d(-4, 1, 0.3);
  io::Trajectory est;
  for (std::size_t k = 0; k < pairs.size(); ++k) est.push_back({pairs.t[k], S * pairs.groundtruth[k]});
  const auto result = eval::evaluate(est, gt, {eval::AlignmentMode::se3, 0.001, {}});
  EXPECT_EQ(result.associated_poses, 130u);
  EXPECT_LT(result.ate.translation_m.rmse, 1e-9);
  EXPECT_NEAR(result.drift.path_length_m, 1.8, 0.1);  // PROVENANCE.md: "the path is about 1.8 m"
}
