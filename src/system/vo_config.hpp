#pragma once
// Every parameter of the VO, read from one YAML file (config/euroc.yaml, config/kitti.yaml, ...). Each section is
// loaded by the module that owns it; a missing key keeps the reference default.
#include <filesystem>
#include <string>

#include <yaml-cpp/yaml.h>

#include "backend/params.hpp"
#include "features/lines/line_params.hpp"
#include "features/nn_matcher_params.hpp"
#include "features/superglue_params.hpp"
#include "features/superpoint_params.hpp"
#include "geometry/triangulation.hpp"
#include "io/config.hpp"
#include "io/dataset.hpp"
#include "map/map.hpp"
#include "system/map_line_projection.hpp"
#include "system/map_point_projection.hpp"
#include "system/relocaliser.hpp"

namespace vkvo::system {

// YAML section `tracking`.
struct TrackingParams {
  int min_num_match = 30;        // fewer matches to the last keyframe: match against the last frame instead
  int init_min_keypoints = 150;  // a frame starts the map with at least this many keypoints ...
  int init_min_stereo = 100;     // ... and this many triangulated stereo matches
  // Lines count towards both: a line observation constrains a pose as much as a point's (2 equations per view), so
  // a frame of edges and few corners (a plain room) can start a map; a line counts for a keypoint when detected
  // and for a stereo match when triangulated.
  bool init_counts_lines = true;
  // A segment that only the lines let start is rebuilt from its first keyframe whose points alone would start one:
  // the thin start's landmarks are dropped, its poses kept (a map begun on a few points cost the frames after it
  // more than it gave; docs/accuracy.md).
  bool rebuild_thin_start = true;
  // A frame whose points fall short of a pose is still matched to the local map's lines (by projection from the
  // pose the points gave, or the prediction) and tracked when points and lines together suffice; the keyframe
  // rule's min_tracked counts its tracked lines too, so such a frame adds landmarks where they are running out.
  bool lines_carry_frames = true;
  // A frame whose points fall short of a pose is also matched to its segment's map points near their projections
  // (key point_projection, map_point_projection.hpp).
  PointProjectionParams point_projection;
  // The two counts above are for images of this many pixels (EuRoC, 752 x 480);
  // smaller images scale them down by the area ratio (SuperPoint finds corners per area: 97 on a 320 x 240
  // rendered room), never up. 0 disables the scaling.
  double reference_image_area = 752.0 * 480.0;
  bool use_lines = true;   // false: the paper's "w/o line" ablation
  int queue_capacity = 2;  // frames in flight between the feature and the optimisation stage
  // Gaps of at most this many untracked frames get poses interpolated between the tracked frames around them,
  // matching the velocities at both ends (TrajectoryRecord); longer ones keep the constant-velocity predictions.
  // 0 interpolates none.
  int bridge_max_frames = 200;
};
TrackingParams load_tracking_params(const YAML::Node& section);

struct VoConfig {
  std::filesystem::path origin;  // the file it came from
  TrackingParams tracking;
  features::LinePipelineParams lines;           // section lines: detector, association, matching
  LineProjectionParams line_projection;         // section lines: projection
  geometry::TriangulationParams triangulation;  // section stereo
  backend::OptimizationParams optimization;     // section optimization
  backend::KeyframeParams keyframe;             // section keyframe
  map::MapParams map;                           // section map
  RelocalisationParams relocalisation;          // section relocalisation
  features::SuperPointParams point_detector;    // section point_detector
  features::SuperGlueParams point_matcher;      // section point_matcher
  features::NnMatcherParams nn_matcher;         // section nn_matcher: the mutual-nearest-neighbour fallback
  // Sections dataset (frame range, stereo pairing) and camera (calibration overrides, kept as YAML: they apply
  // on top of the dataset's own calibration when it is opened; a Kalibr file named there is already resolved
  // against the config's folder).
  io::DatasetOptions dataset;
  std::string matcher = "superglue";       // superglue | nn   (section models: matcher)
  std::filesystem::path superpoint_model;  // section models: superpoint (pack path; may be empty)
  std::filesystem::path superglue_model;   // section models: superglue
};

// Parses every section (those the feature stage and the dataset reader read later too) and throws
// std::runtime_error naming the file and the value or key at fault: a wrong type or value, or a key that no
// module reads (with its line), since a misspelt key would otherwise silently leave its default in place.
VoConfig load_vo_config(const io::Config& config);

// The configuration for images of width x height: tracking.init_min_keypoints and tracking.init_min_stereo
// times min(1, area / tracking.reference_image_area), rounded, but not below 2 x keyframe.min_tracked (a new
// map must start well above the tracking-failure threshold).
VoConfig scale_to_image(const VoConfig& config, int width, int height);
// Every command that takes --config reads it through here (empty path: the defaults), so each one rejects the same
// unknown keys and out-of-range values, whichever sections it uses.
VoConfig load_vo_config_or_defaults(const std::filesystem::path& file);
VoConfig load_vo_config(const std::filesystem::path& file);

// The stereo calibration that the config's `camera:` section gives on its own (its `kalibr` file, or the cameras'
// keys: see io::apply_camera_overrides), for input without a dataset's calibration files, such as StereoOdometry
// fed by a live camera. Throws std::runtime_error naming the config file and the first missing or invalid field.
io::StereoCalibration config_calibration(const VoConfig& config);

}  // namespace vkvo::system
