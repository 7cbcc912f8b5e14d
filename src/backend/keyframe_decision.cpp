#include "backend/keyframe_decision.hpp"

namespace vkvo::backend {

const char* to_string(KeyframeReason reason) {
  switch (reason) {
    case KeyframeReason::none: return "none";
    case KeyframeReason::tracking_failed: return "tracking_failed";
    case KeyframeReason::translation: return "translation";
    case KeyframeReason::rotation: return "rotation";
    case KeyframeReason::few_tracked: return "few_tracked";
    case KeyframeReason::recovered: return "recovered";
    case KeyframeReason::frame_count: return "frame_count";
  }
  return "?";
}

KeyframeReason keyframe_reason(const KeyframeParams& p, const KeyframeDecisionInput& in) {
  if (in.tracked + in.tracked_lines < p.min_tracked) return KeyframeReason::tracking_failed;
  const Eigen::Isometry3d delta = in.T_world_last_keyframe.inverse() * in.T_world_current;
  if (delta.translation().norm() > p.max_translation) return KeyframeReason::translation;
  if (Eigen::AngleAxisd(delta.linear()).angle() > p.max_rotation) return KeyframeReason::rotation;
  if (in.tracked < p.max_tracked) return KeyframeReason::few_tracked;
  if (in.tracked_previous < p.min_tracked) return KeyframeReason::recovered;
  if (in.frames_since_keyframe >= p.max_frames) return KeyframeReason::frame_count;
  return KeyframeReason::none;
}

}  // namespace vkvo::backend
