// io::Config and the camera: section overrides.
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "io/config.hpp"
#include "io/dataset.hpp"

using namespace vkvo;

using test::error_of;

TEST(Config, SectionsAndParamsWithDefaults) {
  const auto config = io::Config::from_string(
      "%YAML:1.0\nsuperpoint:\n  max_keypoints: 400\n  threshold: 0.004\nfeatures:\n  lines:\n    length: 7\n");
  const YAML::Node sp = config.section("superpoint");
  EXPECT_EQ(io::param<int>(sp, "max_keypoints", 1000), 400);
  EXPECT_DOUBLE_EQ(io::param<double>(sp, "threshold", 0.1), 0.004);
  EXPECT_EQ(io::param<int>(sp, "nms_radius", 4), 4);  // missing key -> default
  EXPECT_EQ(io::param<int>(config.section("features.lines"), "length", 0), 7);
  EXPECT_TRUE(config.has_section("features.lines"));
  EXPECT_FALSE(config.has_section("superglue"));
  const YAML::Node missing = config.section("superglue");  // missing section -> empty node, defaults apply
  EXPECT_EQ(io::param<int>(missing, "layers", 18), 18);
  EXPECT_FALSE(config.has_section("superglue"));  // reading did not insert it
  int value = 3;
  io::read_param(sp, "absent", value);
  EXPECT_EQ(value, 3);
}

TEST(Config, WrongTypeNamesKeyAndLine) {
  const auto config = io::Config::from_string("superpoint:\n  max_keypoints: many\n");
  const std::string message = error_of([&] { io::param<int>(config.section("superpoint"), "max_keypoints", 1); });
  EXPECT_NE(message.find("'max_keypoints'"), std::string::npos) << message;
  EXPECT_NE(message.find("line 2"), std::string::npos) << message;
  EXPECT_NE(message.find("integer"), std::string::npos) << message;
}

TEST(Config, FileErrorsNameTheFile) {
  const auto dir = test::temp_dir("config");
  EXPECT_NE(error_of([&] { io::Config::load(dir / "absent.yaml"); }).find("absent.yaml"), std::string::npos);
  test::write_text(dir / "bad.yaml", "a: [1, 2\nb: 3\n");
  const std::string message = error_of([&] { io::Config::load(dir / "bad.yaml"); });
  EXPECT_NE(message.find("bad.yaml"), std::string::npos) << message;
  EXPECT_NE(message.find("invalid YAML"), std::string::npos) << message;
  test::write_text(dir / "good.yaml", "camera:\n  fx: 1\n");
  EXPECT_TRUE(io::Config::load(dir / "good.yaml").has_section("camera"));
}

TEST(CameraOverrides, SharedAndPerCameraKeys) {
  const YAML::Node camera = YAML::Load(
      "width: 640\nheight: 480\nfx: 400\nfy: 401\ncx: 320\ncy: 240\nbaseline: 0.12\n"
      "right:\n  cx: 321.5\n  distortion_model: radtan\n  distortion_coeffs: [0.1, -0.2, 0.001, 0.002]\n");
  const auto calibration = io::apply_camera_overrides(camera, {});
  EXPECT_EQ(calibration.left.width, 640);
  EXPECT_DOUBLE_EQ(calibration.left.fy, 401);
  EXPECT_DOUBLE_EQ(calibration.left.cx, 320);
  EXPECT_DOUBLE_EQ(calibration.right.cx, 321.5);
  EXPECT_EQ(calibration.right.distortion, io::DistortionModel::radtan);
  EXPECT_EQ(calibration.left.distortion, io::DistortionModel::none);
  EXPECT_TRUE(calibration.rectified);
  EXPECT_DOUBLE_EQ(calibration.T_left_right().translation().x(), 0.12);
  EXPECT_NO_THROW(io::validate_calibration(calibration, "test"));
}

TEST(CameraOverrides, TransformAndErrors) {
  const YAML::Node camera =
      YAML::Load("left:\n  T_body_camera: [0, -1, 0, 0.1,  1, 0, 0, 0,  0, 0, 1, 0,  0, 0, 0, 1]\n");
  const auto calibration = io::apply_camera_overrides(camera, {});
  EXPECT_DOUBLE_EQ(calibration.left.T_body_camera(0, 1), -1.0);
  EXPECT_DOUBLE_EQ(calibration.left.T_body_camera.translation().x(), 0.1);

  EXPECT_NE(error_of([] {
              io::apply_camera_overrides(YAML::Load("left: {distortion_model: fancy}"), {});
            }).find("camera.left.distortion_model"),
            std::string::npos);
  EXPECT_NE(error_of([] {
              io::apply_camera_overrides(YAML::Load("left: {T_body_camera: [2, 0, 0, 0]}"), {});
            }).find("camera.left.T_body_camera"),
            std::string::npos);
  EXPECT_NE(error_of([] { io::apply_camera_overrides(YAML::Load("fx: wide"), {}); }).find("'fx'"), std::string::npos);
  EXPECT_NE(error_of([] { io::validate_calibration({}, "mycalib"); }).find("mycalib"), std::string::npos);
  io::StereoCalibration no_baseline =
      io::apply_camera_overrides(YAML::Load("{width: 10, height: 10, fx: 5, fy: 5, cx: 5, cy: 5}"), {});
  EXPECT_NE(error_of([&] { io::validate_calibration(no_baseline, "x"); }).find("baseline"), std::string::npos);
}

