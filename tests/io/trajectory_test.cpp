// Trajectory files (TUM, EuRoC CSV, KITTI), ground-truth frame handling, PLY and JSON writers.
#include <random>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "io/map_ply.hpp"
#include "io/run_summary.hpp"
#include "io/trajectory.hpp"

namespace fs = std::filesystem;
using namespace vkvo;

using test::error_of;
using test::read_text;
using test::write_text;

namespace {

io::Trajectory random_trajectory(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-5, 5);
  io::Trajectory trajectory;
  for (int k = 0; k < n; ++k) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::Quaterniond(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(u(rng), u(rng), u(rng));
    trajectory.push_back({1403636584.5 + 0.05 * k, pose});
  }
  return trajectory;
}

}  // namespace

TEST(TumTrajectory, RoundTripKeepsPosesTo1e9) {
  const fs::path file = test::temp_dir("tum") / "traj.txt";
  const auto original = random_trajectory(50, 1);
  io::write_tum(file, original);
  EXPECT_EQ(io::detect_trajectory_format(file), io::TrajectoryFormat::tum);
  const auto loaded = io::read_tum(file);
  ASSERT_EQ(loaded.size(), original.size());
  for (std::size_t k = 0; k < loaded.size(); ++k) {
    // 9 printed decimals: |dt| <= 5e-10 plus the double's own rounding at 1.4e9 s (2.4e-7).
    EXPECT_NEAR(loaded[k].t, original[k].t, 3e-7);
    EXPECT_LT((loaded[k].pose.translation() - original[k].pose.translation()).norm(), 1e-8);
    EXPECT_LT((loaded[k].pose.linear() - original[k].pose.linear()).norm(), 1e-8);
  }
}

TEST(TumTrajectory, WriterFlushesEveryLineAndWritesExactNanoseconds) {
  const fs::path file = test::temp_dir("tum_flush") / "sub" / "traj.txt";
  io::TumTrajectoryWriter writer(file);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(1, -2, 3.5);
  writer.write_ns(1403636584763555584LL, pose);
  // The writer is still open: the line must already be in the file.
  EXPECT_EQ(read_text(file),
            "1403636584.763555584 1.000000000 -2.000000000 3.500000000 0.000000000 0.000000000 0.000000000 "
            "1.000000000\n");
  writer.write(1403636585.25, pose);
  EXPECT_EQ(io::read_tum(file).size(), 2u);
  EXPECT_EQ(writer.lines_written(), 2u);
  {
    io::TumTrajectoryWriter appender(file, /*append=*/true);
    appender.write(1403636585.5, pose);
  }
  EXPECT_EQ(io::read_tum(file).size(), 3u);
}

TEST(TumTrajectory, MalformedLineNamesFileAndLine) {
  const fs::path file = test::temp_dir("tum_bad") / "traj.txt";
  write_text(file, "# t x y z qx qy qz qw\n0 0 0 0 0 0 0 1\n0.1 0 0 zero 0 0 0 1\n");
  const std::string message = error_of([&] { io::read_tum(file); });
  EXPECT_NE(message.find(file.string() + ":3"), std::string::npos) << message;
  write_text(file, "0 0 0 0 0 0 0 2\n");
  EXPECT_NE(error_of([&] { io::read_tum(file); }).find("quaternion norm"), std::string::npos);
}

// Ground truth and estimates are associated by time: a duplicate or a step back is refused with both lines named.
TEST(TumTrajectory, TimestampsMustIncrease) {
  const fs::path dir = test::temp_dir("trajectory_order");
  write_text(dir / "back.txt", "0.2 0 0 0 0 0 0 1\n0.1 0 0 0 0 0 0 1\n");
  const std::string back = error_of([&] { io::read_tum(dir / "back.txt"); });
  EXPECT_NE(back.find("back.txt:2: timestamp 0.1 is earlier than 0.2 on line 1"), std::string::npos) << back;
  write_text(dir / "twice.csv", "#timestamp [ns],px,py,pz,qw,qx,qy,qz\n100,0,0,0,1,0,0,0\n100,1,0,0,1,0,0,0\n");
  const std::string twice = error_of([&] { io::read_euroc_csv(dir / "twice.csv"); });
  EXPECT_NE(twice.find("twice.csv:3: duplicate timestamp 100 (also on line 2)"), std::string::npos) << twice;
}

