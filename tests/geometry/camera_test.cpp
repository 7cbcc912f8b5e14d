// Pinhole projection/back-projection with Jacobians, and stereo rectification against OpenCV projections.
#include <random>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include "geometry/camera.hpp"
#include "scene.hpp"

namespace vkvo::geometry {
namespace {

TEST(PinholeCamera, ProjectBackprojectRoundTripAndJacobians) {
  const PinholeCamera cam = test::test_stereo_camera().camera;
  std::mt19937 rng(1);
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector3d p = test::random_visible_point(rng, cam, Eigen::Isometry3d::Identity(), 0.5, 20.0);
    Eigen::Matrix<double, 2, 3> J;
    const Eigen::Vector2d px = cam.project(p, &J);
    EXPECT_LT((cam.backproject(px) * p.z() - p).norm(), 1e-9);
    // Central differences, step 1e-6: agreement to 1e-5 px per unit.
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d dp = Eigen::Vector3d::Zero();
      dp[k] = 1e-6;
      const Eigen::Vector2d num = (cam.project(p + dp) - cam.project(p - dp)) / 2e-6;
      EXPECT_LT((num - J.col(k)).norm(), 1e-5 * std::max(1.0, J.col(k).norm()));
    }
    Eigen::Matrix<double, 3, 2> Jb;
    cam.backproject(px, &Jb);
    for (int k = 0; k < 2; ++k) {
      Eigen::Vector2d d = Eigen::Vector2d::Zero();
      d[k] = 1e-3;
      EXPECT_LT(((cam.backproject(px + d) - cam.backproject(px - d)) / 2e-3 - Jb.col(k)).norm(), 1e-9);
    }
  }
}

// Synthetic raw stereo pair with distortion. Gaussian spots are rendered at cv::projectPoints positions of 3D
// points; after rectification each spot must sit at the rectified projection (left) and at the same row in the
// right image with disparity fx * b / z. Spot centroids carry interpolation error: tolerance 0.15 px.
struct RawRig {
  io::StereoCalibration calib;
};

RawRig make_raw_rig(io::DistortionModel model) {
  RawRig r;
  auto& L = r.calib.left;
  auto& R = r.calib.right;
  L.width = R.width = 640;
  L.height = R.height = 480;
  L.fx = 460;
  L.fy = 455;
  L.cx = 322;
  L.cy = 243;
  R.fx = 458;
  R.fy = 457;
  R.cx = 318;
  R.cy = 238;
  L.distortion = R.distortion = model;
  if (model == io::DistortionModel::radtan) {
    L.distortion_coeffs = {-0.28, 0.07, 2e-4, 1.8e-5};
    R.distortion_coeffs = {-0.27, 0.066, -1e-4, -5e-5};
  } else {
    L.distortion_coeffs = {-0.01, 0.02, -0.01, 0.002};
    R.distortion_coeffs = {-0.012, 0.018, -0.008, 0.001};
  }
  // Right camera ~11 cm to the right, slightly rotated; body frame = a rotated left camera.
  L.T_body_camera.linear() = Eigen::AngleAxisd(0.1, Eigen::Vector3d(0.2, 1, 0.3).normalized()).toRotationMatrix();
  L.T_body_camera.translation() = Eigen::Vector3d(0.05, -0.02, 0.01);
  Eigen::Isometry3d T_left_right = Eigen::Isometry3d::Identity();
  T_left_right.linear() = Eigen::AngleAxisd(0.02, Eigen::Vector3d(0.3, -1, 0.5).normalized()).toRotationMatrix();
  T_left_right.translation() = Eigen::Vector3d(0.11, 0.002, -0.001);
  R.T_body_camera = L.T_body_camera * T_left_right;
  return r;
}

Eigen::Vector2d project_raw(const io::CameraCalibration& c, const Eigen::Vector3d& p_cam) {
  const cv::Mat K = (cv::Mat_<double>(3, 3) << c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1);
  const cv::Mat D(c.distortion_coeffs, true);
  std::vector<cv::Point3d> obj{{p_cam.x(), p_cam.y(), p_cam.z()}};
  std::vector<cv::Point2d> img;
  const cv::Mat zero = cv::Mat::zeros(3, 1, CV_64F);
  if (c.distortion == io::DistortionModel::equidistant)
    cv::fisheye::projectPoints(obj, img, zero, zero, K, D);
  else
    cv::projectPoints(obj, zero, zero, K, D, img);
  return {img[0].x, img[0].y};
}

void render_spots(cv::Mat& image, const std::vector<Eigen::Vector2d>& spots, double sigma) {
  for (const auto& s : spots)
    for (int y = int(s.y()) - 8; y <= int(s.y()) + 8; ++y)
      for (int x = int(s.x()) - 8; x <= int(s.x()) + 8; ++x) {
        if (x < 0 || y < 0 || x >= image.cols || y >= image.rows) continue;
        const double r2 = (x - s.x()) * (x - s.x()) + (y - s.y()) * (y - s.y());
        image.at<float>(y, x) += float(std::exp(-r2 / (2 * sigma * sigma)));
      }
}

