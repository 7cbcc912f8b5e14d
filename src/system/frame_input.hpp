#pragma once
// What the feature stage hands to the optimisation stage for one stereo frame.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "features/lines/line_segment.hpp"
#include "features/point_features.hpp"
#include "map/map.hpp"

namespace vkvo::system {

struct FrameInput {
  std::size_t index = 0;  // position in the processed sequence (or the caller's stream)
  std::int64_t timestamp_ns = 0;
  double timestamp_s = 0;
  cv::Mat left, right;                       // rectified 8-bit images (right: used when the frame becomes a keyframe)
  features::PointFeatures points;            // left image
  std::vector<features::LineSegment> lines;  // left image (empty with lines disabled)

  // Matches of `points` to the reference they were matched against: the keyframe `reference_keyframe`, or the
  // previous frame when `matched_previous_frame` (too few matches to the keyframe), or nothing yet.
  features::PointMatches matches;
  map::Id reference_keyframe = map::kInvalidId;
  bool matched_previous_frame = false;
  // The keyframe the feature stage tried first (whichever matches it kept) and the previous frame's features it
  // could fall back to: when the tracker has a newer keyframe by now it makes the same choice again against that
  // one, so the result does not depend on how far the feature stage ran ahead.
  map::Id matched_against = map::kInvalidId;
  std::shared_ptr<const features::PointFeatures> previous_points;

  double pe_ms = 0, le_ms = 0, pm_ms = 0;  // feature-stage timings
};

}  // namespace vkvo::system
