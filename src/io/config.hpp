#pragma once
// YAML configuration access shared by all modules.
//
// A config file holds one section per module (`superpoint:`, `lines:`, `camera:`...). Every module reads its own
// section with `param()` so that a missing key keeps the reference default and a wrong type is an error naming
// the key. Sections are always handed out as const nodes: a non-const YAML::Node::operator[] would insert keys.
#include <filesystem>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "io/calibration.hpp"

namespace vkvo::io {

class Config {
 public:
  // An empty configuration: every section is empty, so every module uses its defaults.
  Config() = default;

  // Parses a YAML file. Throws std::runtime_error naming the file (and line) when it is missing or malformed.
  static Config load(const std::filesystem::path& file);
  // Parses YAML text; `origin` names it in error messages.
  static Config from_string(const std::string& text, const std::string& origin = "<string>");

  // The node of a top-level section, or a nested one with a dotted name ("features.lines").
  // A missing section yields an empty (null) node, so all its keys take their defaults.
  YAML::Node section(const std::string& name) const;
  bool has_section(const std::string& name) const;

  const YAML::Node& root() const { return root_; }
  // Where the config came from (file path or the origin given to from_string); empty for a default Config.
  const std::string& origin() const { return origin_; }

 private:
  YAML::Node root_;
  std::string origin_;
};

// Records the keys that param() reads on this thread while it lives, so that a loader can name the keys of a file
// that nothing read: a misspelt key would otherwise leave its parameter at the default without a word. Logs nest
// (the innermost one records).
class KeyReadLog {
 public:
  KeyReadLog();
  ~KeyReadLog();
  KeyReadLog(const KeyReadLog&) = delete;
  KeyReadLog& operator=(const KeyReadLog&) = delete;

  void note(const YAML::Node& section, const std::string& key);
  // The keys under `node` that were not read, as dotted paths from `prefix` with their lines ("lines.detector.fld.
  // lenght_threshold (line 30)"). Maps are walked into, also in lists; a scalar or a list of scalars is one key.
  std::vector<std::string> unread(const YAML::Node& node, const std::string& prefix = "") const;
  // Throws std::runtime_error naming `origin` (the file) and every unread key under `node`.
  void require_all_read(const YAML::Node& node, const std::string& prefix, const std::string& origin) const;

 private:
  bool was_read(const YAML::Node& section, const std::string& key) const;
  std::vector<std::pair<YAML::Node, std::string>> reads_;
  KeyReadLog* outer_;
};

namespace detail {
void note_key_read(const YAML::Node& section, const std::string& key);  // to the current KeyReadLog, if any
[[noreturn]] void throw_param_error(const YAML::Node& node, const std::string& key, const char* expected);
template <typename T>
constexpr const char* type_name() {
  if constexpr (std::is_same_v<T, bool>)
    return "a boolean";
  else if constexpr (std::is_integral_v<T>)
    return "an integer";
  else if constexpr (std::is_floating_point_v<T>)
    return "a number";
  else if constexpr (std::is_same_v<T, std::string>)
    return "a string";
  else
    return "a value of the expected type";
}
}  // namespace detail

// Reads `section[key]` as T. A missing key (or a missing section) returns `fallback`; a value that does not
// convert to T throws std::runtime_error naming the key and its line.
template <typename T>
T param(const YAML::Node& section, const std::string& key, const T& fallback) {
  if (!section.IsDefined() || !section.IsMap()) return fallback;
  detail::note_key_read(section, key);
  const YAML::Node node = section[key];
  if (!node.IsDefined() || node.IsNull()) return fallback;
  try {
    return node.as<T>();
  } catch (const YAML::Exception&) {
    detail::throw_param_error(node, key, detail::type_name<T>());
  }
}

// In-place form: leaves `value` untouched when the key is missing.
template <typename T>
void read_param(const YAML::Node& section, const std::string& key, T& value) {
  value = param<T>(section, key, value);
}

// Throws std::runtime_error "config key '<name>': expected a map" unless `node` is absent, null or a map (a
// sub-section given as a scalar or a list).
void require_map(const YAML::Node& node, const std::string& name);

// Applies the keys of a `camera:` section on top of `base` (e.g. the dataset's own calibration, or an empty one
// for datasets without a calibration file). Keys, all optional:
//   kalibr                                  a Kalibr camchain file (io/kalibr_camchain.hpp): replaces `base`,
//                                           the other keys then apply on top of it (a relative path is taken
//                                           from the working directory; system::load_vo_config resolves it
//                                           against the config file's folder first)
//   width, height, fx, fy, cx, cy           apply to both cameras
//   baseline                                rectified stereo: right = left shifted by +baseline along x,
//                                           and `rectified` becomes true
//   rectified                               bool
//   left: {...}, right: {...}               per camera: width height fx fy cx cy
//                                           distortion_model (none|radtan|equidistant), distortion_coeffs [..],
//                                           T_body_camera (16 or 12 numbers, row-major; camera -> body, EuRoC's
//                                           T_BS) or T_camera_body (body -> camera, Kalibr's T_cam_imu)
// Throws naming the key on a wrong type, an unknown distortion model or both transforms given. Each value taken
// records its origin in `config_file` (the camera's `origins`) for validate_calibration's messages.
StereoCalibration apply_camera_overrides(const YAML::Node& camera, StereoCalibration base,
                                         const std::string& config_file = {});

// Throws std::runtime_error naming the first missing/invalid field (size, focal length, principal point, distortion
// coefficients, extrinsics, baseline) with the file, key and line it came from (CameraCalibration::origins), or
// `source` where no reader recorded one.
void validate_calibration(const StereoCalibration& calibration, const std::string& source);

}  // namespace vkvo::io
