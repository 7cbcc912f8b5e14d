// Dataset readers on the shared EuRoC and KITTI clips (label `data`); values checked against the files.
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "io/dataset.hpp"

using namespace vkvo;

TEST(EurocData, Mh01SubsetHas130PairsAndFileCalibration) {
  VKVO_REQUIRE_DATA(dir, "datasets/euroc_mh01_subset");
  const auto dataset = io::open_dataset(dir);  // the parent of MH_01_easy
  ASSERT_EQ(dataset->kind(), io::DatasetKind::euroc);
  EXPECT_EQ(dataset->name(), "MH_01_easy");
  ASSERT_EQ(dataset->size(), 130u);
  EXPECT_EQ(dataset->frame(0).timestamp_ns, 1403636584763555584LL);
  EXPECT_EQ(dataset->frame(129).timestamp_ns, 1403636591213555456LL);
  EXPECT_NEAR(dataset->frame(129).timestamp_s - dataset->frame(0).timestamp_s, 6.45, 1e-6);

  // cam0/sensor.yaml and cam1/sensor.yaml
  const auto& calibration = dataset->calibration();
  EXPECT_DOUBLE_EQ(calibration.left.fx, 458.654);
  EXPECT_DOUBLE_EQ(calibration.left.fy, 457.296);
  EXPECT_DOUBLE_EQ(calibration.left.cx, 367.215);
  EXPECT_DOUBLE_EQ(calibration.left.cy, 248.375);
  EXPECT_DOUBLE_EQ(calibration.right.cx, 379.999);
  EXPECT_EQ(calibration.left.width, 752);
  EXPECT_EQ(calibration.left.height, 480);
  EXPECT_EQ(calibration.left.distortion, io::DistortionModel::radtan);
  ASSERT_EQ(calibration.right.distortion_coeffs.size(), 4u);
  EXPECT_DOUBLE_EQ(calibration.right.distortion_coeffs[0], -0.28368365);
  // T_BS is re-orthonormalised: entries agree with the file to its ~1e-10 rounding.
  EXPECT_NEAR(calibration.left.T_body_camera(0, 1), -0.999880929698, 1e-9);
  EXPECT_NEAR(calibration.left.T_body_camera.translation().y(), -0.064676986768, 1e-12);
  EXPECT_NEAR(calibration.right.T_body_camera.translation().y(), 0.0453689425024, 1e-12);
  EXPECT_NEAR(calibration.baseline(), 0.110078, 1e-5);  // the known EuRoC stereo baseline, about 11 cm

  const auto images = dataset->load(64);
  EXPECT_EQ(images.left.type(), CV_8UC1);
  EXPECT_EQ(images.right.cols, 752);
  EXPECT_EQ(images.right.rows, 480);
  ASSERT_TRUE(dataset->groundtruth_path().has_value());
  EXPECT_EQ(dataset->groundtruth_path()->filename(), "MH01_GT.txt");
}

TEST(KittiData, Seq01ClipHas51PairsAndRectifiedCalibration) {
  VKVO_REQUIRE_DATA(dir, "datasets/kitti_seq01_f000-050");
  const auto dataset = io::open_dataset(dir);
  ASSERT_EQ(dataset->kind(), io::DatasetKind::kitti);
  ASSERT_EQ(dataset->size(), 51u);
  EXPECT_DOUBLE_EQ(dataset->frame(50).timestamp_s, 5.0);  // no times.txt: nominal 10 Hz
  const auto& calibration = dataset->calibration();
  EXPECT_TRUE(calibration.rectified);
  EXPECT_DOUBLE_EQ(calibration.left.fx, 718.856);
  EXPECT_DOUBLE_EQ(calibration.left.fy, 718.856);
  EXPECT_DOUBLE_EQ(calibration.left.cx, 607.1928);
  EXPECT_DOUBLE_EQ(calibration.left.cy, 185.2157);
  EXPECT_DOUBLE_EQ(calibration.baseline(), 386.1448 / 718.856);
  EXPECT_EQ(calibration.left.width, 1241);
  EXPECT_EQ(calibration.left.height, 376);
  const auto images = dataset->load(50);
  EXPECT_EQ(images.left.type(), CV_8UC1);
  EXPECT_EQ(images.left.cols, 1241);
  ASSERT_TRUE(dataset->groundtruth_path().has_value());
  EXPECT_EQ(dataset->groundtruth_path()->filename(), "poses.txt");
}
