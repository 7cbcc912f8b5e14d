#pragma once
// The mutual-nearest-neighbour matcher's settings and their YAML loader, apart from the matcher
// (features/nn_matcher.hpp) so that configuration code does not parse the Vulkan headers.
#include <yaml-cpp/yaml.h>

namespace vkvo::features {

struct NnMatcherParams {
  // Keep a mutual pair when 1 - cos(d0, d1) <= this. 0.245 == L2 distance 0.7 between unit descriptors, the
  // SuperPoint demo's nearest-neighbour threshold.
  float max_cosine_distance = 0.245f;
  // Lowe's ratio on L2 distances (best < ratio * second best); <= 0 disables it.
  float ratio = 0.0f;
};

// YAML section `nn_matcher`: max_cosine_distance (or min_similarity = 1 - max_cosine_distance), ratio.
NnMatcherParams load_nn_matcher_params(const YAML::Node& section);

}  // namespace vkvo::features