TEST(EurocCsv, ReadsBothColumnLayouts) {
  const fs::path dir = test::temp_dir("euroc_csv");
  // Rotation of 90 deg about z: q = (w, x, y, z) = (cos 45, 0, 0, sin 45).
  const double c = std::sqrt(0.5);
  write_text(dir / "gt8.txt", fmt::format("#timestamp [ns],px,py,pz,qw,qx,qy,qz\n"
                                          "1403636580863555584.0000000000,1,2,3,{0},0,0,{0}\n",
                                          c));
  std::size_t columns = 0;
  const auto poses = io::read_euroc_csv(dir / "gt8.txt", &columns);
  EXPECT_EQ(columns, 8u);
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_NEAR(poses[0].t, 1403636580.863555584, 3e-7);
  EXPECT_TRUE(poses[0].pose.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_TRUE((poses[0].pose.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  EXPECT_EQ(io::detect_trajectory_format(dir / "gt8.txt"), io::TrajectoryFormat::euroc_csv);
}

TEST(Positions, BlankSecondsOrCommaNanosecondsWithIdentityRotations) {
  const fs::path dir = test::temp_dir("positions");
  write_text(dir / "seconds.txt", "# t x y z\n10.5 1 2 3\n10.6 1.5 2 3\n");
  write_text(dir / "ns.csv", "#timestamp [ns],x,y,z\n1403636580863555584,4,5,6\n");
  EXPECT_EQ(io::detect_trajectory_format(dir / "seconds.txt"), io::TrajectoryFormat::positions);
  EXPECT_EQ(io::detect_trajectory_format(dir / "ns.csv"), io::TrajectoryFormat::positions);
  const auto seconds = io::read_trajectory(dir / "seconds.txt");
  ASSERT_EQ(seconds.size(), 2u);
  EXPECT_DOUBLE_EQ(seconds[1].t, 10.6);
  EXPECT_TRUE(seconds[1].pose.translation().isApprox(Eigen::Vector3d(1.5, 2, 3)));
  EXPECT_TRUE(seconds[1].pose.linear().isIdentity());
  const auto ns = io::read_positions(dir / "ns.csv");
  ASSERT_EQ(ns.size(), 1u);
  EXPECT_NEAR(ns[0].t, 1403636580.863555584, 3e-7);
  EXPECT_TRUE(ns[0].pose.translation().isApprox(Eigen::Vector3d(4, 5, 6)));

  const io::GroundTruth gt = io::read_groundtruth(dir / "seconds.txt");
  EXPECT_FALSE(gt.has_orientation);
  EXPECT_EQ(gt.format, io::TrajectoryFormat::positions);
  EXPECT_NE(gt.note.find("positions only"), std::string::npos);
  // Body poses need their orientation to reach the camera: asking for that conversion is an error.
  EXPECT_NE(test::error_of([&] {
              io::read_groundtruth(dir / "seconds.txt", {.frame = io::PoseFrame::body});
            }).find("positions only"),
            std::string::npos);
  // A line of another width names the file and line.
  write_text(dir / "ragged.txt", "1 2 3 4\n5 6 7\n");
  EXPECT_NE(test::error_of([&] { io::read_positions(dir / "ragged.txt"); }).find("ragged.txt:2"), std::string::npos);
  EXPECT_TRUE(io::read_groundtruth(dir / "ns.csv").poses.size() == 1u);
}

// ORB-SLAM3's EuRoC ground truth (8 columns in a folder named EuRoC_left_cam) has world-to-camera rotations: read
// inverted by default; the same file elsewhere is read as written; either can be forced, or the rotations dropped.
TEST(GroundTruth, OrientationAsWrittenInvertedOrIgnored) {
  const fs::path base = test::temp_dir("gt_orientation");
  const double c = std::sqrt(0.5);  // 90 deg about z
  const std::string rows = fmt::format(
      "#timestamp [ns],px,py,pz,qw,qx,qy,qz\n1000000000,1,2,3,{0},0,0,{0}\n"
      "1100000000,1,2,4,{0},0,0,{0}\n",
      c);
  fs::create_directories(base / "EuRoC_left_cam");
  write_text(base / "EuRoC_left_cam" / "MH01_GT.txt", rows);
  write_text(base / "other_gt.csv", rows);
  const Eigen::Matrix3d written = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const auto orbslam3 = io::read_groundtruth(base / "EuRoC_left_cam" / "MH01_GT.txt");
  EXPECT_TRUE(orbslam3.poses[1].pose.linear().isApprox(written.transpose(), 1e-12));
  EXPECT_TRUE(orbslam3.has_orientation);
  const auto other = io::read_groundtruth(base / "other_gt.csv");
  EXPECT_TRUE(other.poses[1].pose.linear().isApprox(written, 1e-12));
  using O = io::GroundTruthOrientation;
  EXPECT_TRUE(io::read_groundtruth(base / "EuRoC_left_cam" / "MH01_GT.txt", {.orientation = O::as_written})
                  .poses[1]
                  .pose.linear()
                  .isApprox(written, 1e-12));
  EXPECT_TRUE(io::read_groundtruth(base / "other_gt.csv", {.orientation = O::inverse})
                  .poses[1]
                  .pose.linear()
                  .isApprox(written.transpose(), 1e-12));
  const auto ignored = io::read_groundtruth(base / "other_gt.csv", {.orientation = O::none});
  EXPECT_FALSE(ignored.has_orientation);
  EXPECT_TRUE(ignored.poses[1].pose.linear().isIdentity());
  EXPECT_TRUE(ignored.poses[1].pose.translation().isApprox(Eigen::Vector3d(1, 2, 4)));
}

TEST(GroundTruth, EurocBodyPosesAreConvertedWithTbs) {
  // mav0/state_groundtruth_estimate0/data.csv (17 columns) + mav0/cam0/sensor.yaml with a known T_BS.
  const fs::path mav0 = test::temp_dir("gt_body") / "mav0";
  std::string csv = "#timestamp,p_x,p_y,p_z,q_w,q_x,q_y,q_z,v_x,v_y,v_z,bw_x,bw_y,bw_z,ba_x,ba_y,ba_z\n";
  const double c = std::sqrt(0.5);
  csv += fmt::format("1000000000,1,0,0,{0},0,0,{0},0,0,0,0,0,0,0,0,0\n", c);  // body yawed 90 deg at (1,0,0)
  write_text(mav0 / "state_groundtruth_estimate0" / "data.csv", csv);
  write_text(mav0 / "cam0" / "sensor.yaml",
             "%YAML:1.0\nT_BS:\n  cols: 4\n  rows: 4\n  data: [1, 0, 0, 0.5, 0, 1, 0, 0, 0, 0, 1, 0.1, 0, 0, 0, 1]\n"
             "resolution: [752, 480]\ncamera_model: pinhole\nintrinsics: [1, 1, 1, 1]\n"
             "distortion_model: radial-tangential\ndistortion_coefficients: [0, 0, 0, 0]\n");
  const auto gt = io::read_groundtruth(mav0 / "state_groundtruth_estimate0" / "data.csv");
  EXPECT_TRUE(gt.body_to_camera_applied);
  EXPECT_EQ(gt.frame, io::PoseFrame::camera);
  ASSERT_EQ(gt.poses.size(), 1u);
  // The camera sits 0.5 m along body x, which the yaw turns into world +y; and 0.1 m up.
  EXPECT_TRUE(gt.poses[0].pose.translation().isApprox(Eigen::Vector3d(1, 0.5, 0.1), 1e-12))
      << gt.poses[0].pose.translation().transpose();

  io::GroundTruthOptions given;  // T_BS given directly (e.g. from a dataset's calibration) wins over the file
  given.T_body_camera = Eigen::Isometry3d(Eigen::Translation3d(0, 0, 2));
  EXPECT_TRUE(io::read_groundtruth(mav0 / "state_groundtruth_estimate0" / "data.csv", given)
                  .poses[0]
                  .pose.translation()
                  .isApprox(Eigen::Vector3d(1, 0, 2), 1e-12));
  given = {};
  // Rotations dropped: the conversion still used the yaw (the camera lands at +y), then the rotation is identity.
  given.orientation = io::GroundTruthOrientation::none;
  const auto positions = io::read_groundtruth(mav0 / "state_groundtruth_estimate0" / "data.csv", given);
  EXPECT_FALSE(positions.has_orientation);
  EXPECT_TRUE(positions.poses[0].pose.translation().isApprox(Eigen::Vector3d(1, 0.5, 0.1), 1e-12));
  EXPECT_TRUE(positions.poses[0].pose.linear().isIdentity());
  given = {};
  given.frame = io::PoseFrame::camera;  // forced: no conversion
  EXPECT_FALSE(io::read_groundtruth(mav0 / "state_groundtruth_estimate0" / "data.csv", given).body_to_camera_applied);

  fs::remove(mav0 / "cam0" / "sensor.yaml");  // no T_BS: stays a body pose, said so
  const auto body = io::read_groundtruth(mav0 / "state_groundtruth_estimate0" / "data.csv");
  EXPECT_FALSE(body.body_to_camera_applied);
  EXPECT_EQ(body.frame, io::PoseFrame::body);
  EXPECT_TRUE(body.poses[0].pose.translation().isApprox(Eigen::Vector3d(1, 0, 0)));
}

TEST(KittiPoses, TimesFromFileOrNominalRate) {
  const fs::path dir = test::temp_dir("kitti_poses");
  write_text(dir / "poses.txt",
             "1 0 0 0 0 1 0 0 0 0 1 0\n"
             "1.000000e+00 0 0 1.5 0 1 0 -0.25 0 0 1 2\n");
  EXPECT_EQ(io::detect_trajectory_format(dir / "poses.txt"), io::TrajectoryFormat::kitti);
  auto gt = io::read_groundtruth(dir / "poses.txt");
  ASSERT_EQ(gt.poses.size(), 2u);
  EXPECT_DOUBLE_EQ(gt.poses[1].t, 0.1);
  EXPECT_TRUE(gt.poses[1].pose.translation().isApprox(Eigen::Vector3d(1.5, -0.25, 2)));
  write_text(dir / "times.txt", "0.000000e+00\n1.036000e-01\n");
  gt = io::read_groundtruth(dir / "poses.txt");
  EXPECT_DOUBLE_EQ(gt.poses[1].t, 0.1036);
  write_text(dir / "poses.txt", "1 0 0 0 0 1 0 0 0 0 1\n");
  EXPECT_NE(error_of([&] { io::read_kitti_poses(dir / "poses.txt"); }).find("expected 12 numbers"), std::string::npos);
}

TEST(MapPly, HeaderCountsAndEdgesReferenceLineEndpoints) {
  const fs::path file = test::temp_dir("ply") / "map.ply";
  io::MapGeometry map;
  map.points = {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  map.lines = {{{0, 0, 2}, {1, 0, 2}}, {{0, 0, 3}, {0, 1, 3}}};
  map.trajectory = {{0, 0, 0}, {0.1, 0, 0}, {0.2, 0, 0}};
  io::write_map_ply(file, map);
  const std::string text = read_text(file);
  EXPECT_NE(text.find("element vertex 10\n"), std::string::npos);  // 3 points + 4 line ends + 3 path
  EXPECT_NE(text.find("element edge 4\n"), std::string::npos);     // 2 lines + 2 path segments
  std::istringstream in(text.substr(text.find("end_header\n") + 11));
  std::vector<std::string> rows;
  for (std::string row; std::getline(in, row);) rows.push_back(row);
  ASSERT_EQ(rows.size(), 14u);
  EXPECT_EQ(rows[5], "0.000000 0.000000 3.000000 255 40 40");  // second line's start vertex (index 5)
  EXPECT_EQ(rows[11], "5 6 255 40 40");                        // second line's edge
  EXPECT_EQ(rows[13], "8 9 40 220 40");                        // last path segment
  EXPECT_FALSE(fs::exists(file.string() + ".tmp"));
}

TEST(RunSummary, JsonFileRoundTrip) {
  const fs::path file = test::temp_dir("json") / "out" / "summary.json";
  io::StereoCalibration calibration;
  calibration.left.fx = 500;
  calibration.right.T_body_camera.translation() = Eigen::Vector3d(0.2, 0, 0);
  io::write_json_file(file, {{"calibration", io::to_json(calibration)}, {"frames", 12}});
  const auto document = nlohmann::json::parse(read_text(file));
  EXPECT_EQ(document["frames"], 12);
  EXPECT_DOUBLE_EQ(document["calibration"]["left"]["fx"].get<double>(), 500.0);
  EXPECT_DOUBLE_EQ(document["calibration"]["baseline_m"].get<double>(), 0.2);
  EXPECT_DOUBLE_EQ(document["calibration"]["right"]["T_body_camera"][3].get<double>(), 0.2);
}
