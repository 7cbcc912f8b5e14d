#pragma once
// Raw camera calibration as datasets give it (before rectification). geometry/ builds cameras from it.
#include <array>
#include <initializer_list>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vkvo::io {

enum class DistortionModel { none, radtan, equidistant };

// Where a calibration value was read, so that a check made after all sources are merged can name the line to fix.
struct ValueOrigin {
  std::string file;  // empty: the config's camera section
  std::string key;   // as written there: "intrinsics", "cam1.distortion_coeffs", "camera.left.fx", "P0"
  int line = 0;      // 1-based; 0 when unknown
};

struct CameraCalibration {
  int width = 0;
  int height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  DistortionModel distortion = DistortionModel::none;
  std::vector<double> distortion_coeffs;  // radtan: k1 k2 p1 p2 [k3]; equidistant: k1 k2 k3 k4
  Eigen::Isometry3d T_body_camera = Eigen::Isometry3d::Identity();  // sensor (camera) frame -> body frame
  // By field name (width, height, fx, fy, cx, cy, distortion_coeffs, T_body_camera); filled by the readers.
  std::map<std::string, ValueOrigin> origins;

  void set_origin(std::initializer_list<const char*> fields, const ValueOrigin& origin) {
    for (const char* field : fields) origins[field] = origin;
  }
};

struct StereoCalibration {
  CameraCalibration left;
  CameraCalibration right;
  // True when the images are already rectified (KITTI): then left/right share K, no distortion, and the
  // right camera is translated by -baseline along x.
  bool rectified = false;

  // Pose of the right camera in the left camera's frame (x_left = T_left_right * x_right).
  Eigen::Isometry3d T_left_right() const { return left.T_body_camera.inverse() * right.T_body_camera; }
  // Distance between the two optical centres in metres.
  double baseline() const { return T_left_right().translation().norm(); }
};

}  // namespace vkvo::io
