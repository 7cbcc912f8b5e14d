#pragma once
// Whether the current frame becomes a keyframe (paper sec. "Keyframe Selection" plus the frame-count rule).
#include <Eigen/Geometry>

#include "backend/params.hpp"

namespace vkvo::backend {

struct KeyframeDecisionInput {
  Eigen::Isometry3d T_world_last_keyframe = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_world_current = Eigen::Isometry3d::Identity();
  int tracked = 0;           // map points (inliers) tracked by the current frame
  int tracked_lines = 0;     // map lines (inliers) tracked by the current frame
  int tracked_previous = 0;  // same for the previous frame (< min_tracked: tracking failed there)
  int frames_since_keyframe = 0;
};

enum class KeyframeReason { none, tracking_failed, translation, rotation, few_tracked, recovered, frame_count };
const char* to_string(KeyframeReason reason);

// The first rule that fires, or none. A frame tracking fewer than min_tracked points and lines together never
// becomes a keyframe (its pose is unreliable); that case is reported as tracking_failed. The other rules count
// points alone: a line observation constrains a pose as a point's does, but the map's points are what run out.
KeyframeReason keyframe_reason(const KeyframeParams& params, const KeyframeDecisionInput& input);
inline bool need_new_keyframe(const KeyframeParams& params, const KeyframeDecisionInput& input) {
  const KeyframeReason r = keyframe_reason(params, input);
  return r != KeyframeReason::none && r != KeyframeReason::tracking_failed;
}

}  // namespace vkvo::backend
