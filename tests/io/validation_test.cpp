// io::validate_config_values and io::validate_calibration: every number a user gives is finite and in range, the
// message naming the file, the key path and its line (issue 36).
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "io/config.hpp"
#include "io/dataset.hpp"
#include "io/kalibr_camchain.hpp"
#include "io/validation.hpp"

using namespace vkvo;
using test::error_of;

namespace {

void expect_rejected(const std::string& yaml, const std::vector<std::string>& fragments) {
  const auto config = io::Config::from_string(yaml, "bad.yaml");
  const std::string message = error_of([&] { io::validate_config_values(config); });
  ASSERT_NE(message, "<no exception>") << "accepted:\n" << yaml;
  EXPECT_NE(message.find("bad.yaml"), std::string::npos) << message;
  for (const auto& fragment : fragments) EXPECT_NE(message.find(fragment), std::string::npos) << message;
}

io::CameraCalibration pinhole() {
  io::CameraCalibration c;
  c.width = 752, c.height = 480, c.fx = 458.0, c.fy = 457.0, c.cx = 367.0, c.cy = 248.0;
  return c;
}

io::StereoCalibration stereo_of(const io::CameraCalibration& left) {
  io::StereoCalibration s;
  s.left = left;
  s.right = left;
  s.right.T_body_camera.translation().x() = 0.11;
  return s;
}

}  // namespace

TEST(ConfigValidation, NegativeThreadCountNamesKeyPathAndLine) {
  expect_rejected("tracking:\n  use_lines: true\noptimization:\n  num_threads: -2\n",
                  {"optimization.num_threads", "line 4", "-2", "[1, inf)"});
}

TEST(ConfigValidation, NanAndInfinityAreRejectedAnywhere) {
  expect_rejected("point_matcher:\n  match_threshold: .nan\n", {"point_matcher.match_threshold", "line 2", "finite"});
  expect_rejected("camera:\n  left:\n    distortion_coeffs: [0.1, .inf, 0, 0]\n",
                  {"camera.left.distortion_coeffs[1]", "line 3", "finite"});
}

TEST(ConfigValidation, ThresholdsAndRatiosOutsideTheUnitInterval) {
  expect_rejected("nn_matcher:\n  ratio: 1.5\n", {"nn_matcher.ratio", "[0, 1]"});
  expect_rejected("point_detector:\n  keypoint_threshold: -0.1\n", {"point_detector.keypoint_threshold"});
  expect_rejected("stereo:\n  max_depth: -3\n", {"stereo.max_depth", "(0, inf)"});
}

TEST(ConfigValidation, ShippedConfigsPass) {
  for (const auto& entry : std::filesystem::directory_iterator(test::source_dir() / "config")) {
    if (entry.path().extension() != ".yaml") continue;
    EXPECT_NO_THROW(io::validate_config_values(io::Config::load(entry.path()))) << entry.path();
  }
}

TEST(CalibrationValidation, NonFiniteAndAbsurdDistortionAreRejected) {
  io::CameraCalibration c = pinhole();
  c.distortion = io::DistortionModel::radtan;
  c.distortion_coeffs = {-0.28, 0.07, 0.0002, 0.00002};  // EuRoC MH_01 cam0
  EXPECT_NO_THROW(io::validate_calibration(stereo_of(c), "cam.yaml"));
  c.distortion_coeffs[0] = std::nan("");
  EXPECT_NE(error_of([&] { io::validate_calibration(stereo_of(c), "cam.yaml"); }).find("distortion_coeffs"),
            std::string::npos);
  c.distortion_coeffs[0] = -1e6;
  const std::string message = error_of([&] { io::validate_calibration(stereo_of(c), "cam.yaml"); });
  EXPECT_NE(message.find("folds over"), std::string::npos) << message;
  EXPECT_NE(message.find("cam.yaml"), std::string::npos) << message;
}

TEST(CalibrationValidation, InfiniteIntrinsicsAreRejected) {
  io::CameraCalibration c = pinhole();
  c.cx = std::numeric_limits<double>::infinity();
  EXPECT_NE(error_of([&] { io::validate_calibration(stereo_of(c), "cam.yaml"); }).find("cx"), std::string::npos);
  c = pinhole();
  c.fx = std::numeric_limits<double>::infinity();
  EXPECT_NE(error_of([&] { io::validate_calibration(stereo_of(c), "cam.yaml"); }).find("fx"), std::string::npos);
}

