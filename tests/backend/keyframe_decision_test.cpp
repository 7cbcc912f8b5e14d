// Keyframe rules and the back-end parameter loaders.
#include <gtest/gtest.h>

#include "backend/keyframe_decision.hpp"
#include "backend/params.hpp"

namespace vkvo::backend {
namespace {

KeyframeDecisionInput steady() {
  KeyframeDecisionInput in;
  in.tracked = 150;
  in.tracked_previous = 150;
  in.frames_since_keyframe = 5;
  return in;
}

TEST(KeyframeDecision, EachRuleFiresAtItsThreshold) {
  const KeyframeParams p;
  EXPECT_EQ(keyframe_reason(p, steady()), KeyframeReason::none);
  EXPECT_FALSE(need_new_keyframe(p, steady()));

  auto in = steady();
  in.T_world_current.translation() = Eigen::Vector3d(0.3, 0.3, 0.2);  // 0.469 m
  EXPECT_EQ(keyframe_reason(p, in), KeyframeReason::none);
  in.T_world_current.translation() = Eigen::Vector3d(0.3, 0.3, 0.25);  // 0.495 m... still below 0.5
  EXPECT_EQ(keyframe_reason(p, in), KeyframeReason::none);
  in.T_world_current.translation() = Eigen::Vector3d(0.3, 0.3, 0.3);  // 0.52 m
  EXPECT_EQ(keyframe_reason(p, in), KeyframeReason::translation);

  in = steady();
  in.T_world_current.linear() = Eigen::AngleAxisd(0.50, Eigen::Vector3d::UnitY()).toRotationMatrix();
  EXPECT_EQ(keyframe_reason(p, in), KeyframeReason::none);
  in.T_world_current.linear() = Eigen::AngleAxisd(0.53, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  EXPECT_EQ(keyframe_reason(p, in), KeyframeReason::rotation);

  in = steady();
  in.tracked = 80;
  EXPECT_EQ(keyframe_reason(p, in), KeyframeReason::none);
  in.tracked = 79;
  EXPECT_EQ(keyframe_reason(p, in), KeyframeReason::few_tracked);
  in.tracked = 10;
  EXPECT_EQ(keyframe_reason(p, in), KeyframeReason::few_tracked);
  in.tracked = 9;
  EXPECT_EQ(keyframe_reason(p, in), KeyframeReason::tracking_failed);
  EXPECT_FALSE(need_new_keyframe(p, in));

  // Tracked lines constrain the pose like points: with them the frame still counts as tracked (and, with few
  // points, makes a keyframe), while few_tracked keeps counting the points the map needs.
  in.tracked_lines = 1;
  EXPECT_EQ(keyframe_reason(p, in), KeyframeReason::few_tracked);
  EXPECT_TRUE(need_new_keyframe(p, in));
  in.tracked = 4;
  in.tracked_lines = 5;
  EXPECT_EQ(keyframe_reason(p, in), KeyframeReason::tracking_failed);
  in.tracked_lines = 6;
  EXPECT_EQ(keyframe_reason(p, in), KeyframeReason::few_tracked);
  in = steady();
  in.tracked_lines = 100;
  EXPECT_EQ(keyframe_reason(p, in), KeyframeReason::none);

  in = steady();
  in.tracked_previous = 9;
  EXPECT_EQ(keyframe_reason(p, in), KeyframeReason::recovered);
  EXPECT_TRUE(need_new_keyframe(p, in));

  in = steady();
  in.frames_since_keyframe = 299;
  EXPECT_EQ(keyframe_reason(p, in), KeyframeReason::none);
  in.frames_since_keyframe = 300;
  EXPECT_EQ(keyframe_reason(p, in), KeyframeReason::frame_count);
  EXPECT_STREQ(to_string(KeyframeReason::frame_count), "frame_count");

  // The pose difference is relative to the last keyframe, wherever it is.
  in = steady();
  in.T_world_last_keyframe.translation() = Eigen::Vector3d(10, 0, 0);
  in.T_world_current.translation() = Eigen::Vector3d(10.2, 0, 0);
  EXPECT_EQ(keyframe_reason(p, in), KeyframeReason::none);
}

TEST(BackendParams, DefaultsAndYaml) {
  const OptimizationParams d;
  EXPECT_EQ(d.mono_point_chi2, 50.0);
  EXPECT_EQ(d.stereo_point_chi2, 75.0);
  EXPECT_EQ(d.mono_line_chi2, 50.0);
  EXPECT_EQ(d.stereo_line_chi2, 75.0);
  EXPECT_EQ(d.pixel_sigma, 0.8);
  EXPECT_EQ(d.window_size, 10);
  const OptimizationParams o = load_optimization_params(YAML::Load("{window_size: 7, pixel_sigma: 1.0}"));
  EXPECT_EQ(o.window_size, 7);
  EXPECT_EQ(o.pixel_sigma, 1.0);
  EXPECT_EQ(o.ba_iterations, d.ba_iterations);
  EXPECT_THROW(load_optimization_params(YAML::Load("{window_size: ten}")), std::runtime_error);
  const OptimizationParams none = load_optimization_params(YAML::Node());
  EXPECT_EQ(none.pose_rounds, d.pose_rounds);

  const KeyframeParams k = load_keyframe_params(YAML::Load("{max_translation: 0.3, max_frames: 100}"));
  EXPECT_EQ(k.max_translation, 0.3);
  EXPECT_EQ(k.max_frames, 100);
  EXPECT_EQ(k.max_rotation, 0.52);
  EXPECT_EQ(k.max_tracked, 80);
  EXPECT_EQ(k.min_tracked, 10);
  EXPECT_THROW(load_keyframe_params(YAML::Load("{min_tracked: 1.5}")), std::runtime_error);
}

}  // namespace
}  // namespace vkvo::backend
