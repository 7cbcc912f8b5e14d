#pragma once
// Matches the keypoints of two images (SuperGlue on the device, or the mutual-nearest-neighbour fallback).
#include "features/point_features.hpp"

namespace vkvo::features {

class PointMatcher {
 public:
  virtual ~PointMatcher() = default;
  // Matches from image a to image b; either set may be empty (then nothing matches).
  virtual PointMatches match(const PointFeatures& a, const PointFeatures& b) = 0;
};

}  // namespace vkvo::features
