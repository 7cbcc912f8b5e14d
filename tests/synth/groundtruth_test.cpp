// Ground truth vs images: a white square marker at a known world position is found in the rendered left and
// right images where the ground-truth poses read back from the written files (EuRoC CSV, TUM, sensor.yaml)
// project it. Reference: the area centroid of the projected square (exact for a polygon), compared with the
// intensity-weighted centroid of the rendered blob.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/test_support.hpp"
#include "synth/tiny_config.hpp"
#include "tools/synth/renderer.hpp"
#include "tools/synth/sequence_writer.hpp"

namespace vkvo::synth {
namespace {

namespace fs = std::filesystem;
using testing::tiny_config;

struct GroundTruthRow {
  int64_t t_ns;
  Eigen::Vector3d p, v;
  Eigen::Quaterniond q;
};

// An independent reader of the EuRoC ground-truth CSV.
std::vector<GroundTruthRow> read_euroc_groundtruth(const fs::path& path) {
  std::ifstream in(path);
  std::vector<GroundTruthRow> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream s(line);
    GroundTruthRow r;
    double qw, qx, qy, qz;
    s >> r.t_ns >> r.p.x() >> r.p.y() >> r.p.z() >> qw >> qx >> qy >> qz >> r.v.x() >> r.v.y() >> r.v.z();
    r.q = Eigen::Quaterniond(qw, qx, qy, qz);
    rows.push_back(r);
  }
  return rows;
}

Eigen::Isometry3d pose_of(const GroundTruthRow& r) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = r.q.normalized().toRotationMatrix();
  T.translation() = r.p;
  return T;
}

Eigen::Isometry3d read_T_BS(const fs::path& sensor_yaml) {
  const YAML::Node node = YAML::LoadFile(sensor_yaml.string());
  const auto data = node["T_BS"]["data"].as<std::vector<double>>();
  EXPECT_EQ(data.size(), 16u);
  Eigen::Matrix4d M;
  for (int i = 0; i < 16; ++i) M(i / 4, i % 4) = data[i];
  Eigen::Isometry3d T;
  T.matrix() = M;
  return T;
}

// Area centroid of the projected polygon (shoelace formula).
cv::Point2d projected_centroid(const std::vector<Eigen::Vector3d>& corners_world, const Eigen::Isometry3d& T_wc,
                               const RigParams& rig) {
  std::vector<cv::Point2d> poly;
  for (const auto& pw : corners_world) {
    const Eigen::Vector3d pc = T_wc.inverse() * pw;
    poly.emplace_back(rig.fx * pc.x() / pc.z() + rig.cx, rig.fy * pc.y() / pc.z() + rig.cy);
  }
  double area = 0, cx = 0, cy = 0;
  for (size_t i = 0; i < poly.size(); ++i) {
    const cv::Point2d a = poly[i], b = poly[(i + 1) % poly.size()];
    const double cross = a.x * b.y - b.x * a.y;
    area += cross;
    cx += (a.x + b.x) * cross;
    cy += (a.y + b.y) * cross;
  }
  return {cx / (3 * area), cy / (3 * area)};
}

// The bright blob: threshold half-way between background and marker, then weights from a local background.
std::optional<cv::Point2d> marker_centroid(const cv::Mat& image) {
  double lo, hi;
  cv::minMaxLoc(image, &lo, &hi);
  cv::Mat mask = image > (lo + hi) / 2;
  if (cv::countNonZero(mask) < 4) return std::nullopt;
  const cv::Rect box = cv::boundingRect(mask);
  const cv::Rect window = cv::Rect(box.x - 3, box.y - 3, box.width + 6, box.height + 6) & cv::Rect({}, image.size());
  if (window.width != box.width + 6 || window.height != box.height + 6) return std::nullopt;  // touches the border
  cv::Mat roi;
  image(window).convertTo(roi, CV_64F);
  double border = 0;
  int n = 0;
  for (int x = 0; x < roi.cols; ++x) border += roi.at<double>(0, x) + roi.at<double>(roi.rows - 1, x), n += 2;
  for (int y = 0; y < roi.rows; ++y) border += roi.at<double>(y, 0) + roi.at<double>(y, roi.cols - 1), n += 2;
  border /= n;
  double sum = 0, sx = 0, sy = 0;
  for (int y = 0; y < roi.rows; ++y)
    for (int x = 0; x < roi.cols; ++x) {
      const double w = std::clamp((roi.at<double>(y, x) - border) / (hi - border), 0.0, 1.0);
      sum += w, sx += w * (x + window.x), sy += w * (y + window.y);
    }
  return cv::Point2d(sx / sum, sy / sum);
}

