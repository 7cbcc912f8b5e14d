#include "system/vo_config.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "io/validation.hpp"

namespace vkvo::system {

TrackingParams load_tracking_params(const YAML::Node& section) {
  TrackingParams p;
  io::read_param(section, "min_num_match", p.min_num_match);
  io::read_param(section, "init_min_keypoints", p.init_min_keypoints);
  io::read_param(section, "init_min_stereo", p.init_min_stereo);
  io::read_param(section, "init_counts_lines", p.init_counts_lines);
  io::read_param(section, "rebuild_thin_start", p.rebuild_thin_start);
  io::read_param(section, "lines_carry_frames", p.lines_carry_frames);
  p.point_projection = load_point_projection_params(section["point_projection"]);
  io::read_param(section, "reference_image_area", p.reference_image_area);
  io::read_param(section, "use_lines", p.use_lines);
  io::read_param(section, "queue_capacity", p.queue_capacity);
  if (p.queue_capacity < 1) throw std::runtime_error("tracking.queue_capacity must be at least 1");
  io::read_param(section, "bridge_max_frames", p.bridge_max_frames);
  if (p.bridge_max_frames < 0) throw std::runtime_error("tracking.bridge_max_frames must not be negative");
  return p;
}

VoConfig load_vo_config(const io::Config& config) {
  io::KeyReadLog key_log;  // every section below is parsed, so a key that no loader reads is a mistake
  io::validate_config_values(config);
  VoConfig vo;
  vo.origin = config.origin();
  vo.tracking = load_tracking_params(config.section("tracking"));
  vo.lines = features::load_line_pipeline_params(config.section("lines"));
  vo.line_projection = load_line_projection_params(config.section("lines")["projection"]);
  vo.triangulation = geometry::load_triangulation_params(config.section("stereo"));
  if (!(vo.triangulation.min_depth < vo.triangulation.max_depth)) {
    const YAML::Node stereo = config.section("stereo");
    throw std::runtime_error(
        io::config_error_message(config.origin(), "stereo.min_depth",
                                 stereo["min_depth"].IsDefined() ? stereo["min_depth"] : stereo["max_depth"],
                                 fmt::format("min_depth {} must be less than max_depth {}", vo.triangulation.min_depth,
                                             vo.triangulation.max_depth)));
  }
  vo.optimization = backend::load_optimization_params(config.section("optimization"));
  vo.keyframe = backend::load_keyframe_params(config.section("keyframe"));
  vo.map = map::load_map_params(config.section("map"));
  vo.relocalisation = load_relocalisation_params(config.section("relocalisation"));
  // Every section is parsed here, those of components a run may not use too (SuperGlue's under the NN matcher),
  // so that a wrong key or value stops the run before any work.
  vo.point_detector = features::load_superpoint_params(config.section("point_detector"));
  vo.point_matcher = features::load_superglue_params(config.section("point_matcher"));
  vo.nn_matcher = features::load_nn_matcher_params(config.section("nn_matcher"));
  YAML::Node camera = config.section("camera");
  // A Kalibr camchain named in the camera section is relative to the config file, wherever the run starts.
  if (const auto camchain = io::param<std::string>(camera, "kalibr", ""); !camchain.empty()) {
    const std::filesystem::path path(camchain);
    if (path.is_relative() && !config.origin().empty() && std::filesystem::exists(config.origin()))
      camera["kalibr"] = (std::filesystem::path(config.origin()).parent_path() / path).lexically_normal().string();
  }
  vo.dataset = io::load_dataset_options(config.section("dataset"), camera);
  vo.dataset.config_file = config.origin();
  // The camera section is applied when the dataset opens (on top of its calibration); applied to nothing now, it
  // checks its keys and values (and reads a Kalibr file named there) up front.
  io::apply_camera_overrides(camera, {}, config.origin());
  const YAML::Node models = config.section("models");
  io::read_param(models, "matcher", vo.matcher);
  if (vo.matcher != "superglue" && vo.matcher != "nn")
    throw std::runtime_error(config.origin() + ": models.matcher must be 'superglue' or 'nn', not '" + vo.matcher +
                             "'");
  std::string superpoint, superglue;
  io::read_param(models, "superpoint", superpoint);
  io::read_param(models, "superglue", superglue);
  vo.superpoint_model = superpoint;
  vo.superglue_model = superglue;

  key_log.require_all_read(config.root(), "", config.origin());
  return vo;
}

VoConfig load_vo_config(const std::filesystem::path& file) { return load_vo_config(io::Config::load(file)); }

VoConfig load_vo_config_or_defaults(const std::filesystem::path& file) {
  return load_vo_config(file.empty() ? io::Config() : io::Config::load(file));
}

io::StereoCalibration config_calibration(const VoConfig& config) {
  io::StereoCalibration calibration =
      io::apply_camera_overrides(config.dataset.camera_overrides, {}, config.dataset.config_file);
  io::validate_calibration(calibration, config.origin.string() + " (camera section)");
  return calibration;
}

VoConfig scale_to_image(const VoConfig& config, int width, int height) {
  VoConfig scaled = config;
  const double reference = config.tracking.reference_image_area;
  if (reference <= 0 || width <= 0 || height <= 0) return scaled;
  const double factor = std::min(1.0, double(width) * double(height) / reference);
  const int floor = 2 * config.keyframe.min_tracked;
  auto scale = [&](int count) {
    return std::max(std::min(count, floor), static_cast<int>(std::lround(count * factor)));
  };
  scaled.tracking.init_min_keypoints = scale(config.tracking.init_min_keypoints);
  scaled.tracking.init_min_stereo = scale(config.tracking.init_min_stereo);
  return scaled;
}

}  // namespace vkvo::system
