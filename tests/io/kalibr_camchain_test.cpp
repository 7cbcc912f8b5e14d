// Kalibr camchain files -> stereo calibration, and the config's camera.kalibr key.
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "io/config.hpp"
#include "io/kalibr_camchain.hpp"

namespace fs = std::filesystem;
using namespace vkvo;

using test::error_of;
using test::write_text;

namespace {

// cam1 sits 0.1 m along cam0's x, turned 90 degrees about z; the IMU 0.05 m below cam0 (camera y is down).
const char* kCamchain = R"(cam0:
  camera_model: pinhole
  intrinsics: [400.0, 401.0, 320.0, 240.0]
  distortion_model: radtan
  distortion_coeffs: [-0.1, 0.02, 0.001, -0.002]
  resolution: [640, 480]
  rostopic: /cam0/image_raw
cam1:
  T_cn_cnm1:
  - [0.0, 1.0, 0.0, 0.0]
  - [-1.0, 0.0, 0.0, 0.1]
  - [0.0, 0.0, 1.0, 0.0]
  - [0.0, 0.0, 0.0, 1.0]
  camera_model: pinhole
  intrinsics: [402.0, 403.0, 321.0, 241.0]
  distortion_model: equidistant
  distortion_coeffs: [0.01, -0.002, 0.0003, -0.00004]
  resolution: [640, 480]
)";

}  // namespace

TEST(KalibrCamchain, CamerasAndTheChainTransform) {
  const fs::path file = test::temp_dir("kalibr") / "camchain.yaml";
  write_text(file, kCamchain);
  const io::StereoCalibration calibration = io::read_kalibr_camchain(file);
  EXPECT_FALSE(calibration.rectified);
  EXPECT_EQ(calibration.left.width, 640);
  EXPECT_DOUBLE_EQ(calibration.left.fy, 401.0);
  EXPECT_DOUBLE_EQ(calibration.right.cx, 321.0);
  EXPECT_EQ(calibration.left.distortion, io::DistortionModel::radtan);
  EXPECT_EQ(calibration.right.distortion, io::DistortionModel::equidistant);
  ASSERT_EQ(calibration.right.distortion_coeffs.size(), 4u);
  EXPECT_DOUBLE_EQ(calibration.right.distortion_coeffs[3], -0.00004);
  // The body is cam0; T_cn_cnm1 maps cam0 coordinates into cam1's, so cam1's centre is at -R^T t in cam0.
  EXPECT_TRUE(calibration.left.T_body_camera.isApprox(Eigen::Isometry3d::Identity()));
  const Eigen::Vector3d right_centre = calibration.T_left_right().translation();
  EXPECT_NEAR(right_centre.x(), 0.1, 1e-12) << right_centre.transpose();
  EXPECT_NEAR(right_centre.norm(), 0.1, 1e-12);
  const Eigen::Vector3d x_of_right = calibration.T_left_right().rotation().col(0);  // cam1's x axis in cam0
  EXPECT_NEAR(x_of_right.y(), 1.0, 1e-12) << x_of_right.transpose();
}

TEST(KalibrCamchain, ImuCamFileUsesTheImuAsBody) {
  std::string text = kCamchain;
  const std::string imu0 =
      "  T_cam_imu:\n  - [1.0, 0.0, 0.0, 0.0]\n  - [0.0, 1.0, 0.0, 0.05]\n"
      "  - [0.0, 0.0, 1.0, 0.0]\n  - [0.0, 0.0, 0.0, 1.0]\n";
  // cam1 from the IMU = cam1 from cam0 * cam0 from the IMU.
  const std::string imu1 =
      "  T_cam_imu:\n  - [0.0, 1.0, 0.0, 0.05]\n  - [-1.0, 0.0, 0.0, 0.1]\n"
      "  - [0.0, 0.0, 1.0, 0.0]\n  - [0.0, 0.0, 0.0, 1.0]\n";
  text.insert(text.find("cam1:\n"), imu0);
  text += imu1;
  const fs::path file = test::temp_dir("kalibr_imu") / "camchain-imucam.yaml";
  write_text(file, text);
  const io::StereoCalibration calibration = io::read_kalibr_camchain(file);
  EXPECT_NEAR(calibration.left.T_body_camera.translation().y(), -0.05, 1e-12);  // cam0 0.05 m above the IMU
  EXPECT_NEAR(calibration.T_left_right().translation().x(), 0.1, 1e-12);
  EXPECT_NEAR(calibration.baseline(), 0.1, 1e-12);
}

TEST(KalibrCamchain, ConfigKeyAndOverridesOnTop) {
  const fs::path file = test::temp_dir("kalibr_cfg") / "camchain.yaml";
  write_text(file, kCamchain);
  const io::StereoCalibration calibration =
      io::apply_camera_overrides(YAML::Load("{kalibr: " + file.string() + ", right: {fx: 410}}"), {});
  EXPECT_DOUBLE_EQ(calibration.left.fx, 400.0);
  EXPECT_DOUBLE_EQ(calibration.right.fx, 410.0);
  EXPECT_NO_THROW(io::validate_calibration(calibration, "kalibr"));
}

TEST(KalibrCamchain, ErrorsNameTheFileAndField) {
  const fs::path dir = test::temp_dir("kalibr_errors");
  const auto message_for = [&](const std::string& text) {
    write_text(dir / "camchain.yaml", text);
    return error_of([&] { io::read_kalibr_camchain(dir / "camchain.yaml"); });
  };
  std::string text = kCamchain;
  std::string message = message_for(text.substr(0, text.find("cam1:")));
  EXPECT_NE(message.find("missing camera 'cam1'"), std::string::npos) << message;
  EXPECT_NE(message.find("camchain.yaml"), std::string::npos) << message;

  text = kCamchain;
  text.replace(text.find("equidistant"), 11, "fov");
  message = message_for(text);
  EXPECT_NE(message.find("cam1.distortion_model"), std::string::npos) << message;

  text = kCamchain;
  text.replace(text.find("pinhole"), 7, "omni");
  EXPECT_NE(message_for(text).find("not supported (pinhole only)"), std::string::npos);

  text = kCamchain;
  text.replace(text.find("  intrinsics: [400.0"), 2, "  x");
  EXPECT_NE(message_for(text).find("missing field 'cam0.intrinsics'"), std::string::npos);

  text = kCamchain;
  text.replace(text.find("  T_cn_cnm1"), 11, "  T_other");
  EXPECT_NE(message_for(text).find("neither T_cn_cnm1"), std::string::npos);

  EXPECT_NE(error_of([&] { io::read_kalibr_camchain(dir / "absent.yaml"); }).find("missing"), std::string::npos);
}
