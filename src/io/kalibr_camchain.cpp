// Kalibr camera-chain files (camchain.yaml, camchain-imucam.yaml): the calibration most visual-inertial datasets
// publish. Per camera: camera_model (pinhole only here), intrinsics [fu, fv, pu, pv], distortion_model (radtan,
// equidistant, none), distortion_coeffs, resolution [w, h]; T_cam_imu (body -> camera, in -imucam files) and, from
// cam1 on, T_cn_cnm1 (previous camera -> this camera). 4x4 transforms are lists of 4 rows.
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "io/kalibr_camchain.hpp"
#include "io/yaml_utils.hpp"

namespace vkvo::io {

namespace fs = std::filesystem;

namespace {

// Camera `name`'s 4x4 transform `key`, 4 rows of 4 numbers; nullopt where absent.
std::optional<Eigen::Isometry3d> read_transform(const YAML::Node& cam, const fs::path& file, const std::string& name,
                                                const char* key) {
  const std::string field = name + "." + key;
  const YAML::Node rows = cam[key];
  if (!rows.IsDefined() || rows.IsNull()) return std::nullopt;
  if (!rows.IsSequence() || rows.size() != 4)
    throw std::runtime_error(fmt::format("{}: field '{}' must be 4 rows of 4 numbers", file.string(), field));
  std::vector<double> values;
  for (std::size_t r = 0; r < 4; ++r) {
    const auto row = required_numbers(rows[r], file, fmt::format("{}[{}]", field, r), 4);
    values.insert(values.end(), row.begin(), row.end());
  }
  try {
    return isometry_from_row_major(values);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(fmt::format("{}: field '{}': {}", file.string(), field, e.what()));
  }
}

CameraCalibration read_camera(const YAML::Node& cam, const fs::path& file, const std::string& name) {
  CameraCalibration camera;
  const YAML::Node model = cam["camera_model"];
  if (model.IsDefined() && model.as<std::string>() != "pinhole")
    throw std::runtime_error(fmt::format("{}: {}.camera_model '{}' is not supported (pinhole only)", file.string(),
                                         name, model.as<std::string>()));
  const auto intrinsics = required_numbers(cam["intrinsics"], file, name + ".intrinsics", 4);
  camera.fx = intrinsics[0];
  camera.fy = intrinsics[1];
  camera.cx = intrinsics[2];
  camera.cy = intrinsics[3];
  camera.set_origin({"fx", "fy", "cx", "cy"}, origin_of(cam["intrinsics"], file, name + ".intrinsics"));
  std::tie(camera.width, camera.height) = required_resolution(cam["resolution"], file, name + ".resolution");
  camera.set_origin({"width", "height"}, origin_of(cam["resolution"], file, name + ".resolution"));
  const std::string distortion = required_string(cam["distortion_model"], file, name + ".distortion_model");
  try {
    camera.distortion = parse_distortion_model(distortion);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(fmt::format("{}: field '{}.distortion_model': {}", file.string(), name, e.what()));
  }
  if (camera.distortion != DistortionModel::none) {
    camera.distortion_coeffs = required_numbers(cam["distortion_coeffs"], file, name + ".distortion_coeffs", 0);
    camera.set_origin({"distortion_coeffs"}, origin_of(cam["distortion_coeffs"], file, name + ".distortion_coeffs"));
  }
  return camera;
}

}  // namespace

StereoCalibration read_kalibr_camchain(const fs::path& file) {
  if (!fs::is_regular_file(file))
    throw std::runtime_error(fmt::format("{}: Kalibr camchain file is missing", file.string()));
  const YAML::Node root = load_yaml_file(file);
  if (!root.IsMap()) throw std::runtime_error(fmt::format("{}: expected a YAML map", file.string()));
  for (const char* cam : {"cam0", "cam1"})
    if (const YAML::Node node = root[cam]; !node.IsDefined() || !node.IsMap())
      throw std::runtime_error(fmt::format("{}: missing camera '{}'", file.string(), cam));

  StereoCalibration calibration;
  calibration.left = read_camera(root["cam0"], file, "cam0");
  calibration.right = read_camera(root["cam1"], file, "cam1");
  calibration.rectified = false;
  // The body is the IMU where both cameras have T_cam_imu, else cam0; then cam1 sits where T_cn_cnm1 puts it.
  const auto left_from_body = read_transform(root["cam0"], file, "cam0", "T_cam_imu");
  const auto right_from_body = read_transform(root["cam1"], file, "cam1", "T_cam_imu");
  if (left_from_body && right_from_body) {
    calibration.left.T_body_camera = left_from_body->inverse();
    calibration.right.T_body_camera = right_from_body->inverse();
    calibration.left.set_origin({"T_body_camera"}, origin_of(root["cam0"]["T_cam_imu"], file, "cam0.T_cam_imu"));
    calibration.right.set_origin({"T_body_camera"}, origin_of(root["cam1"]["T_cam_imu"], file, "cam1.T_cam_imu"));
  } else {
    const auto right_from_left = read_transform(root["cam1"], file, "cam1", "T_cn_cnm1");
    if (!right_from_left)
      throw std::runtime_error(fmt::format(
          "{}: cam1 has neither T_cn_cnm1 nor (with cam0) T_cam_imu: where it sits is unknown", file.string()));
    calibration.right.T_body_camera = right_from_left->inverse();
    calibration.right.set_origin({"T_body_camera"}, origin_of(root["cam1"]["T_cn_cnm1"], file, "cam1.T_cn_cnm1"));
  }
  return calibration;
}

}  // namespace vkvo::io
