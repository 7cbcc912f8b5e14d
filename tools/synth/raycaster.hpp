#pragma once
// Analytic ray caster for the axis-aligned scene: one ray per pixel through its centre (OpenCV convention:
// pixel (u, v) sees direction ((u - cx) / fx, (v - cy) / fy, 1) in the camera frame), mip-mapped texture lookups
// over the pixel footprint, and 4 extra rays in the pixels on a depth or surface boundary (geometric anti-aliasing).
// Boxes are culled per 16x16 tile by their projected bounds, so a pixel tests only the boxes that can cover it.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "tools/synth/scene.hpp"

namespace vkvo::synth {

struct PinholeCamera {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
};

struct RenderOptions {
  bool anti_alias = true;
  bool parallel = true;  // split rows over cv::parallel_for_ (cv::setNumThreads(1) makes it serial)
};

class RayCaster {
 public:
  explicit RayCaster(const Scene& scene) : scene_(scene) {}

  // Linear radiance (albedo x irradiance, CV_32F) seen by `camera` at pose T_world_camera; optionally the depth
  // (camera z, metres, CV_32F) of the surface through each pixel centre.
  void render(const PinholeCamera& camera, const Eigen::Isometry3d& T_world_camera, cv::Mat& radiance,
              cv::Mat* depth = nullptr, const RenderOptions& options = {}) const;

  const Scene& scene() const { return scene_; }

 private:
  const Scene& scene_;
};

}  // namespace vkvo::synth
