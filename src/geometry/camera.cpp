#include "geometry/camera.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

namespace vkvo::geometry {

Eigen::Matrix3d PinholeCamera::K() const {
  Eigen::Matrix3d K;
  K << fx, 0, cx, 0, fy, cy, 0, 0, 1;
  return K;
}

Eigen::Vector2d PinholeCamera::project(const Eigen::Vector3d& p, Eigen::Matrix<double, 2, 3>* J) const {
  const double inv_z = 1.0 / p.z();
  const double x = p.x() * inv_z, y = p.y() * inv_z;
  if (J) {
    *J << fx * inv_z, 0, -fx * x * inv_z,  //
        0, fy * inv_z, -fy * y * inv_z;
  }
  return {fx * x + cx, fy * y + cy};
}

Eigen::Vector3d PinholeCamera::backproject(const Eigen::Vector2d& pixel, Eigen::Matrix<double, 3, 2>* J) const {
  if (J) *J << 1.0 / fx, 0, 0, 1.0 / fy, 0, 0;
  return {(pixel.x() - cx) / fx, (pixel.y() - cy) / fy, 1.0};
}

bool PinholeCamera::in_image(const Eigen::Vector2d& pixel, double border) const {
  return pixel.x() >= border && pixel.y() >= border && pixel.x() <= width - 1 - border &&
         pixel.y() <= height - 1 - border;
}

Eigen::Vector2d StereoCamera::project_right(const Eigen::Vector3d& p_left) const {
  return camera.project(p_left - Eigen::Vector3d(baseline, 0, 0));
}

Eigen::Isometry3d StereoCamera::T_left_right() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(baseline, 0, 0);
  return T;
}

namespace {

cv::Mat camera_matrix(const io::CameraCalibration& c) {
  return (cv::Mat_<double>(3, 3) << c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1);
}

cv::Mat distortion_vector(const io::CameraCalibration& c, const char* side) {
  const auto& d = c.distortion_coeffs;
  switch (c.distortion) {
    case io::DistortionModel::none: return cv::Mat::zeros(4, 1, CV_64F);
    case io::DistortionModel::radtan:  // OpenCV order k1 k2 p1 p2 [k3] is the EuRoC order
      if (d.size() != 4 && d.size() != 5)
        throw std::runtime_error(std::string("stereo rig: ") + side + " radtan distortion needs 4 or 5 coefficients");
      break;
    case io::DistortionModel::equidistant:  // OpenCV fisheye k1..k4
      if (d.size() != 4)
        throw std::runtime_error(std::string("stereo rig: ") + side + " equidistant distortion needs 4 coefficients");
      break;
  }
  return cv::Mat(d, true);
}

PinholeCamera pinhole_from(const cv::Mat& P, int width, int height) {
  PinholeCamera cam;
  cam.fx = P.at<double>(0, 0);
  cam.fy = P.at<double>(1, 1);
  cam.cx = P.at<double>(0, 2);
  cam.cy = P.at<double>(1, 2);
  cam.width = width;
  cam.height = height;
  return cam;
}

}  // namespace

StereoRig::StereoRig(const io::StereoCalibration& calib) {
  const auto& L = calib.left;
  const auto& R = calib.right;
  if (L.width <= 0 || L.height <= 0 || L.width != R.width || L.height != R.height)
    throw std::runtime_error("stereo rig: left and right image sizes must be positive and equal");
  const Eigen::Isometry3d T_right_left = R.T_body_camera.inverse() * L.T_body_camera;

  if (calib.rectified) {
    if (L.distortion != io::DistortionModel::none || R.distortion != io::DistortionModel::none)
      throw std::runtime_error("stereo rig: rectified input must not carry distortion");
    stereo_.camera = {L.fx, L.fy, L.cx, L.cy, L.width, L.height};
    const Eigen::Vector3d t_left_right = T_right_left.inverse().translation();
    if (t_left_right.x() <= 0 || std::abs(t_left_right.y()) + std::abs(t_left_right.z()) > 1e-3 * t_left_right.x())
      throw std::runtime_error("stereo rig: rectified right camera must be displaced along +x of the left camera");
    stereo_.baseline = t_left_right.x();
    T_body_rect_ = L.T_body_camera;
    return;
  }

  if ((L.distortion == io::DistortionModel::equidistant) != (R.distortion == io::DistortionModel::equidistant))
    throw std::runtime_error("stereo rig: mixing equidistant and radtan cameras is not supported");
  const bool fisheye = L.distortion == io::DistortionModel::equidistant;
  const cv::Mat K1 = camera_matrix(L), K2 = camera_matrix(R);
  const cv::Mat D1 = distortion_vector(L, "left"), D2 = distortion_vector(R, "right");
  cv::Mat rot, trans;  // x_right = rot * x_left + trans
  cv::eigen2cv(Eigen::Matrix3d(T_right_left.linear()), rot);
  cv::eigen2cv(Eigen::Vector3d(T_right_left.translation()), trans);
  const cv::Size size(L.width, L.height);
  cv::Mat R1, R2, P1, P2, Q;
  if (fisheye) {
    cv::fisheye::stereoRectify(K1, D1, K2, D2, size, rot, trans, R1, R2, P1, P2, Q, cv::CALIB_ZERO_DISPARITY, size, 0.0,
                               1.0);
    cv::fisheye::initUndistortRectifyMap(K1, D1, R1, P1, size, CV_16SC2, left_map1_, left_map2_);
    cv::fisheye::initUndistortRectifyMap(K2, D2, R2, P2, size, CV_16SC2, right_map1_, right_map2_);
  } else {
    cv::stereoRectify(K1, D1, K2, D2, size, rot, trans, R1, R2, P1, P2, Q, cv::CALIB_ZERO_DISPARITY, 0.0, size);
    cv::initUndistortRectifyMap(K1, D1, R1, P1, size, CV_16SC2, left_map1_, left_map2_);
    cv::initUndistortRectifyMap(K2, D2, R2, P2, size, CV_16SC2, right_map1_, right_map2_);
  }
  P1.convertTo(P1, CV_64F);
  P2.convertTo(P2, CV_64F);
  if (std::abs(P2.at<double>(1, 3)) > 1e-6 * std::abs(P2.at<double>(0, 3)))
    throw std::runtime_error("stereo rig: vertical stereo pairs are not supported");
  stereo_.camera = pinhole_from(P1, L.width, L.height);
  stereo_.baseline = -P2.at<double>(0, 3) / P2.at<double>(0, 0);
  if (stereo_.baseline <= 0) throw std::runtime_error("stereo rig: right camera must lie to the right of the left");

  Eigen::Matrix3d R1e;
  cv::cv2eigen(R1, R1e);  // x_rect = R1 * x_rawleft
  T_rawleft_rect_.linear() = R1e.transpose();
  T_body_rect_ = L.T_body_camera * T_rawleft_rect_;
}

void StereoRig::rectify(const cv::Mat& raw_left, const cv::Mat& raw_right, cv::Mat& left, cv::Mat& right) const {
  if (raw_left.size() != image_size() || raw_right.size() != image_size())
    throw std::runtime_error("stereo rig: image size differs from the calibration");
  if (!needs_remap()) {
    left = raw_left;
    right = raw_right;
    return;
  }
  cv::remap(raw_left, left, left_map1_, left_map2_, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  cv::remap(raw_right, right, right_map1_, right_map2_, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
}

}  // namespace vkvo::geometry
