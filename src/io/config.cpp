#include "io/config.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "io/kalibr_camchain.hpp"
#include "io/yaml_utils.hpp"

namespace vkvo::io {

Config Config::load(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file))
    throw std::runtime_error(fmt::format("{}: config file does not exist", file.string()));
  Config config;
  config.root_ = load_yaml_file(file);
  config.origin_ = file.string();
  if (config.root_.IsDefined() && !config.root_.IsNull() && !config.root_.IsMap())
    throw std::runtime_error(fmt::format("{}: top level must be a map of sections", file.string()));
  return config;
}

Config Config::from_string(const std::string& text, const std::string& origin) {
  Config config;
  config.root_ = parse_yaml(text, origin);
  config.origin_ = origin;
  if (config.root_.IsDefined() && !config.root_.IsNull() && !config.root_.IsMap())
    throw std::runtime_error(fmt::format("{}: top level must be a map of sections", origin));
  return config;
}

YAML::Node Config::section(const std::string& name) const {
  // Walk const nodes only: a non-const operator[] would insert the missing keys into the tree. `reset` rebinds
  // the handle; assigning (`node = child`) would overwrite the referenced node's contents instead.
  YAML::Node node;
  node.reset(root_);
  std::size_t start = 0;
  while (start <= name.size()) {
    const std::size_t dot = std::min(name.find('.', start), name.size());
    if (!node.IsMap()) return YAML::Node();
    const YAML::Node& parent = node;
    const YAML::Node child = parent[name.substr(start, dot - start)];
    if (!child.IsDefined()) return YAML::Node();
    node.reset(child);
    start = dot + 1;
  }
  return node;
}

bool Config::has_section(const std::string& name) const {
  const YAML::Node node = section(name);
  return node.IsDefined() && !node.IsNull();
}

namespace {
thread_local KeyReadLog* current_key_log = nullptr;
}  // namespace

KeyReadLog::KeyReadLog() : outer_(current_key_log) { current_key_log = this; }
KeyReadLog::~KeyReadLog() { current_key_log = outer_; }

void KeyReadLog::note(const YAML::Node& section, const std::string& key) { reads_.emplace_back(section, key); }

bool KeyReadLog::was_read(const YAML::Node& section, const std::string& key) const {
  for (const auto& [node, read_key] : reads_)
    if (read_key == key && node.is(section)) return true;
  return false;
}

std::vector<std::string> KeyReadLog::unread(const YAML::Node& node, const std::string& prefix) const {
  std::vector<std::string> keys;
  if (!node.IsMap()) return keys;
  for (const auto& entry : node) {
    const std::string key = entry.first.as<std::string>();
    const std::string path = prefix.empty() ? key : prefix + "." + key;
    const YAML::Node& value = entry.second;
    const auto append = [&](std::vector<std::string> more) { keys.insert(keys.end(), more.begin(), more.end()); };
    if (value.IsMap()) {
      append(unread(value, path));
    } else if (value.IsSequence() && value.size() > 0 && value[0].IsMap()) {
      for (std::size_t i = 0; i < value.size(); ++i) append(unread(value[i], fmt::format("{}[{}]", path, i)));
    } else if (!was_read(node, key)) {
      keys.push_back(fmt::format("{} (line {})", path, entry.first.Mark().line + 1));
    }
  }
  return keys;
}

void KeyReadLog::require_all_read(const YAML::Node& node, const std::string& prefix, const std::string& origin) const {
  const std::vector<std::string> keys = unread(node, prefix);
  if (keys.empty()) return;
  throw std::runtime_error(fmt::format("{}: {} not a vkvo parameter (misspelt, or in the wrong section?): {}", origin,
                                       keys.size() == 1 ? "this key is" : "these keys are", fmt::join(keys, ", ")));
}

namespace detail {
void note_key_read(const YAML::Node& section, const std::string& key) {
  if (current_key_log) current_key_log->note(section, key);
}

void throw_param_error(const YAML::Node& node, const std::string& key, const char* expected) {
  const auto mark = node.Mark();
  const std::string where = mark.is_null() ? std::string() : fmt::format(" (line {})", mark.line + 1);
  throw std::runtime_error(fmt::format("config key '{}'{}: expected {}", key, where, expected));
}
}  // namespace detail

