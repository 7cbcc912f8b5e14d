#pragma once
// Keypoints of one image as the point networks produce and consume them.
#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>

namespace vkvo::features {

struct PointFeatures {
  int image_width = 0;
  int image_height = 0;
  std::vector<Eigen::Vector2f> keypoints;  // x, y in pixels, sorted by score (descending)
  std::vector<float> scores;
  // size() x descriptor_dim, row-major, L2-normalised rows
  Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> descriptors;

  std::size_t size() const { return keypoints.size(); }
};

// Point matches from image 0 to image 1.
struct PointMatches {
  std::vector<int> matches0;   // per keypoint of image 0: index in image 1, or -1
  std::vector<float> scores0;  // matching confidence per keypoint of image 0 (0 where unmatched)
  std::size_t count() const {
    std::size_t n = 0;
    for (int m : matches0) n += m >= 0;
    return n;
  }
};

// `n` keypoints uniform over a width x height image with uniform scores in [0, 1) and Gaussian descriptors of
// `dim` channels normalised to unit length (not sorted by score): the input of the matcher benchmarks and tests.
PointFeatures random_point_features(std::size_t n, int dim, std::mt19937& rng, int width, int height);

}  // namespace vkvo::features
