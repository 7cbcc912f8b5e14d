#pragma once
// A synthetic stereo scene seen by a moving rig, and a PointFrontend that "detects" the projections of its
// points exactly (plus optional noise) and matches them by identity. It lets the tracker and the pipeline be
// tested without a GPU: every pose error then comes from the VO itself.
#include <random>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "geometry/camera.hpp"
#include "system/point_frontend.hpp"

namespace vkvo::test {

struct SyntheticScene {
  geometry::StereoCamera stereo;
  std::vector<Eigen::Vector3d> points;          // world
  std::vector<Eigen::Isometry3d> T_world_left;  // per frame, rectified left camera

  // A room-sized cloud of points and a smooth forward/sideways path with some rotation.
  static SyntheticScene make(int frames, int points, std::uint32_t seed);
};

// Images handed to the oracle are blank except for a tag in the first row (frame index, left/right), so they
// survive a round trip through PNG files and the dataset readers.
class OracleFrontend : public system::PointFrontend {
 public:
  OracleFrontend(const SyntheticScene& scene, double pixel_noise, std::uint32_t seed);

  // The tagged placeholder image of `frame`'s left or right view.
  cv::Mat image(int frame, bool right) const;
  features::PointFeatures detect(const cv::Mat& gray) override;
  features::PointMatches match(const features::PointFeatures& a, const features::PointFeatures& b) override;

 private:
  const SyntheticScene* scene_;
  double noise_;
  std::mt19937 rng_;
};

}  // namespace vkvo::test