// A value that passes the readers but fails validation is traced back to the file, key and line it came from, in
// each of the three places a calibration is read: a EuRoC sensor.yaml, a Kalibr camchain and the config.
// A resolution beyond int's range was converted to int unchecked (UB; found by the kalibr_camchain fuzzer):
// both readers of a `resolution` list refuse it with file, field and line.
TEST(CalibrationValidation, ResolutionMustBeWholePixelsInRange) {
  const std::filesystem::path dir = test::temp_dir("calibration_resolution");
  test::write_text(dir / "sensor.yaml",
                   "camera_model: pinhole\nresolution: [2.2e84, 480]\nintrinsics: [458.0, 457.0, 367.0, 248.0]\n"
                   "distortion_model: radial-tangential\ndistortion_coefficients: [0, 0, 0, 0]\n");
  std::string message = error_of([&] { io::read_euroc_camera_yaml(dir / "sensor.yaml"); });
  EXPECT_NE(message.find("sensor.yaml: field 'resolution' (line 2): 2.2e+84 is not a whole number of pixels"),
            std::string::npos)
      << message;
  test::write_text(dir / "camchain.yaml",
                   "cam0:\n  camera_model: pinhole\n  intrinsics: [458.0, 457.0, 367.0, 248.0]\n"
                   "  resolution: [752.5, 480]\n  distortion_model: radtan\n  distortion_coeffs: [0, 0, 0, 0]\n"
                   "cam1:\n  camera_model: pinhole\n  intrinsics: [458.0, 457.0, 367.0, 248.0]\n"
                   "  resolution: [752, 480]\n  distortion_model: radtan\n  distortion_coeffs: [0, 0, 0, 0]\n"
                   "  T_cn_cnm1:\n  - [1, 0, 0, -0.11]\n  - [0, 1, 0, 0]\n  - [0, 0, 1, 0]\n  - [0, 0, 0, 1]\n");
  message = error_of([&] { io::read_kalibr_camchain(dir / "camchain.yaml"); });
  EXPECT_NE(message.find("camchain.yaml: field 'cam0.resolution' (line 4): 752.5 is not a whole number"),
            std::string::npos)
      << message;
}

TEST(CalibrationValidation, MessagesNameTheFileKeyAndLineTheValueCameFrom) {
  const std::filesystem::path dir = test::temp_dir("calibration_origin");
  const std::string euroc =
      "camera_model: pinhole\n"
      "resolution: [752, 480]\n"
      "T_BS:\n"
      "  data: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\n"
      "intrinsics: [-458.0, 457.0, 367.0, 248.0]\n"
      "distortion_model: radial-tangential\n"
      "distortion_coefficients: [-0.28, 0.07, 0.0002, 0.00002]\n";
  test::write_text(dir / "sensor.yaml", euroc);
  io::StereoCalibration stereo = stereo_of(io::read_euroc_camera_yaml(dir / "sensor.yaml"));
  std::string message = error_of([&] { io::validate_calibration(stereo, "dataset"); });
  EXPECT_NE(message.find("sensor.yaml: intrinsics (line 5): left camera: field 'fx'"), std::string::npos) << message;

  const std::string camchain =
      "cam0:\n"
      "  camera_model: pinhole\n"
      "  intrinsics: [458.0, 457.0, 367.0, 248.0]\n"
      "  resolution: [752, 480]\n"
      "  distortion_model: radtan\n"
      "  distortion_coeffs: [-0.28, 0.07, 0.0002, 0.00002]\n"
      "cam1:\n"
      "  camera_model: pinhole\n"
      "  intrinsics: [458.0, 457.0, 367.0, 248.0]\n"
      "  resolution: [752, 480]\n"
      "  distortion_model: radtan\n"
      "  distortion_coeffs: [-1.0e6, 0.07, 0.0002, 0.00002]\n"
      "  T_cn_cnm1:\n"
      "  - [1, 0, 0, -0.11]\n"
      "  - [0, 1, 0, 0]\n"
      "  - [0, 0, 1, 0]\n"
      "  - [0, 0, 0, 1]\n";
  test::write_text(dir / "camchain.yaml", camchain);
  message = error_of([&] { io::validate_calibration(io::read_kalibr_camchain(dir / "camchain.yaml"), "dataset"); });
  EXPECT_NE(message.find("camchain.yaml: cam1.distortion_coeffs (line 12): right camera: field 'distortion_coeffs' "
                         "the radial distortion folds over"),
            std::string::npos)
      << message;

  // The config's camera section overrides one value of the file; the message points at the override.
  const auto config = io::Config::from_string("camera:\n  left:\n    fx: 400\n    cy: -1\n", "run.yaml");
  stereo =
      io::apply_camera_overrides(config.section("camera"), io::read_kalibr_camchain(dir / "camchain.yaml"), "run.yaml");
  message = error_of([&] { io::validate_calibration(stereo, "dataset"); });
  EXPECT_NE(message.find("run.yaml: camera.left.cy (line 4): left camera: field 'cy'"), std::string::npos) << message;
}