namespace {

// The config's camera section as a source of calibration values: `section` is its key path ("camera",
// "camera.left") for the origins that validate_calibration names.
struct CameraSection {
  const YAML::Node& node;
  std::string section;
  const std::string& config_file;

  void note_origin(CameraCalibration& camera, const char* key, std::initializer_list<const char*> fields) const {
    if (node[key].IsDefined()) camera.set_origin(fields, origin_of(node[key], config_file, section + "." + key));
  }
};

void apply_camera_keys(const CameraSection& source, CameraCalibration& camera) {
  read_param(source.node, "width", camera.width);
  read_param(source.node, "height", camera.height);
  read_param(source.node, "fx", camera.fx);
  read_param(source.node, "fy", camera.fy);
  read_param(source.node, "cx", camera.cx);
  read_param(source.node, "cy", camera.cy);
  for (const char* key : {"width", "height", "fx", "fy", "cx", "cy"}) source.note_origin(camera, key, {key});
}

void apply_per_camera_keys(const YAML::Node& node, const std::string& name, const std::string& config_file,
                           CameraCalibration& camera) {
  if (!node.IsDefined() || node.IsNull()) return;
  if (!node.IsMap()) throw std::runtime_error(fmt::format("config key 'camera.{}': expected a map", name));
  const CameraSection source{node, "camera." + name, config_file};
  apply_camera_keys(source, camera);
  const auto model = param<std::string>(node, "distortion_model", "");
  if (!model.empty()) {
    try {
      camera.distortion = parse_distortion_model(model);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(fmt::format("config key 'camera.{}.distortion_model': {}", name, e.what()));
    }
  }
  read_param(node, "distortion_coeffs", camera.distortion_coeffs);
  source.note_origin(camera, "distortion_coeffs", {"distortion_coeffs"});
  // The camera's pose on the body as EuRoC's T_BS gives it (camera -> body), or as Kalibr's T_cam_imu does
  // (body -> camera; UMA-VI publishes that one), so that either can be pasted as published.
  const auto read_transform = [&](const char* key) -> std::optional<Eigen::Isometry3d> {
    const auto values = param<std::vector<double>>(node, key, {});
    if (values.empty()) return std::nullopt;
    try {
      return isometry_from_row_major(values);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(fmt::format("config key 'camera.{}.{}': {}", name, key, e.what()));
    }
  };
  const auto body_camera = read_transform("T_body_camera");
  const auto camera_body = read_transform("T_camera_body");
  if (body_camera && camera_body)
    throw std::runtime_error(
        fmt::format("config section 'camera.{}': give T_body_camera or T_camera_body, not both", name));
  if (body_camera) camera.T_body_camera = *body_camera;
  if (camera_body) camera.T_body_camera = camera_body->inverse();
  source.note_origin(camera, body_camera ? "T_body_camera" : "T_camera_body", {"T_body_camera"});
}

}  // namespace

StereoCalibration apply_camera_overrides(const YAML::Node& camera, StereoCalibration base,
                                         const std::string& config_file) {
  if (!camera.IsDefined() || camera.IsNull()) return base;
  if (!camera.IsMap()) throw std::runtime_error("config section 'camera': expected a map");
  const auto camchain = param<std::string>(camera, "kalibr", "");
  if (!camchain.empty()) base = read_kalibr_camchain(camchain);
  const CameraSection source{camera, "camera", config_file};
  apply_camera_keys(source, base.left);
  apply_camera_keys(source, base.right);
  if (camera["baseline"].IsDefined()) {
    const double baseline = param<double>(camera, "baseline", 0.0);
    if (!(baseline > 0)) throw std::runtime_error("config key 'camera.baseline': must be positive (metres)");
    base.rectified = true;
    base.right.T_body_camera = base.left.T_body_camera * Eigen::Translation3d(baseline, 0, 0);
    source.note_origin(base.right, "baseline", {"T_body_camera"});
  }
  read_param(camera, "rectified", base.rectified);
  apply_per_camera_keys(camera["left"], "left", config_file, base.left);
  apply_per_camera_keys(camera["right"], "right", config_file, base.right);
  return base;
}