Eigen::Vector2d centroid(const cv::Mat& image, const Eigen::Vector2d& guess) {
  double sw = 0, sx = 0, sy = 0;
  for (int y = int(std::round(guess.y())) - 7; y <= int(std::round(guess.y())) + 7; ++y)
    for (int x = int(std::round(guess.x())) - 7; x <= int(std::round(guess.x())) + 7; ++x) {
      const double w = image.at<float>(y, x);
      sw += w;
      sx += w * x;
      sy += w * y;
    }
  return {sx / sw, sy / sw};
}

void check_rectification(io::DistortionModel model) {
  const RawRig raw = make_raw_rig(model);
  const StereoRig rig(raw.calib);
  ASSERT_TRUE(rig.needs_remap());
  // stereoRectify puts the whole camera offset on the rectified x axis.
  const Eigen::Vector3d t_lr = (raw.calib.left.T_body_camera.inverse() * raw.calib.right.T_body_camera).translation();
  EXPECT_NEAR(rig.baseline(), t_lr.norm(), 1e-9);
  const PinholeCamera& cam = rig.camera();
  // Body pose of the rectified frame agrees with the raw-left pose composed with the rectifying rotation.
  EXPECT_LT(
      (rig.T_body_rectified().matrix() - (raw.calib.left.T_body_camera * rig.T_rawleft_rectified()).matrix()).norm(),
      1e-12);

  std::mt19937 rng(7);
  std::vector<Eigen::Vector3d> points_rect;
  std::vector<Eigen::Vector2d> spots_left, spots_right;
  const Eigen::Isometry3d T_rightraw_rect = raw.calib.right.T_body_camera.inverse() * rig.T_body_rectified();
  while (points_rect.size() < 12) {
    const Eigen::Vector3d p = test::random_visible_point(rng, cam, Eigen::Isometry3d::Identity(), 1.5, 6.0);
    const Eigen::Vector2d l = cam.project(p), r = rig.stereo().project_right(p);
    if (!cam.in_image(l, 40) || !cam.in_image(r, 40)) continue;
    bool far_enough = true;  // spots must not overlap in either image
    for (size_t i = 0; i < points_rect.size(); ++i)
      far_enough &=
          (cam.project(points_rect[i]) - l).norm() > 30 && (rig.stereo().project_right(points_rect[i]) - r).norm() > 30;
    if (!far_enough) continue;
    points_rect.push_back(p);
    spots_left.push_back(project_raw(raw.calib.left, rig.T_rawleft_rectified() * p));
    spots_right.push_back(project_raw(raw.calib.right, T_rightraw_rect * p));
  }
  cv::Mat raw_left = cv::Mat::zeros(480, 640, CV_32F), raw_right = raw_left.clone();
  render_spots(raw_left, spots_left, 2.0);
  render_spots(raw_right, spots_right, 2.0);
  cv::Mat left, right;
  rig.rectify(raw_left, raw_right, left, right);
  ASSERT_EQ(left.size(), raw_left.size());
  for (size_t i = 0; i < points_rect.size(); ++i) {
    const Eigen::Vector2d expect_l = cam.project(points_rect[i]);
    const Eigen::Vector2d expect_r = rig.stereo().project_right(points_rect[i]);
    const Eigen::Vector2d got_l = centroid(left, expect_l), got_r = centroid(right, expect_r);
    EXPECT_LT((got_l - expect_l).norm(), 0.15) << "left spot " << i;
    EXPECT_LT((got_r - expect_r).norm(), 0.15) << "right spot " << i;
    EXPECT_LT(std::abs(got_l.y() - got_r.y()), 0.2) << "rows differ, spot " << i;
  }
}

TEST(StereoRig, RectifiesRadtanPair) { check_rectification(io::DistortionModel::radtan); }
TEST(StereoRig, RectifiesEquidistantPair) { check_rectification(io::DistortionModel::equidistant); }

TEST(StereoRig, AlreadyRectifiedInputPassesThrough) {
  io::StereoCalibration calib;
  calib.rectified = true;
  for (auto* c : {&calib.left, &calib.right}) {
    c->width = 1241;
    c->height = 376;
    c->fx = c->fy = 718.856;
    c->cx = 607.1928;
    c->cy = 185.2157;
  }
  calib.right.T_body_camera.translation() = Eigen::Vector3d(0.537165, 0, 0);
  const StereoRig rig(calib);
  EXPECT_FALSE(rig.needs_remap());
  EXPECT_NEAR(rig.baseline(), 0.537165, 1e-12);
  EXPECT_DOUBLE_EQ(rig.camera().fx, 718.856);
  cv::Mat l(376, 1241, CV_8U, cv::Scalar(3)), r(376, 1241, CV_8U, cv::Scalar(4)), lo, ro;
  rig.rectify(l, r, lo, ro);
  EXPECT_EQ(lo.data, l.data);
  EXPECT_EQ(ro.at<uchar>(10, 10), 4);
  calib.right.T_body_camera.translation() = Eigen::Vector3d(-0.5, 0, 0);
  EXPECT_THROW(StereoRig{calib}, std::runtime_error);
}

}  // namespace
}  // namespace vkvo::geometry
