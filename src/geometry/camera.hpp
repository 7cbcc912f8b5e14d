#pragma once
// Rectified pinhole cameras and the stereo rig that produces them from raw calibrations.
// Conventions: pixel (u, v) with the origin at the centre of the top-left pixel (OpenCV); camera frame x right,
// y down, z forward. T_a_b maps coordinates in frame b to frame a.
#include <optional>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "io/calibration.hpp"

namespace vkvo::geometry {

// Undistorted pinhole camera (after rectification).
struct PinholeCamera {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  int width = 0, height = 0;

  Eigen::Matrix3d K() const;

  // Projection of a point in the camera frame; J (optional) = d pixel / d point. The point must have z > 0.
  Eigen::Vector2d project(const Eigen::Vector3d& p_camera, Eigen::Matrix<double, 2, 3>* J = nullptr) const;
  // Ray through a pixel, scaled to z = 1; J (optional) = d ray / d pixel.
  Eigen::Vector3d backproject(const Eigen::Vector2d& pixel, Eigen::Matrix<double, 3, 2>* J = nullptr) const;
  bool in_image(const Eigen::Vector2d& pixel, double border = 0.0) const;
};

// A rectified stereo pair: both cameras share K; the right camera sits at +baseline along the left camera's x
// axis (p_right = p_left - [baseline, 0, 0]), so a point at depth z appears at u_right = u_left - fx * b / z.
struct StereoCamera {
  PinholeCamera camera;
  double baseline = 0;

  // Pixel in the right image of a point given in the (rectified) left camera frame.
  Eigen::Vector2d project_right(const Eigen::Vector3d& p_left) const;
  Eigen::Isometry3d T_left_right() const;
};

// Builds the rectified stereo camera from two raw calibrations (OpenCV stereoRectify, radtan or equidistant) and
// remaps raw images into it. For already rectified input (KITTI) the remap is the identity.
class StereoRig {
 public:
  explicit StereoRig(const io::StereoCalibration& calibration);

  const StereoCamera& stereo() const { return stereo_; }
  const PinholeCamera& camera() const { return stereo_.camera; }
  double baseline() const { return stereo_.baseline; }
  cv::Size image_size() const { return {stereo_.camera.width, stereo_.camera.height}; }
  bool needs_remap() const { return !left_map1_.empty(); }

  // Pose of the rectified left camera in the body frame and in the raw left (cam0) frame. Trajectories estimated
  // in the rectified frame are expressed in cam0 with T_cam0_rect * T * T_cam0_rect^-1.
  const Eigen::Isometry3d& T_body_rectified() const { return T_body_rect_; }
  const Eigen::Isometry3d& T_rawleft_rectified() const { return T_rawleft_rect_; }

  // Remaps raw images to the rectified pair (bilinear). Input images keep their type; for rectified input this is a
  // shallow copy.
  void rectify(const cv::Mat& raw_left, const cv::Mat& raw_right, cv::Mat& left, cv::Mat& right) const;

 private:
  StereoCamera stereo_;
  Eigen::Isometry3d T_body_rect_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_rawleft_rect_ = Eigen::Isometry3d::Identity();
  cv::Mat left_map1_, left_map2_, right_map1_, right_map2_;
};

}  // namespace vkvo::geometry