namespace {
// The radial part of the distortion must grow monotonically from the centre to the farthest image corner, or
// undistortion has no unique answer there (an absurd coefficient folds the image over itself). Returns the problem.
std::optional<std::string> radial_distortion_problem(const CameraCalibration& c) {
  if (c.distortion == DistortionModel::none || c.distortion_coeffs.size() < 2) return std::nullopt;
  const auto& k = c.distortion_coeffs;
  const double corner_x = std::max(c.cx, c.width - c.cx) / c.fx, corner_y = std::max(c.cy, c.height - c.cy) / c.fy;
  const double corner = std::hypot(corner_x, corner_y);
  // radtan: r_d = r (1 + k1 r^2 + k2 r^4 [+ k3 r^6]); equidistant: theta_d = theta (1 + k1 t^2 + ... + k4 t^8).
  const bool fisheye = c.distortion == DistortionModel::equidistant;
  const std::vector<double> radial = fisheye ? std::vector<double>{k[0], k[1], k[2], k[3]}
                                             : std::vector<double>{k[0], k[1], k.size() == 5 ? k[4] : 0.0};
  const double extent = fisheye ? std::atan(corner) : corner;
  constexpr int kSamples = 256;
  for (int i = 1; i <= kSamples; ++i) {
    const double r = extent * i / kSamples;
    double derivative = 1.0, power = 1.0;
    for (std::size_t j = 0; j < radial.size(); ++j) {
      power *= r * r;
      derivative += static_cast<double>(2 * j + 3) * radial[j] * power;
    }
    if (!(derivative > 0))
      return fmt::format(
          "the radial distortion folds over at {:.3g} of the {:.3g} {} to the farthest corner (the "
          "coefficients are not those of a real lens)",
          r, extent, fisheye ? "rad" : "normalised radius");
  }
  return std::nullopt;
}
}  // namespace

void validate_calibration(const StereoCalibration& calibration, const std::string& source) {
  const auto check_camera = [&](const CameraCalibration& c, const char* side) {
    // Names the file, key and line the value came from where a reader recorded it, else `source`.
    const auto fail = [&](const char* field, const std::string& why) {
      const auto origin = c.origins.find(field);
      if (origin == c.origins.end())
        throw std::runtime_error(fmt::format("{}: {} camera: field '{}' {}", source, side, field, why));
      const ValueOrigin& o = origin->second;
      const std::string line = o.line > 0 ? fmt::format(" (line {})", o.line) : std::string();
      throw std::runtime_error(fmt::format("{}: {}{}: {} camera: field '{}' {}", o.file.empty() ? "config" : o.file,
                                           o.key, line, side, field, why));
    };
    if (c.width <= 0) fail("width", "missing or not positive");
    if (c.height <= 0) fail("height", "missing or not positive");
    if (!(c.fx > 0) || !std::isfinite(c.fx)) fail("fx", "missing, not positive or not finite");
    if (!(c.fy > 0) || !std::isfinite(c.fy)) fail("fy", "missing, not positive or not finite");
    if (!(c.cx > 0) || !std::isfinite(c.cx)) fail("cx", "missing, not positive or not finite");
    if (!(c.cy > 0) || !std::isfinite(c.cy)) fail("cy", "missing, not positive or not finite");
    const std::size_t n = c.distortion_coeffs.size();
    if (c.distortion == DistortionModel::radtan && n != 4 && n != 5)
      fail("distortion_coeffs", fmt::format("radtan needs 4 or 5 coefficients, got {}", n));
    if (c.distortion == DistortionModel::equidistant && n != 4)
      fail("distortion_coeffs", fmt::format("equidistant needs 4 coefficients, got {}", n));
    for (std::size_t i = 0; i < n; ++i)
      if (!std::isfinite(c.distortion_coeffs[i]))
        fail("distortion_coeffs", fmt::format("coefficient {} is {}", i, c.distortion_coeffs[i]));
    if (const auto problem = radial_distortion_problem(c)) fail("distortion_coeffs", *problem);
    if (!c.T_body_camera.matrix().allFinite()) fail("T_body_camera", "has a non-finite entry");
  };
  check_camera(calibration.left, "left");
  check_camera(calibration.right, "right");
  if (!(calibration.baseline() > 1e-6))
    throw std::runtime_error(fmt::format("{}: stereo baseline is zero (missing right camera extrinsics)", source));
}

void require_map(const YAML::Node& node, const std::string& name) {
  if (node && !node.IsMap() && !node.IsNull()) throw std::runtime_error("config key '" + name + "': expected a map");
}

}  // namespace vkvo::io
