#pragma once
// Reader for Kalibr's camera-chain calibration files (camchain.yaml / camchain-imucam.yaml).
#include <filesystem>

#include "io/calibration.hpp"

namespace vkvo::io {

// cam0 and cam1 of a Kalibr camchain (pinhole cameras; radtan, equidistant or no distortion). The body frame is
// the IMU where both cameras give T_cam_imu, else cam0 (cam1 placed by its T_cn_cnm1). Throws std::runtime_error
// naming the file and the field that is missing or malformed.
StereoCalibration read_kalibr_camchain(const std::filesystem::path& file);

}  // namespace vkvo::io
