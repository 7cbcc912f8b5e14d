// The shipped config files: every one loads, and the cameras of those that carry them (OIVIO, UMA-VI, whose bags
// come without a sensor.yaml) rectify as AirVO's own camera files for those datasets say they do. Those files give
// the rectification OpenCV computed from the same published calibration: R1, R2, the rectified P and bf (baseline
// times the rectified focal length). A transform read with the wrong convention (UMA-VI's is Kalibr's T_cam_imu,
// OIVIO's EuRoC's T_BS) moves R1 and R2 by a degree; the tolerances are a few times the files' rounding.
#include <filesystem>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "common/test_support.hpp"
#include "features/lines/line_params.hpp"
#include "geometry/camera.hpp"
#include "io/config.hpp"
#include "system/vo_config.hpp"

namespace vkvo::system {
namespace {

namespace fs = std::filesystem;

fs::path config_file(const char* name) { return test::source_dir() / "config" / name; }

// The calibration a config's camera section gives on its own (as for a dataset folder without sensor.yaml).
io::StereoCalibration calibration_of(const fs::path& file) {
  const VoConfig config = load_vo_config(file);
  const io::StereoCalibration calibration = io::apply_camera_overrides(config.dataset.camera_overrides, {});
  io::validate_calibration(calibration, file.string());
  return calibration;
}

double angle_between(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

struct ReferenceRectification {
  Eigen::Matrix3d left_R, right_R;  // raw camera -> rectified camera (OpenCV's R1, R2)
  double f, cx, cy;                 // the rectified camera (P1 = P2 but for the baseline)
  double bf;                        // baseline times f
};

void expect_rectification(const fs::path& config, const ReferenceRectification& reference) {
  SCOPED_TRACE(config.string());
  const io::StereoCalibration calibration = calibration_of(config);
  const geometry::StereoRig rig(calibration);
  EXPECT_NEAR(rig.camera().fx, reference.f, 1e-3);
  EXPECT_NEAR(rig.camera().fy, reference.f, 1e-3);
  EXPECT_NEAR(rig.camera().cx, reference.cx, 1e-3);
  EXPECT_NEAR(rig.camera().cy, reference.cy, 1e-3);
  EXPECT_NEAR(rig.baseline() * rig.camera().fx, reference.bf, 1e-3);
  const Eigen::Matrix3d left_R = rig.T_rawleft_rectified().rotation().transpose();
  // The rectified cameras share one orientation: R2 = R1 * R_left_right.
  const Eigen::Matrix3d right_R = left_R * calibration.T_left_right().rotation();
  EXPECT_LT(angle_between(left_R, reference.left_R), 1e-4) << left_R;
  EXPECT_LT(angle_between(right_R, reference.right_R), 1e-4) << right_R;
  EXPECT_EQ(rig.image_size(), cv::Size(calibration.left.width, calibration.left.height));
}

TEST(DatasetConfigs, EveryShippedConfigLoads) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(test::source_dir() / "config")) {
    if (entry.path().extension() != ".yaml" || entry.path().filename() == "lines.yaml") continue;
    SCOPED_TRACE(entry.path().string());
    const VoConfig config = load_vo_config(entry.path());
    EXPECT_GT(config.keyframe.max_frames, 0);
    if (config.dataset.camera_overrides.IsDefined() && !config.dataset.camera_overrides.IsNull()) {
      EXPECT_NO_THROW(calibration_of(entry.path()));
    }
    ++count;
  }
  EXPECT_GE(count, 4);  // euroc, kitti, oivio, uma_vi
}

// config/lines.yaml is `vkvo lines --config`'s: only its lines section, every key of it a parameter.
TEST(DatasetConfigs, LinesConfigHasOnlyParameters) {
  const io::Config config = io::Config::load(config_file("lines.yaml"));
  const io::KeyReadLog key_log;
  const features::LinePipelineParams params = features::load_line_pipeline_params(config.section("lines"));
  EXPECT_NO_THROW(key_log.require_all_read(config.root(), "", config.origin()));
  EXPECT_FALSE(params.detector.merge_stages.empty());
}

// AirVO's configs/oivio.yaml: LEFT.R, RIGHT.R, LEFT.P, bf.
TEST(DatasetConfigs, OivioCamerasRectifyAsAirVoComputed) {
  ReferenceRectification reference;
  reference.left_R << 0.9999935662, -0.0033233921, -0.0013500365, 0.0033244884, 0.9999941453, 0.0008106159,
      0.0013473346, -0.0008150989, 0.9999987602;
  reference.right_R << 0.9999943337, -0.0022228281, 0.0025281572, 0.0022248824, 0.9999971969, -0.0008100474,
      -0.0025263495, 0.0008156677, 0.9999964761;
  reference.f = 644.6438364153;
  reference.cx = 637.7982711792;
  reference.cy = 355.1050758362;
  reference.bf = 32.3252131124;
  expect_rectification(config_file("oivio.yaml"), reference);
}

// AirVO's configs/uma_bumblebee.yaml (equidistant model): LEFT.R, RIGHT.R, LEFT.P, bf.
ReferenceRectification uma_vi_reference() {
  ReferenceRectification reference;
  reference.left_R << 0.9999757844, -0.0030431402, 0.0062585921, 0.0030488685, 0.9999949418, -0.0009059397,
      -0.0062558036, 0.0009249994, 0.9999800044;
  reference.right_R << 0.9999861135, -0.0048552073, 0.0020493192, 0.0048533292, 0.9999877989, 0.0009204513,
      -0.0020537631, -0.0009104925, 0.9999974765;
  reference.f = 437.0655449072;
  reference.cx = 526.2194189577;
  reference.cy = 393.3895879877;
  reference.bf = 52.1485318013;
  return reference;
}

TEST(DatasetConfigs, UmaViCamerasRectifyAsAirVoComputed) {
  expect_rectification(config_file("uma_vi.yaml"), uma_vi_reference());
}

// The same calibration in the form Kalibr writes it (camchain-imucam.yaml: T_cam_imu as 4 rows), named by a
// config's camera.kalibr relative to the config file: the same rig.
TEST(DatasetConfigs, KalibrCamchainGivesTheSameRig) {
  const fs::path dir = test::temp_dir("kalibr_uma");
  test::write_text(dir / "calib" / "camchain-imucam.yaml", R"(cam0:
  T_cam_imu:
  - [-0.9999075129222311, 0.009129044547616321, 0.010080979482447605, 0.04494077481347731]
  - [-0.009349824313881894, -0.9997125937593437, -0.022075114139336903, 0.11756299478603587]
  - [0.009876557445660702, -0.022167327863611475, 0.9997054882256121, 0.009662092028551384]
  - [0.0, 0.0, 0.0, 1.0]
  camera_model: pinhole
  distortion_coeffs: [-0.06871322616238257, 0.02451994273357104, -0.02288817712592593, 0.005970525621928401]
  distortion_model: equidistant
  intrinsics: [548.675336190778, 549.8818969986276, 516.3866093184781, 399.5429120347567]
  resolution: [1024, 768]
cam1:
  T_cam_imu:
  - [-0.9998724792210668, 0.007228050454964115, 0.014240104737598703, -0.0741199925822667]
  - [-0.007567637071889531, -0.9996847674053032, -0.023939437899691232, 0.11804314089236007]
  - [0.014062580327431065, -0.024044149068442884, 0.9996119860876564, 0.009444780183617524]
  - [0.0, 0.0, 0.0, 1.0]
  camera_model: pinhole
  distortion_coeffs: [-0.05876304711291024, 0.006137940939145979, -0.007300242063869814, 0.001414838413761872]
  distortion_model: equidistant
  intrinsics: [546.704969318968, 547.905312283432, 524.6107126324622, 381.4119390580929]
  resolution: [1024, 768]
)");
  test::write_text(dir / "uma_kalibr.yaml", "camera:\n  kalibr: calib/camchain-imucam.yaml\n");
  expect_rectification(dir / "uma_kalibr.yaml", uma_vi_reference());
}

}  // namespace
}  // namespace vkvo::system
