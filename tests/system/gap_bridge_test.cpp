// GapBridge: untracked frames held until tracking resumes, then released interpolated between the tracked poses
// around the gap; closed-form poses (rotation about one axis, straight translation) give the expected values.
#include <gtest/gtest.h>

#include <cmath>

#include "system/gap_bridge.hpp"

namespace vkvo::system {
namespace {

constexpr std::int64_t kStepNs = 50'000'000;  // 20 Hz

// Yaw `angle` about z and position (x, 0, 0).
Eigen::Isometry3d pose(double angle, double x) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, 0, 0);
  return T;
}

FramePose frame(int index, const Eigen::Isometry3d& T, bool tracked) {
  return {.timestamp_ns = index * kStepNs, .T_world_camera = T, .tracked = tracked};
}

double yaw(const Eigen::Isometry3d& T) { return std::atan2(T.linear()(1, 0), T.linear()(0, 0)); }

TEST(InterpolatePose, MatchesTheClosedFormAlongOneAxis) {
  const Eigen::Isometry3d a = pose(0.2, 1.0), b = pose(0.8, 3.0);
  for (const double f : {0.0, 0.25, 0.5, 1.0}) {
    const Eigen::Isometry3d T = interpolate_pose(a, b, f);
    EXPECT_NEAR(yaw(T), 0.2 + 0.6 * f, 1e-12) << f;
    EXPECT_NEAR((T.translation() - Eigen::Vector3d(1.0 + 2.0 * f, 0, 0)).norm(), 0.0, 1e-12) << f;
  }
}

TEST(GapBridge, TrackedFramesPassStraightThrough) {
  GapBridge bridge(5);
  for (int i = 0; i < 3; ++i) {
    const auto out = bridge.push(frame(i, pose(0.1 * i, i), true));
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].timestamp_ns, i * kStepNs);
    EXPECT_FALSE(out[0].bridged);
  }
  EXPECT_EQ(bridge.frames_bridged(), 0);
}

TEST(GapBridge, ClosedGapIsInterpolatedByTime) {
  GapBridge bridge(5);
  bridge.push(frame(0, pose(0.0, 0.0), true));
  // Predictions far off the truth: the bridge must replace them.
  for (int i = 1; i <= 3; ++i) EXPECT_TRUE(bridge.push(frame(i, pose(1.5, 10.0 * i), false)).empty()) << i;
  EXPECT_EQ(bridge.held(), 3u);
  const auto out = bridge.push(frame(4, pose(0.4, 2.0), true));
  ASSERT_EQ(out.size(), 4u);
  for (int i = 1; i <= 3; ++i) {
    const FramePose& p = out[i - 1];
    EXPECT_EQ(p.timestamp_ns, i * kStepNs);
    EXPECT_TRUE(p.bridged);
    EXPECT_FALSE(p.tracked);
    EXPECT_NEAR(yaw(p.T_world_camera), 0.1 * i, 1e-12);
    EXPECT_NEAR(p.T_world_camera.translation().x(), 0.5 * i, 1e-12);
  }
  EXPECT_TRUE(out[3].tracked);
  EXPECT_FALSE(out[3].bridged);
  EXPECT_EQ(bridge.frames_bridged(), 3);
  EXPECT_EQ(bridge.held(), 0u);
}

TEST(GapBridge, UntrackedBeforeTheFirstTrackedFrameIsReleasedAtOnce) {
  GapBridge bridge(5);
  const auto out = bridge.push(frame(0, pose(0.3, 1.0), false));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(out[0].bridged);
  EXPECT_NEAR(yaw(out[0].T_world_camera), 0.3, 1e-12);
}

TEST(GapBridge, GapLongerThanTheLimitKeepsItsPredictions) {
  GapBridge bridge(2);
  bridge.push(frame(0, pose(0.0, 0.0), true));
  EXPECT_TRUE(bridge.push(frame(1, pose(1.0, 1.0), false)).empty());
  EXPECT_TRUE(bridge.push(frame(2, pose(2.0, 2.0), false)).empty());
  const auto overflow = bridge.push(frame(3, pose(3.0, 3.0), false));  // third held pose: over the limit
  ASSERT_EQ(overflow.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_FALSE(overflow[i].bridged);
    EXPECT_NEAR(overflow[i].T_world_camera.translation().x(), i + 1.0, 1e-12);
  }
  EXPECT_EQ(bridge.push(frame(4, pose(4.0, 4.0), false)).size(), 1u);  // the rest of this gap: at once
  EXPECT_EQ(bridge.push(frame(5, pose(0.5, 5.0), true)).size(), 1u);
  // A later short gap is bridged again.
  EXPECT_TRUE(bridge.push(frame(6, pose(0.0, 0.0), false)).empty());
  const auto out = bridge.push(frame(7, pose(0.7, 7.0), true));
  ASSERT_EQ(out.size(), 2u);
  EXPECT_TRUE(out[0].bridged);
  EXPECT_NEAR(out[0].T_world_camera.translation().x(), 6.0, 1e-12);
  EXPECT_EQ(bridge.frames_bridged(), 1);
}

TEST(GapBridge, FlushReleasesAnOpenGapAsPredicted) {
  GapBridge bridge(5);
  bridge.push(frame(0, pose(0.0, 0.0), true));
  bridge.push(frame(1, pose(0.2, 9.0), false));
  const auto out = bridge.flush();
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(out[0].bridged);
  EXPECT_NEAR(out[0].T_world_camera.translation().x(), 9.0, 1e-12);
  EXPECT_TRUE(bridge.flush().empty());
}

TEST(GapBridge, ZeroLimitDisablesBridging) {
  GapBridge bridge(0);
  bridge.push(frame(0, pose(0.0, 0.0), true));
  EXPECT_EQ(bridge.push(frame(1, pose(0.2, 9.0), false)).size(), 1u);
  EXPECT_EQ(bridge.frames_bridged(), 0);
}

}  // namespace
}  // namespace vkvo::system
