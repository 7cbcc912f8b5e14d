// The image-size scaling of the map-initialisation thresholds (system/vo_config.hpp: scale_to_image).
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "io/dataset.hpp"
#include "system/vo_config.hpp"

namespace vkvo::system {
namespace {

TEST(VoConfig, InitialisationThresholdsScaleDownWithTheImageArea) {
  const VoConfig config = load_vo_config(test::source_dir() / "config" / "euroc.yaml");
  ASSERT_EQ(config.tracking.init_min_keypoints, 150);
  ASSERT_EQ(config.tracking.init_min_stereo, 100);
  ASSERT_DOUBLE_EQ(config.tracking.reference_image_area, 752.0 * 480.0);
  EXPECT_TRUE(config.tracking.init_counts_lines);
  EXPECT_FALSE(load_tracking_params(YAML::Load("{init_counts_lines: false}")).init_counts_lines);
  EXPECT_TRUE(config.tracking.rebuild_thin_start);
  EXPECT_FALSE(load_tracking_params(YAML::Load("{rebuild_thin_start: false}")).rebuild_thin_start);
  EXPECT_TRUE(config.tracking.lines_carry_frames);
  EXPECT_FALSE(load_tracking_params(YAML::Load("{lines_carry_frames: false}")).lines_carry_frames);

  const VoConfig euroc = scale_to_image(config, 752, 480);  // the reference size: unchanged
  EXPECT_EQ(euroc.tracking.init_min_keypoints, 150);
  EXPECT_EQ(euroc.tracking.init_min_stereo, 100);
  const VoConfig kitti = scale_to_image(config, 1241, 376);  // larger: never scaled up
  EXPECT_EQ(kitti.tracking.init_min_keypoints, 150);
  EXPECT_EQ(kitti.tracking.init_min_stereo, 100);
  // 320 x 240 (synth small preset) is 0.2128 of the area: 150 -> 32, 100 -> 21. Real SuperPoint finds 97
  // keypoints with 76 gated stereo matches on its first frame, which the unscaled 150 / 100 refused.
  const VoConfig small = scale_to_image(config, 320, 240);
  EXPECT_EQ(small.tracking.init_min_keypoints, 32);
  EXPECT_EQ(small.tracking.init_min_stereo, 21);
  EXPECT_EQ(small.keyframe.max_tracked, config.keyframe.max_tracked);
  // Tiny images: not below 2 x keyframe.min_tracked (= 20).
  const VoConfig tiny = scale_to_image(config, 80, 60);
  EXPECT_EQ(tiny.tracking.init_min_keypoints, 20);
  EXPECT_EQ(tiny.tracking.init_min_stereo, 20);

  VoConfig fixed = config;
  fixed.tracking.reference_image_area = 0;  // disabled
  EXPECT_EQ(scale_to_image(fixed, 320, 240).tracking.init_min_keypoints, 150);
}

// A key no module reads is named with its line, at every depth: a module's section, a flow map inside it, a list
// of maps, the camera section, a section of its own.
TEST(VoConfig, KeysNoModuleReadsAreNamedWithTheirLines) {
  const auto config = io::Config::from_string(
      "point_detector:\n"
      "  max_keypoint: 500\n"  // line 2
      "lines:\n"
      "  detector:\n"
      "    fld: {length_threshold: 10, canny_treshold1: 50}\n"  // line 5
      "    merge_stages:\n"
      "      - {max_angle: 0.05, max_gap: 15}\n"  // line 7
      "camera:\n"
      "  left: {fx: 500, T_body_cam: [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0]}\n"  // line 9
      "tracker:\n"
      "  min_num_match: 20\n",  // line 11
      "typos.yaml");
  const std::string message = test::error_of([&] { load_vo_config(config); });
  EXPECT_NE(message.find("typos.yaml"), std::string::npos) << message;
  for (const char* key : {"point_detector.max_keypoint (line 2)", "lines.detector.fld.canny_treshold1 (line 5)",
                          "lines.detector.merge_stages[0].max_gap (line 7)", "camera.left.T_body_cam (line 9)",
                          "tracker.min_num_match (line 11)"})
    EXPECT_NE(message.find(key), std::string::npos) << key << " not in: " << message;
  // The keys that are parameters are not named.
  for (const char* key : {"length_threshold", "max_angle", "left.fx"})
    EXPECT_EQ(message.find(key), std::string::npos) << key << " in: " << message;
}

// Every section is parsed at load time, those read later by the feature stage or the dataset reader included, so a
// bad value fails before any work starts and a component's keys are checked even where a run does not use it.
TEST(VoConfig, EverySectionIsCheckedAtLoad) {
  EXPECT_NE(test::error_of([] {
              load_vo_config(io::Config::from_string("point_detector: {precision: fp64}\n"));
            }).find("precision"),
            std::string::npos);
  EXPECT_NE(test::error_of([] {
              load_vo_config(io::Config::from_string("point_matcher: {sinkhorn_iters: 50}\n"));
            }).find("point_matcher.sinkhorn_iters"),
            std::string::npos);
  EXPECT_NE(test::error_of([] { load_vo_config(io::Config::from_string("dataset: {stride: 0}\n")); }).find("stride"),
            std::string::npos);
  const VoConfig config = load_vo_config(io::Config::from_string(
      "models: {matcher: nn}\npoint_matcher: {sinkhorn_iterations: 50}\nnn_matcher: {min_similarity: 0.8}\n"
      "dataset: {first_frame: 3}\ncamera: {fx: 400, left: {T_camera_body: [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0]}}\n"));
  EXPECT_EQ(config.dataset.range.first, 3u);
  EXPECT_EQ(config.point_matcher.sinkhorn_iterations, 50);
  EXPECT_NEAR(config.nn_matcher.max_cosine_distance, 0.2f, 1e-6f);
  EXPECT_EQ(io::apply_camera_overrides(config.dataset.camera_overrides, {}).left.fx, 400.0);
}

// Issue 40: AirVO's code's line choices are config options, parsed and checked like every other key.
TEST(VoConfig, AirvoLineChoicesAreOptions) {
  const VoConfig defaults = load_vo_config(io::Config::from_string("{}\n"));
  EXPECT_EQ(defaults.lines.matching.score, features::LineMatchScore::kPaper);
  EXPECT_EQ(defaults.optimization.line_weight, 1.0);
  EXPECT_TRUE(defaults.optimization.pose_with_lines);
  const VoConfig airvo =
      load_vo_config(io::Config::from_string("lines: {matching: {score: airvo, score_threshold: 0.8}}\n"
                                             "optimization: {line_weight: 0.1, pose_with_lines: false}\n"));
  EXPECT_EQ(airvo.lines.matching.score, features::LineMatchScore::kAirvo);
  EXPECT_FLOAT_EQ(airvo.lines.matching.score_threshold, 0.8f);
  EXPECT_EQ(airvo.optimization.line_weight, 0.1);
  EXPECT_FALSE(airvo.optimization.pose_with_lines);
  const std::string score =
      test::error_of([] { load_vo_config(io::Config::from_string("lines: {matching: {score: squared}}\n")); });
  EXPECT_NE(score.find("expected 'paper' or 'airvo', got 'squared'"), std::string::npos) << score;
  const std::string weight =
      test::error_of([] { load_vo_config(io::Config::from_string("optimization: {line_weight: 0}\n")); });
  EXPECT_NE(weight.find("optimization.line_weight"), std::string::npos) << weight;
}

// A live camera has no dataset calibration files: the camera section alone gives the calibration, or an error that
// names the config and the missing field.
TEST(VoConfig, CameraSectionAloneGivesTheCalibration) {
  const VoConfig config = load_vo_config(io::Config::from_string(
      "camera: {width: 640, height: 480, fx: 400, fy: 410, cx: 320, cy: 240, baseline: 0.12}\n", "robot.yaml"));
  const io::StereoCalibration c = config_calibration(config);
  EXPECT_TRUE(c.rectified);
  EXPECT_EQ(c.right.width, 640);
  EXPECT_EQ(c.left.fy, 410.0);
  EXPECT_NEAR(c.baseline(), 0.12, 1e-12);
  EXPECT_NEAR(c.T_left_right().translation().x(), 0.12, 1e-12);

  const std::string missing = test::error_of([] {
    config_calibration(
        load_vo_config(io::Config::from_string("camera: {width: 640, height: 480, fx: 400}\n", "robot.yaml")));
  });
  EXPECT_NE(missing.find("robot.yaml (camera section): left camera: field 'fy'"), std::string::npos) << missing;
}

}  // namespace
}  // namespace vkvo::system

