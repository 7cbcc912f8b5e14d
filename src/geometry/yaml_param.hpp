#pragma once
// Reading optional parameters from a YAML section: a missing key keeps the default, a value of the wrong type
// throws std::runtime_error naming the key. Shared by the geometry, map and backend parameter loaders.
#include <stdexcept>
#include <string>

#include <yaml-cpp/yaml.h>

namespace vkvo::geometry {

template <typename T>
void read_optional(const YAML::Node& section, const std::string& key, T& value) {
  if (!section || !section.IsMap()) return;
  const YAML::Node node = section[key];
  if (!node) return;
  try {
    value = node.as<T>();
  } catch (const YAML::Exception& e) {
    throw std::runtime_error("config key '" + key + "' has the wrong type: " + e.what());
  }
}

}  // namespace vkvo::geometry
