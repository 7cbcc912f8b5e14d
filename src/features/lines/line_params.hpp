#pragma once
// Parameters of the line pipeline (detection + merge, point association, line matching) with the reference
// defaults, and their YAML loaders. Every key is optional: a missing key keeps the default, a key of the wrong
// type throws std::runtime_error naming it.
#include <vector>

#include <yaml-cpp/yaml.h>

namespace vkvo::features {

enum class LineDetectorMethod { kFastLineDetector, kLsd };

// OpenCV ximgproc FastLineDetector settings (reference config), in pixels of the (possibly downscaled)
// detection image.
struct FldParams {
  int length_threshold = 7;
  float distance_threshold = 1.414f;
  double canny_threshold1 = 50.0;
  double canny_threshold2 = 50.0;
  int canny_aperture = 3;
};

// OpenCV LSD (cv::createLineSegmentDetector) settings; only the refinement mode is exposed.
struct LsdParams {
  enum class Refine { kNone, kStandard, kAdvanced };
  Refine refine = Refine::kStandard;
};

// When two segments are fused (full-resolution pixels). See merge_segments().
struct MergeParams {
  float max_angle = 0.03f;             // delta_theta [rad]
  float max_midpoint_distance = 3.0f;  // delta_d [px]
  float max_endpoint_gap = 50.0f;      // delta_ep [px], only when the segments do not overlap
};

// One merge pass followed by a length filter. The reference code runs a coarse-gap and a wide-gap pass.
struct MergeStage {
  MergeParams merge;
  float min_length_after = 0.0f;  // segments shorter than this are dropped after the pass [px]
};

struct LineDetectorParams {
  LineDetectorMethod method = LineDetectorMethod::kFastLineDetector;
  float scale = 0.5f;  // detect on the image resized by this factor, coordinates mapped back to full size
  FldParams fld;
  LsdParams lsd;
  // Reference code: merge (0.05 rad, 5 px, 15 px) then drop < 30 px; merge (0.03 rad, 3 px, 50 px).
  std::vector<MergeStage> merge_stages = {{{0.05f, 5.0f, 15.0f}, 30.0f}, {{0.03f, 3.0f, 50.0f}, 0.0f}};
  float min_length = 60.0f;  // final length filter [px, full resolution]
  // The edge thresholds above hold for a well-exposed image; one whose intensities (1st to 99th percentile) span
  // less than this many grey levels is stretched linearly to span them first, so that a dim or flat image keeps
  // its edges. 0: off.
  float min_contrast = 128.0f;
};

// Point-to-line association, paper eq. 1.
struct AssociationParams {
  float max_distance = 3.0f;   // point-to-infinite-line distance must be < this [px]
  float extent_margin = 3.0f;  // slack on the segment's x/y extent [px]
  // true: x within the x-extent AND y within the y-extent (the reference code's box test; the paper's literal
  // "or" accepts every point on the infinite extension of an axis-aligned segment). false: the paper's "or".
  bool require_both_extents = true;
  float grid_cell_size = 16.0f;  // bucket size of the spatial grid over the points [px]
};

// Which score a line pair must reach: the paper's S = N_pm / min(N_m, N_n) > delta_S (eq. 2), or AirVO's code's
// N_pm^2 / min(N_m, N_n) >= delta_S, which favours lines sharing many points over short, sparsely supported ones.
enum class LineMatchScore { kPaper, kAirvo };

// Line matching through point matches: accept when the score passes score_threshold and N_pm > shared_threshold.
struct LineMatchParams {
  float score_threshold = 0.5f;  // delta_S
  int shared_threshold = 1;      // delta_N: at least shared_threshold + 1 shared point matches
  LineMatchScore score = LineMatchScore::kPaper;
};

// Left-right matching by appearance for the lines point matches leave unpaired (stereo_line_matching.hpp).
struct StereoLineMatchParams {
  bool by_appearance = true;
  // Rows a segment must span [px]: a flatter one has no extent across the epipolar lines to compare, and its
  // back-projected planes nearly coincide.
  float min_rows = 10.0f;
  // Rows both segments span, as a fraction of the longer one's: images of one 3D segment span the same rows.
  float min_row_overlap = 0.5f;
  // ZNCC over the strips (each row's samples across the line, all rows the two share).
  float min_zncc = 0.8f;
  // The best candidate's ZNCC above the second best's: parallel edges of one polarity correlate alike, and only
  // a clear winner is taken.
  float min_margin = 0.1f;
  // Samples either side of the line on each row [px].
  int half_width = 3;
};

// Keyframe-to-reference-keyframe matching by appearance for the new keyframe's lines that neither the stereo pair
// nor the point matches placed (system/keyframe_line_matching.hpp): the same line seen from two poses.
struct KeyframeLineMatchParams {
  bool by_appearance = true;
  // Samples transferred from the new keyframe's segment that land on the reference segment, as a fraction of the
  // samples, and the reference segment's extent they cover, as a fraction of its length: both images of one 3D
  // segment overlap.
  float min_overlap = 0.5f;
  float min_zncc = 0.8f;    // as for stereo pairs
  float min_margin = 0.1f;  // ... the clear winner among candidates
  int half_width = 3;       // samples either side of the line, across it [px]
};

struct LinePipelineParams {
  LineDetectorParams detector;
  AssociationParams association;
  LineMatchParams matching;
  StereoLineMatchParams stereo_matching;
  KeyframeLineMatchParams keyframe_matching;
};

LineDetectorParams load_line_detector_params(const YAML::Node& section);
AssociationParams load_association_params(const YAML::Node& section);
LineMatchParams load_line_match_params(const YAML::Node& section);
StereoLineMatchParams load_stereo_line_match_params(const YAML::Node& section);
KeyframeLineMatchParams load_keyframe_line_match_params(const YAML::Node& section);
// Reads the sub-sections `detector`, `association`, `matching`, `stereo_matching` and `keyframe_matching` of a
// `lines` section.
LinePipelineParams load_line_pipeline_params(const YAML::Node& section);

}  // namespace vkvo::features