// Issue 36: semantic checks in load_vo_config, which every command that takes --config goes through.
TEST(VoConfig, OutOfRangeAndInconsistentValuesNameFileKeyAndLine) {
  const auto message_of = [](const std::string& yaml) {
    return vkvo::test::error_of(
        [&] { vkvo::system::load_vo_config(vkvo::io::Config::from_string(yaml, "user.yaml")); });
  };
  const std::string threads = message_of("optimization:\n  num_threads: -4\n");
  EXPECT_NE(threads.find("user.yaml: optimization.num_threads (line 2)"), std::string::npos) << threads;
  const std::string depths = message_of("stereo:\n  min_depth: 5.0\n  max_depth: 2.0\n");
  EXPECT_NE(depths.find("stereo.min_depth (line 2)"), std::string::npos) << depths;
  EXPECT_NE(depths.find("less than max_depth 2"), std::string::npos) << depths;
  // Only max_depth given, below the default min_depth: the relation is checked on the parsed values.
  EXPECT_NE(message_of("stereo:\n  max_depth: 0.05\n").find("min_depth"), std::string::npos);
  EXPECT_NE(message_of("nn_matcher:\n  ratio: .nan\n").find("not a finite number"), std::string::npos);
}

TEST(VoConfig, DirectoryAsConfigIsNamed) {
  const auto dir = vkvo::test::temp_dir("vo_config_dir");
  EXPECT_NE(vkvo::test::error_of([&] { vkvo::system::load_vo_config_or_defaults(dir); }).find("is a directory"),
            std::string::npos);
}
