#include "io/validation.hpp"

#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

namespace vkvo::io {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A key's allowed values: [min, max], or (min, max] when min_exclusive.
struct Rule {
  const char* path;
  double min;
  double max;
  bool min_exclusive = false;
};

Rule positive(const char* path) { return {path, 0.0, kInf, true}; }
Rule non_negative(const char* path) { return {path, 0.0, kInf}; }
Rule at_least_one(const char* path) { return {path, 1.0, kInf}; }
Rule unit(const char* path) { return {path, 0.0, 1.0}; }

// Every numeric key with a range narrower than "any finite number". Counts and sizes start at 1 where zero would
// make a component do nothing or divide by zero; thresholds that are probabilities or ratios lie in [0, 1].
const std::vector<Rule>& rules() {
  static const std::vector<Rule> table = {
      at_least_one("tracking.min_num_match"),
      at_least_one("tracking.init_min_keypoints"),
      at_least_one("tracking.init_min_stereo"),
      positive("tracking.reference_image_area"),
      at_least_one("tracking.queue_capacity"),
      non_negative("tracking.bridge_max_frames"),
      positive("optimization.pixel_sigma"),
      positive("optimization.mono_point_chi2"),
      positive("optimization.stereo_point_chi2"),
      positive("optimization.mono_line_chi2"),
      positive("optimization.stereo_line_chi2"),
      positive("optimization.line_weight"),
      at_least_one("optimization.pose_rounds"),
      at_least_one("optimization.pose_iterations"),
      non_negative("optimization.min_pose_inliers"),
      unit("optimization.pnp_prior_min_inlier_ratio"),
      {"optimization.pnp_min_points", 4.0, kInf},  // a PnP pose needs four points
      at_least_one("optimization.pnp_iterations"),
      unit("optimization.pnp_confidence"),
      at_least_one("optimization.window_size"),
      non_negative("optimization.min_covisible"),
      non_negative("optimization.ba_iterations"),
      non_negative("optimization.ba_rounds"),
      at_least_one("optimization.num_threads"),
      non_negative("keyframe.max_translation"),
      non_negative("keyframe.max_rotation"),
      non_negative("keyframe.max_tracked"),
      non_negative("keyframe.min_tracked"),
      at_least_one("keyframe.max_frames"),
      non_negative("lines.detector.min_length"),
      non_negative("lines.detector.fld.length_threshold"),
      non_negative("lines.detector.fld.distance_threshold"),
      non_negative("lines.detector.fld.canny_threshold1"),
      non_negative("lines.detector.fld.canny_threshold2"),
      {"lines.detector.fld.canny_aperture", 3.0, 7.0},  // OpenCV's Sobel apertures 3, 5, 7
      non_negative("lines.association.max_distance"),
      non_negative("lines.association.extent_margin"),
      unit("lines.matching.score_threshold"),
      non_negative("lines.matching.shared_threshold"),
      non_negative("lines.projection.max_distance"),
      unit("lines.projection.min_overlap"),
      {"nn_matcher.max_cosine_distance", 0.0, 2.0},
      {"nn_matcher.min_similarity", -1.0, 1.0},
      unit("nn_matcher.ratio"),
      unit("point_matcher.match_threshold"),
      at_least_one("point_matcher.sinkhorn_iterations"),
      unit("point_detector.keypoint_threshold"),
      non_negative("point_detector.nms_radius"),
      non_negative("point_detector.remove_borders"),
      non_negative("stereo.max_y_diff"),
      positive("stereo.min_depth"),
      positive("stereo.max_depth"),
      {"stereo.min_line_plane_angle_deg", 0.0, 90.0},
      non_negative("stereo.line_fit_min_points"),
      non_negative("map.min_point_observations"),
      non_negative("map.min_line_observations"),
      non_negative("map.culling_grace_keyframes"),
      {"map.mono_point_min_parallax_deg", 0.0, 90.0},
      non_negative("relocalisation.max_distance"),
      non_negative("relocalisation.max_angle"),
      unit("relocalisation.min_inlier_ratio"),
      non_negative("dataset.first_frame"),
      at_least_one("dataset.stride"),
      positive("dataset.max_stereo_dt_ms"),
      at_least_one("camera.width"),
      at_least_one("camera.height"),
      positive("camera.fx"),
      positive("camera.fy"),
      positive("camera.baseline"),
      at_least_one("camera.left.width"),
      at_least_one("camera.left.height"),
      positive("camera.left.fx"),
      positive("camera.left.fy"),
      at_least_one("camera.right.width"),
      at_least_one("camera.right.height"),
      positive("camera.right.fx"),
      positive("camera.right.fy"),
  };
  return table;
}

YAML::Node find(const YAML::Node& root, const std::string& path) {
  YAML::Node node;
  node.reset(root);  // const walk: operator[] on a non-const node would insert keys
  std::size_t start = 0;
  while (start <= path.size()) {
    const std::size_t dot = path.find('.', start);
    const std::string key = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (!node.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    const YAML::Node& const_node = node;
    const YAML::Node child = const_node[key];
    if (!child.IsDefined()) return YAML::Node(YAML::NodeType::Undefined);
    node.reset(child);
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return node;
}

std::optional<double> number(const YAML::Node& node) {
  if (!node.IsScalar()) return std::nullopt;
  double value = 0;
  if (!YAML::convert<double>::decode(node, value)) return std::nullopt;
  return value;
}

// Every scalar that reads as a number must be finite: YAML's .nan and .inf convert without complaint.
void require_finite(const YAML::Node& node, const std::string& path, const std::string& origin) {
  if (node.IsMap()) {
    for (const auto& item : node) {
      const std::string key = item.first.as<std::string>("?");
      require_finite(item.second, path.empty() ? key : path + "." + key, origin);
    }
  } else if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) require_finite(node[i], fmt::format("{}[{}]", path, i), origin);
  } else if (const auto value = number(node); value && !std::isfinite(*value)) {
    throw std::runtime_error(
        config_error_message(origin, path, node, fmt::format("{} is not a finite number", *value)));
  }
}

std::string range_text(const Rule& rule) {
  const std::string low = fmt::format("{}{}", rule.min_exclusive ? "(" : "[", rule.min);
  const std::string high = std::isinf(rule.max) ? "inf)" : fmt::format("{}]", rule.max);
  return low + ", " + high;
}

}  // namespace

std::string config_error_message(const std::string& origin, const std::string& key_path, const YAML::Node& node,
                                 const std::string& problem) {
  const auto mark = node.Mark();
  const std::string line = mark.is_null() ? std::string() : fmt::format(" (line {})", mark.line + 1);
  return fmt::format("{}: {}{}: {}", origin.empty() ? std::string("config") : origin, key_path, line, problem);
}

void validate_config_values(const Config& config) {
  const YAML::Node& root = config.root();
  if (!root.IsDefined() || root.IsNull()) return;
  require_finite(root, "", config.origin());
  for (const Rule& rule : rules()) {
    const YAML::Node node = find(root, rule.path);
    if (!node.IsDefined()) continue;
    const auto value = number(node);
    if (!value) continue;  // a wrong type is reported by the loader, with the type it expects
    const bool low = rule.min_exclusive ? *value <= rule.min : *value < rule.min;
    if (low || *value > rule.max)
      throw std::runtime_error(config_error_message(config.origin(), rule.path, node,
                                                    fmt::format("{} is outside {}", *value, range_text(rule))));
  }
}

}  // namespace vkvo::io
