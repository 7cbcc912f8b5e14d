#pragma once
// Small YAML helpers shared by the config loader and the dataset readers.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <Eigen/Geometry>

#include "io/calibration.hpp"

namespace vkvo::io {

// Parses a YAML file. OpenCV-style files start with a `%YAML:1.0` directive that yaml-cpp rejects; that line is
// dropped. Throws std::runtime_error naming the file (and the line of a syntax error).
YAML::Node load_yaml_file(const std::filesystem::path& file);

// Parses YAML text, dropping a leading `%YAML:1.0` directive; `origin` names the text in errors.
YAML::Node parse_yaml(const std::string& text, const std::string& origin);

// `node` as `count` numbers (any number where 0). Throws std::runtime_error naming `file` and `field` when the node
// is missing, not a list of numbers, or of another length.
std::vector<double> required_numbers(const YAML::Node& node, const std::filesystem::path& file,
                                     const std::string& field, std::size_t count);
// `node` as an image resolution [width, height]: two whole numbers in [1, 65536]. Throws std::runtime_error
// naming `file`, `field` and its line otherwise (an out-of-range number must never reach an int conversion).
std::pair<int, int> required_resolution(const YAML::Node& node, const std::filesystem::path& file,
                                        const std::string& field);
// `node` as a string; throws std::runtime_error naming `file` and `field` when it is missing.
std::string required_string(const YAML::Node& node, const std::filesystem::path& file, const std::string& field);

// Where `node` sits in `file` (line 0 where yaml-cpp has no mark, e.g. an absent node).
ValueOrigin origin_of(const YAML::Node& node, const std::filesystem::path& file, const std::string& key);

// "none"/"pinhole", "radtan"/"radial-tangential"/"plumb_bob", "equidistant"/"equi"/"fisheye".
// Throws std::invalid_argument listing the accepted names.
DistortionModel parse_distortion_model(const std::string& name);
const char* to_string(DistortionModel model);

// A 4x4 row-major homogeneous matrix (16 numbers, or 12 for the top 3x4 rows) as a rigid transform. The rotation
// part must be orthonormal to 1e-3 (it is re-orthonormalised); throws std::invalid_argument otherwise.
Eigen::Isometry3d isometry_from_row_major(const std::vector<double>& values);

}  // namespace vkvo::io
