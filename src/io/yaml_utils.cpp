#include "io/yaml_utils.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

namespace vkvo::io {

YAML::Node parse_yaml(const std::string& text, const std::string& origin) {
  std::string body = text;
  // yaml-cpp only knows `%YAML 1.x`; OpenCV writes `%YAML:1.0`. Blank the directive line (keeping line numbers).
  if (body.rfind("%YAML", 0) == 0) {
    const auto eol = body.find('\n');
    body = eol == std::string::npos ? std::string() : body.substr(eol);
  }
  try {
    return YAML::Load(body);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(fmt::format("{}: invalid YAML at line {}: {}", origin, e.mark.line + 1, e.msg));
  }
}

YAML::Node load_yaml_file(const std::filesystem::path& file) {
  if (std::filesystem::is_directory(file))
    throw std::runtime_error(fmt::format("{}: is a directory, not a YAML file", file.string()));
  std::ifstream in(file);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open YAML file", file.string()));
  std::ostringstream text;
  text << in.rdbuf();
  return parse_yaml(text.str(), file.string());
}

std::vector<double> required_numbers(const YAML::Node& node, const std::filesystem::path& file,
                                     const std::string& field, std::size_t count) {
  if (!node.IsDefined() || node.IsNull())
    throw std::runtime_error(fmt::format("{}: missing field '{}'", file.string(), field));
  std::vector<double> values;
  try {
    values = node.as<std::vector<double>>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error(fmt::format("{}: field '{}' is not a list of numbers", file.string(), field));
  }
  if (count != 0 && values.size() != count)
    throw std::runtime_error(
        fmt::format("{}: field '{}' has {} numbers, expected {}", file.string(), field, values.size(), count));
  return values;
}

std::pair<int, int> required_resolution(const YAML::Node& node, const std::filesystem::path& file,
                                        const std::string& field) {
  constexpr double kMaxSide = 65536;
  const std::vector<double> values = required_numbers(node, file, field, 2);
  for (const double v : values)
    if (!(v >= 1 && v <= kMaxSide && v == std::floor(v)))
      throw std::runtime_error(fmt::format("{}: field '{}' (line {}): {} is not a whole number of pixels in [1, {}]",
                                           file.string(), field, origin_of(node, file, field).line, v, kMaxSide));
  return {static_cast<int>(values[0]), static_cast<int>(values[1])};
}

std::string required_string(const YAML::Node& node, const std::filesystem::path& file, const std::string& field) {
  if (!node.IsDefined() || node.IsNull())
    throw std::runtime_error(fmt::format("{}: missing field '{}'", file.string(), field));
  return node.as<std::string>();
}

ValueOrigin origin_of(const YAML::Node& node, const std::filesystem::path& file, const std::string& key) {
  const YAML::Mark mark = node.IsDefined() ? node.Mark() : YAML::Mark::null_mark();
  return {file.string(), key, mark.is_null() ? 0 : mark.line + 1};
}

DistortionModel parse_distortion_model(const std::string& name) {
  if (name == "none" || name == "pinhole") return DistortionModel::none;
  if (name == "radtan" || name == "radial-tangential" || name == "plumb_bob") return DistortionModel::radtan;
  if (name == "equidistant" || name == "equi" || name == "fisheye") return DistortionModel::equidistant;
  throw std::invalid_argument(
      fmt::format("unknown distortion model '{}' (expected none, radtan/radial-tangential or equidistant)", name));
}

const char* to_string(DistortionModel model) {
  switch (model) {
    case DistortionModel::none: return "none";
    case DistortionModel::radtan: return "radtan";
    case DistortionModel::equidistant: return "equidistant";
  }
  return "unknown";
}

Eigen::Isometry3d isometry_from_row_major(const std::vector<double>& values) {
  if (values.size() != 16 && values.size() != 12)
    throw std::invalid_argument(fmt::format("expected 16 (4x4) or 12 (3x4) numbers, got {}", values.size()));
  if (values.size() == 16 && (values[12] != 0 || values[13] != 0 || values[14] != 0 || values[15] != 1))
    throw std::invalid_argument("last row of a 4x4 transform must be 0 0 0 1");
  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) rotation(r, c) = values[r * 4 + c];
    translation(r) = values[r * 4 + 3];
  }
  const double orthonormality_error = (rotation * rotation.transpose() - Eigen::Matrix3d::Identity()).norm();
  if (orthonormality_error > 1e-3 || rotation.determinant() < 0)
    throw std::invalid_argument(fmt::format("rotation part is not a rotation (|R R^T - I| = {:.3g}, det = {:.4f})",
                                            orthonormality_error, rotation.determinant()));
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  // Files carry ~10 digits: project onto SO(3) so that later compositions stay rigid.
  T.linear() = Eigen::Quaterniond(rotation).normalized().toRotationMatrix();
  T.translation() = translation;
  return T;
}

}  // namespace vkvo::io
