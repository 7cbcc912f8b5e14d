// Ground-truth readers on the shared files (label `data`).
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "io/dataset.hpp"
#include "io/trajectory.hpp"

using namespace vkvo;

TEST(GroundTruthData, EurocLeftCamGroundTruth) {
  VKVO_REQUIRE_DATA(file, "datasets/euroc_mh01_subset/groundtruth/EuRoC_left_cam/MH01_GT.txt");
  const auto gt = io::read_groundtruth(file);
  EXPECT_EQ(gt.format, io::TrajectoryFormat::euroc_csv);
  EXPECT_EQ(gt.frame, io::PoseFrame::camera);  // 8 columns: already the cam0 pose
  EXPECT_FALSE(gt.body_to_camera_applied);
  ASSERT_EQ(gt.poses.size(), 3638u);  // PROVENANCE.md
  // First row: 1403636580863555584, 4.6650211767,-1.8472146877,0.7812067206, q = 0.4502123789 0.6912148472 ...
  EXPECT_NEAR(gt.poses[0].t, 1403636580.863555584, 3e-7);
  EXPECT_NEAR(gt.poses[0].pose.translation().x(), 4.6650211767, 1e-12);
  EXPECT_NEAR(gt.poses[0].pose.translation().z(), 0.7812067206, 1e-12);
  // The file's rotation is world-to-camera (GroundTruthOrientation::automatic): read inverted.
  const Eigen::Matrix3d written =
      Eigen::Quaterniond(0.4502123789, 0.6912148472, 0.4743667630, -0.307419945794).normalized().toRotationMatrix();
  EXPECT_TRUE(gt.poses[0].pose.linear().isApprox(written.transpose(), 1e-9));
  EXPECT_NE(gt.note.find("inverted"), std::string::npos) << gt.note;
  const auto as_written = io::read_groundtruth(file, {.orientation = io::GroundTruthOrientation::as_written});
  EXPECT_TRUE(as_written.poses[0].pose.linear().isApprox(written, 1e-9));
}

TEST(GroundTruthData, KittiPoses) {
  VKVO_REQUIRE_DATA(file, "datasets/kitti_seq01_f000-050/KITTI_sequence_2/poses.txt");
  const auto gt = io::read_groundtruth(file);
  EXPECT_EQ(gt.format, io::TrajectoryFormat::kitti);
  ASSERT_EQ(gt.poses.size(), 51u);
  EXPECT_DOUBLE_EQ(gt.poses[50].t, 5.0);
  // Line 2 of poses.txt: translation column (5.154656e-02, -2.424883e-02, 1.000725e+00).
  EXPECT_TRUE(gt.poses[1].pose.translation().isApprox(Eigen::Vector3d(5.154656e-02, -2.424883e-02, 1.000725), 1e-12));
  double path = 0;
  for (std::size_t k = 1; k < gt.poses.size(); ++k)
    path += (gt.poses[k].pose.translation() - gt.poses[k - 1].pose.translation()).norm();
  EXPECT_NEAR(path, 51.8, 0.1);  // PROVENANCE.md: "a 51.8 m path"
}

TEST(GroundTruthData, FoundWithTheDatasets) {
  VKVO_REQUIRE_DATA(dir, "datasets");
  const auto euroc = io::read_dataset_groundtruth(*io::open_dataset(dir / "euroc_mh01_subset"));
  ASSERT_TRUE(euroc.has_value());
  EXPECT_EQ(euroc->poses.size(), 3638u);
  EXPECT_FALSE(euroc->body_to_camera_applied);  // EuRoC_left_cam is already the cam0 pose
  const auto kitti = io::read_dataset_groundtruth(*io::open_dataset(dir / "kitti_seq01_f000-050"));
  ASSERT_TRUE(kitti.has_value());
  EXPECT_EQ(kitti->poses.size(), 51u);
}
