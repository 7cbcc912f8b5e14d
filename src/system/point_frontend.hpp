#pragma once
// What the VO needs from the point networks: keypoints + descriptors of one image, and matches between two
// images. The Vulkan SuperPoint + SuperGlue/NN implementation lives in network_frontend.*; tests can plug in
// other implementations (e.g. an oracle on a synthetic scene) to exercise the tracker without a GPU.
#include <memory>

#include <opencv2/core.hpp>

#include "features/point_features.hpp"

namespace vkvo::system {

class PointFrontend {
 public:
  virtual ~PointFrontend() = default;
  virtual features::PointFeatures detect(const cv::Mat& gray) = 0;
  // Matches from the keypoints of `a` to those of `b`.
  virtual features::PointMatches match(const features::PointFeatures& a, const features::PointFeatures& b) = 0;
};

}  // namespace vkvo::system
