#include "system/oracle_frontend.hpp"

#include <unordered_map>

namespace vkvo::test {

SyntheticScene SyntheticScene::make(int frames, int points, std::uint32_t seed) {
  SyntheticScene s;
  s.stereo.camera = {.fx = 458.0, .fy = 457.0, .cx = 376.0, .cy = 240.0, .width = 752, .height = 480};
  s.stereo.baseline = 0.11;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < points; ++i)  // a box of 12 x 8 x 6 m in front of the start
    s.points.emplace_back(6.0 * u(rng), 3.0 * u(rng), 6.0 + 3.0 * u(rng));
  for (int f = 0; f < frames; ++f) {
    const double t = 0.05 * f;  // 20 Hz
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translate(Eigen::Vector3d(0.4 * std::sin(0.8 * t), 0.1 * std::sin(1.3 * t), 0.3 * t));
    T.rotate(Eigen::AngleAxisd(0.15 * std::sin(0.7 * t), Eigen::Vector3d::UnitY()) *
             Eigen::AngleAxisd(0.05 * std::sin(1.1 * t), Eigen::Vector3d::UnitX()));
    s.T_world_left.push_back(T);
  }
  return s;
}

OracleFrontend::OracleFrontend(const SyntheticScene& scene, double pixel_noise, std::uint32_t seed)
    : scene_(&scene), noise_(pixel_noise), rng_(seed) {}

namespace {
constexpr unsigned char kTag = 0xa7;
}

cv::Mat OracleFrontend::image(int frame, bool right) const {
  cv::Mat m(scene_->stereo.camera.height, scene_->stereo.camera.width, CV_8UC1, cv::Scalar(0));
  m.at<unsigned char>(0, 0) = kTag;
  m.at<unsigned char>(0, 1) = static_cast<unsigned char>(frame % 256);
  m.at<unsigned char>(0, 2) = static_cast<unsigned char>(frame / 256);
  m.at<unsigned char>(0, 3) = right ? 1 : 0;
  return m;
}

// Keypoints carry the scene point id in `scores` so that match() can pair them by identity.
features::PointFeatures OracleFrontend::detect(const cv::Mat& gray) {
  features::PointFeatures out;
  out.image_width = gray.cols;
  out.image_height = gray.rows;
  if (gray.empty() || gray.at<unsigned char>(0, 0) != kTag) return out;  // untagged (e.g. black): nothing seen
  const int frame = gray.at<unsigned char>(0, 1) + 256 * gray.at<unsigned char>(0, 2);
  const bool right = gray.at<unsigned char>(0, 3) != 0;
  if (frame >= static_cast<int>(scene_->T_world_left.size())) return out;
  Eigen::Isometry3d T_camera_world = scene_->T_world_left[static_cast<std::size_t>(frame)].inverse();
  if (right) T_camera_world = scene_->stereo.T_left_right().inverse() * T_camera_world;
  std::normal_distribution<double> noise(0.0, noise_);
  for (std::size_t i = 0; i < scene_->points.size(); ++i) {
    const Eigen::Vector3d p = T_camera_world * scene_->points[i];
    if (p.z() < 0.2) continue;
    Eigen::Vector2d px = scene_->stereo.camera.project(p);
    if (!scene_->stereo.camera.in_image(px, 8.0)) continue;
    if (noise_ > 0) px += Eigen::Vector2d(noise(rng_), noise(rng_));
    out.keypoints.push_back(px.cast<float>());
    out.scores.push_back(static_cast<float>(i));
  }
  out.descriptors.setZero(static_cast<Eigen::Index>(out.keypoints.size()), 1);
  return out;
}

features::PointMatches OracleFrontend::match(const features::PointFeatures& a, const features::PointFeatures& b) {
  std::unordered_map<int, int> index_in_b;
  for (std::size_t j = 0; j < b.scores.size(); ++j) index_in_b[static_cast<int>(b.scores[j])] = static_cast<int>(j);
  features::PointMatches m;
  m.matches0.assign(a.size(), -1);
  m.scores0.assign(a.size(), 0.0f);
  for (std::size_t i = 0; i < a.size(); ++i)
    if (const auto it = index_in_b.find(static_cast<int>(a.scores[i])); it != index_in_b.end()) {
      m.matches0[i] = it->second;
      m.scores0[i] = 1.0f;
    }
  return m;
}

}  // namespace vkvo::test
