#include "features/lines/line_params.hpp"

#include <stdexcept>
#include <string>
#include <utility>

#include "io/config.hpp"

namespace vkvo::features {
namespace {

// Reads section[key] as one of two names, mapped to `first` or `second`; absent keeps `value`.
template <typename Enum>
void read_choice(const YAML::Node& section, const std::string& context, const char* key,
                 std::pair<const char*, Enum> first, std::pair<const char*, Enum> second, Enum& value) {
  std::string name = value == second.second ? second.first : first.first;
  io::read_param(section, key, name);
  if (name == first.first) {
    value = first.second;
  } else if (name == second.first) {
    value = second.second;
  } else {
    throw std::runtime_error("config key '" + context + "." + key + "': expected '" + first.first + "' or '" +
                             second.first + "', got '" + name + "'");
  }
}

MergeStage load_merge_stage(const YAML::Node& node, const std::string& context) {
  io::require_map(node, context);
  MergeStage stage;
  io::read_param(node, "max_angle", stage.merge.max_angle);
  io::read_param(node, "max_midpoint_distance", stage.merge.max_midpoint_distance);
  io::read_param(node, "max_endpoint_gap", stage.merge.max_endpoint_gap);
  io::read_param(node, "min_length_after", stage.min_length_after);
  return stage;
}

// The switch and the gates shared by the two appearance matchings (stereo_matching, keyframe_matching).
void read_appearance_gates(const YAML::Node& section, const std::string& name, bool& by_appearance, float& min_zncc,
                           float& min_margin, int& half_width) {
  io::read_param(section, "by_appearance", by_appearance);
  io::read_param(section, "min_zncc", min_zncc);
  io::read_param(section, "min_margin", min_margin);
  io::read_param(section, "half_width", half_width);
  if (!(min_zncc >= -1.0f && min_zncc <= 1.0f))
    throw std::runtime_error("config key '" + name + ".min_zncc': must lie in [-1, 1]");
  if (!(min_margin >= 0.0f)) throw std::runtime_error("config key '" + name + ".min_margin': must not be negative");
  if (half_width < 1) throw std::runtime_error("config key '" + name + ".half_width': must be at least 1");
}

}  // namespace

LineDetectorParams load_line_detector_params(const YAML::Node& section) {
  LineDetectorParams params;
  io::require_map(section, "detector");
  if (!section || !section.IsMap()) return params;
  const std::string ctx = "detector.";

  read_choice(section, "detector", "method", {"fld", LineDetectorMethod::kFastLineDetector},
              {"lsd", LineDetectorMethod::kLsd}, params.method);
  io::read_param(section, "scale", params.scale);
  if (!(params.scale > 0.0f && params.scale <= 1.0f))
    throw std::runtime_error("config key 'detector.scale': must lie in (0, 1]");
  io::read_param(section, "min_length", params.min_length);
  io::read_param(section, "min_contrast", params.min_contrast);
  if (!(params.min_contrast >= 0.0f && params.min_contrast <= 255.0f))
    throw std::runtime_error("config key 'detector.min_contrast': must lie in [0, 255]");

  if (const YAML::Node fld = section["fld"]) {
    io::require_map(fld, ctx + "fld");
    io::read_param(fld, "length_threshold", params.fld.length_threshold);
    io::read_param(fld, "distance_threshold", params.fld.distance_threshold);
    io::read_param(fld, "canny_threshold1", params.fld.canny_threshold1);
    io::read_param(fld, "canny_threshold2", params.fld.canny_threshold2);
    io::read_param(fld, "canny_aperture", params.fld.canny_aperture);
  }
  if (const YAML::Node lsd = section["lsd"]) {
    io::require_map(lsd, ctx + "lsd");
    std::string refine = "standard";
    io::read_param(lsd, "refine", refine);
    if (refine == "none") {
      params.lsd.refine = LsdParams::Refine::kNone;
    } else if (refine == "standard") {
      params.lsd.refine = LsdParams::Refine::kStandard;
    } else if (refine == "advanced") {
      params.lsd.refine = LsdParams::Refine::kAdvanced;
    } else {
      throw std::runtime_error("config key 'detector.lsd.refine': expected none, standard or advanced");
    }
  }
  if (const YAML::Node stages = section["merge_stages"]) {
    if (!stages.IsSequence()) throw std::runtime_error("config key 'detector.merge_stages': expected a list");
    params.merge_stages.clear();
    for (size_t i = 0; i < stages.size(); ++i)
      params.merge_stages.push_back(load_merge_stage(stages[i], ctx + "merge_stages[" + std::to_string(i) + "]"));
  }
  return params;
}

AssociationParams load_association_params(const YAML::Node& section) {
  AssociationParams params;
  io::require_map(section, "association");
  io::read_param(section, "max_distance", params.max_distance);
  io::read_param(section, "extent_margin", params.extent_margin);
  io::read_param(section, "require_both_extents", params.require_both_extents);
  io::read_param(section, "grid_cell_size", params.grid_cell_size);
  if (!(params.grid_cell_size > 0.0f))
    throw std::runtime_error("config key 'association.grid_cell_size': must be positive");
  return params;
}

LineMatchParams load_line_match_params(const YAML::Node& section) {
  LineMatchParams params;
  io::require_map(section, "matching");
  read_choice(section, "matching", "score", {"paper", LineMatchScore::kPaper}, {"airvo", LineMatchScore::kAirvo},
              params.score);
  io::read_param(section, "score_threshold", params.score_threshold);
  io::read_param(section, "shared_threshold", params.shared_threshold);
  return params;
}

StereoLineMatchParams load_stereo_line_match_params(const YAML::Node& section) {
  StereoLineMatchParams params;
  io::require_map(section, "stereo_matching");
  read_appearance_gates(section, "stereo_matching", params.by_appearance, params.min_zncc, params.min_margin,
                        params.half_width);
  io::read_param(section, "min_rows", params.min_rows);
  io::read_param(section, "min_row_overlap", params.min_row_overlap);
  if (!(params.min_rows >= 2.0f)) throw std::runtime_error("config key 'stereo_matching.min_rows': must be at least 2");
  if (!(params.min_row_overlap > 0.0f && params.min_row_overlap <= 1.0f))
    throw std::runtime_error("config key 'stereo_matching.min_row_overlap': must lie in (0, 1]");
  return params;
}

KeyframeLineMatchParams load_keyframe_line_match_params(const YAML::Node& section) {
  KeyframeLineMatchParams params;
  io::require_map(section, "keyframe_matching");
  read_appearance_gates(section, "keyframe_matching", params.by_appearance, params.min_zncc, params.min_margin,
                        params.half_width);
  io::read_param(section, "min_overlap", params.min_overlap);
  if (!(params.min_overlap > 0.0f && params.min_overlap <= 1.0f))
    throw std::runtime_error("config key 'keyframe_matching.min_overlap': must lie in (0, 1]");
  return params;
}

LinePipelineParams load_line_pipeline_params(const YAML::Node& section) {
  LinePipelineParams params;
  io::require_map(section, "lines");
  if (!section || !section.IsMap()) return params;
  params.detector = load_line_detector_params(section["detector"]);
  params.association = load_association_params(section["association"]);
  params.matching = load_line_match_params(section["matching"]);
  params.stereo_matching = load_stereo_line_match_params(section["stereo_matching"]);
  params.keyframe_matching = load_keyframe_line_match_params(section["keyframe_matching"]);
  return params;
}

}  // namespace vkvo::features
