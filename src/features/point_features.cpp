#include "features/point_features.hpp"

namespace vkvo::features {

PointFeatures random_point_features(std::size_t n, int dim, std::mt19937& rng, int width, int height) {
  PointFeatures f;
  f.image_width = width;
  f.image_height = height;
  std::uniform_real_distribution<float> ux(0.0f, float(width)), uy(0.0f, float(height)), us(0.0f, 1.0f);
  std::normal_distribution<float> nd(0.0f, 1.0f);
  f.descriptors.resize(Eigen::Index(n), dim);
  for (std::size_t i = 0; i < n; ++i) {
    f.keypoints.emplace_back(ux(rng), uy(rng));
    f.scores.push_back(us(rng));
    for (int c = 0; c < dim; ++c) f.descriptors(Eigen::Index(i), c) = nd(rng);
    f.descriptors.row(Eigen::Index(i)).normalize();
  }
  return f;
}

}  // namespace vkvo::features