TEST(GroundTruth, MarkerProjectsWhereTheRenderedMarkerIs) {
  SynthConfig config = tiny_config(10);
  config.sensor.read_noise = 0;  // sub-pixel centroids; noise is tested elsewhere
  config.sensor.shot_noise = 0;
  config.trajectory.speed = 0.8;  // enough motion over 10 frames to exercise the poses
  config.trajectory.yaw_rate_deg = 30;

  // A dim empty room with the generated geometry's lights, and a thin white 24 cm square 2 m ahead of frame 0.
  const SmoothTrajectory trajectory(config.trajectory, config.seed);
  const Eigen::Isometry3d T0 = trajectory.pose(0.0);
  const Eigen::Vector3d center = T0 * Eigen::Vector3d(0, 0, 2.0);
  const double half = 0.12;
  auto scene = std::make_shared<Scene>();
  scene->room = Eigen::AlignedBox3f(config.scene.room_min, config.scene.room_max);
  const int dull = scene->add_texture(Texture::constant(0.15));
  const int white = scene->add_texture(Texture::constant(1.0));
  scene->room_textures = {dull, dull, dull, dull, dull, dull};
  scene->lights = {{{-1.5f, 0.f, 2.9f}, 1.f}, {{1.5f, 0.f, 2.9f}, 1.f}};
  // Thin along world x: the camera starts looking roughly along +x, so it sees the x = min face.
  const Eigen::Vector3f c = center.cast<float>();
  scene->add_box(Eigen::AlignedBox3f(c - Eigen::Vector3f(0.001f, half, half), c + Eigen::Vector3f(0.001f, half, half)),
                 white);
  std::vector<Eigen::Vector3d> face;
  for (const auto& [dy, dz] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}})
    face.emplace_back(center.x() - 0.001, center.y() + dy * half, center.z() + dz * half);

  const fs::path dir = vkvo::test::temp_dir("synth_marker");
  write_asl_sequence(StereoRenderer(config, scene), dir);

  const auto gt = read_euroc_groundtruth(dir / "mav0/state_groundtruth_estimate0/data.csv");
  ASSERT_EQ(gt.size(), 10u);
  const Eigen::Isometry3d T_B_cam0 = read_T_BS(dir / "mav0/cam0/sensor.yaml");
  const Eigen::Isometry3d T_B_cam1 = read_T_BS(dir / "mav0/cam1/sensor.yaml");
  EXPECT_TRUE(T_B_cam0.isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_NEAR(T_B_cam1.translation().x(), config.rig.baseline, 1e-12);

  int checked = 0;
  for (const auto& row : gt) {
    const fs::path name = std::to_string(row.t_ns) + ".png";
    const cv::Mat left = cv::imread((dir / "mav0/cam0/data" / name).string(), cv::IMREAD_GRAYSCALE);
    const cv::Mat right = cv::imread((dir / "mav0/cam1/data" / name).string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(left.empty() || right.empty()) << name;
    const auto found_left = marker_centroid(left), found_right = marker_centroid(right);
    if (!found_left || !found_right) continue;
    const cv::Point2d expect_left = projected_centroid(face, pose_of(row) * T_B_cam0, config.rig);
    const cv::Point2d expect_right = projected_centroid(face, pose_of(row) * T_B_cam1, config.rig);
    EXPECT_NEAR(found_left->x, expect_left.x, 0.2) << name;
    EXPECT_NEAR(found_left->y, expect_left.y, 0.2) << name;
    EXPECT_NEAR(found_right->x, expect_right.x, 0.2) << name;
    EXPECT_NEAR(found_right->y, expect_right.y, 0.2) << name;
    // Disparity of the marker: f b / z of its centre, within the centroid tolerance.
    const double z = ((pose_of(row) * T_B_cam0).inverse() * center).z();
    EXPECT_NEAR(found_left->x - found_right->x, config.rig.fx * config.rig.baseline / z, 0.3) << name;
    ++checked;
  }
  EXPECT_GE(checked, 8) << "the marker should stay in view for most frames";
}

TEST(GroundTruth, TumFileAndVelocitiesAgreeWithTheEurocFile) {
  const SynthConfig config = tiny_config(8);
  const fs::path dir = vkvo::test::temp_dir("synth_gt_files");
  write_asl_sequence(StereoRenderer(config, std::make_shared<Scene>(generate_indoor_scene(config.scene, 5))), dir);
  const auto gt = read_euroc_groundtruth(dir / "mav0/state_groundtruth_estimate0/data.csv");
  ASSERT_EQ(gt.size(), 8u);

  std::ifstream tum(dir / "groundtruth_tum.txt");
  std::string line;
  size_t i = 0;
  while (std::getline(tum, line)) {
    if (line.empty() || line[0] == '#') continue;
    ASSERT_LT(i, gt.size());
    std::istringstream s(line);
    std::string stamp;
    double x, y, z, qx, qy, qz, qw;
    s >> stamp >> x >> y >> z >> qx >> qy >> qz >> qw;
    const size_t dot = stamp.find('.');
    ASSERT_NE(dot, std::string::npos);
    EXPECT_EQ(std::stoll(stamp.substr(0, dot)) * 1'000'000'000 + std::stoll(stamp.substr(dot + 1)), gt[i].t_ns);
    EXPECT_NEAR((Eigen::Vector3d(x, y, z) - gt[i].p).norm(), 0.0, 1e-8);
    EXPECT_NEAR(std::abs(Eigen::Quaterniond(qw, qx, qy, qz).dot(gt[i].q)), 1.0, 1e-8);
    ++i;
  }
  EXPECT_EQ(i, gt.size());
  // Velocity vs central differences of the positions at 20 Hz (the path's acceleration bounds the error).
  for (size_t k = 1; k + 1 < gt.size(); ++k) {
    const double dt = (gt[k + 1].t_ns - gt[k - 1].t_ns) * 1e-9;
    EXPECT_NEAR((gt[k].v - (gt[k + 1].p - gt[k - 1].p) / dt).norm(), 0.0, 0.01) << k;
  }
}

}  // namespace
}  // namespace vkvo::synth