// Kalibr's T_cam_imu (body -> camera) is the inverse of EuRoC's T_BS (camera -> body): the same pose either way.
TEST(CameraOverrides, CameraBodyTransformIsTheInverse) {
  const YAML::Node camera = YAML::Load(
      "left:\n  T_body_camera: [0, -1, 0, 0.1,  1, 0, 0, 0.2,  0, 0, 1, 0.3,  0, 0, 0, 1]\n"
      "right:\n  T_camera_body: [0, 1, 0, -0.2,  -1, 0, 0, 0.1,  0, 0, 1, -0.3]\n");
  const auto calibration = io::apply_camera_overrides(camera, {});
  // The right entry is the left one inverted (R^T, -R^T t), so both cameras sit at the same pose.
  EXPECT_TRUE(calibration.right.T_body_camera.isApprox(calibration.left.T_body_camera, 1e-12))
      << calibration.right.T_body_camera.matrix();
  EXPECT_NEAR(calibration.right.T_body_camera.translation().y(), 0.2, 1e-12);

  const std::string both = error_of([] {
    io::apply_camera_overrides(YAML::Load("left: {T_body_camera: [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0], "
                                          "T_camera_body: [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0]}"),
                               {});
  });
  EXPECT_NE(both.find("not both"), std::string::npos) << both;
  EXPECT_NE(error_of([] {
              io::apply_camera_overrides(YAML::Load("right: {T_camera_body: [1, 0, 0]}"), {});
            }).find("camera.right.T_camera_body"),
            std::string::npos);
}

TEST(KeyReadLog, NamesWhatParamDidNotReadAndNests) {
  const auto config = io::Config::from_string("a: {x: 1, y: 2}\nb:\n  - {z: 3}\n  - {z: 4, w: 5}\nc: [1, 2]\n");
  io::KeyReadLog outer;
  {
    io::KeyReadLog inner;  // records instead of `outer` while it lives
    EXPECT_EQ(io::param<int>(config.section("a"), "x", 0), 1);
    EXPECT_EQ(inner.unread(config.root()),
              (std::vector<std::string>{"a.y (line 1)", "b[0].z (line 3)", "b[1].z (line 4)", "b[1].w (line 4)",
                                        "c (line 5)"}));
  }
  EXPECT_EQ(io::param<int>(config.section("a"), "y", 0), 2);
  EXPECT_EQ(io::param<int>(config.root()["b"][1], "w", 0), 5);
  EXPECT_EQ(io::param<std::vector<int>>(config.root(), "c", {}).size(), 2u);
  EXPECT_EQ(io::param<int>(config.section("a"), "absent", 7), 7);  // a missing key is no trouble
  EXPECT_EQ(outer.unread(config.root()),
            (std::vector<std::string>{"a.x (line 1)", "b[0].z (line 3)", "b[1].z (line 4)"}));
}

TEST(DatasetOptions, FromConfigSection) {
  const auto config = io::Config::from_string(
      "dataset:\n  first_frame: 10\n  last_frame: 99\n  stride: 3\n  max_stereo_dt_ms: 2.5\ncamera:\n  fx: 7\n");
  const auto options = io::load_dataset_options(config.section("dataset"), config.section("camera"));
  EXPECT_EQ(options.range.first, 10u);
  ASSERT_TRUE(options.range.last.has_value());
  EXPECT_EQ(*options.range.last, 99u);
  EXPECT_EQ(options.range.stride, 3u);
  EXPECT_EQ(options.max_stereo_dt_ns, 2'500'000);
  EXPECT_EQ(io::param<double>(options.camera_overrides, "fx", 0.0), 7.0);
  const auto defaults = io::load_dataset_options(YAML::Node());
  EXPECT_EQ(defaults.range.first, 0u);
  EXPECT_FALSE(defaults.range.last.has_value());
  EXPECT_EQ(defaults.range.stride, 1u);
  EXPECT_NE(error_of([] { io::load_dataset_options(YAML::Load("stride: 0")); }).find("'stride'"), std::string::npos);
}
