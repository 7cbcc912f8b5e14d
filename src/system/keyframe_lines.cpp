#include "system/keyframe_lines.hpp"

#include <optional>

namespace vkvo::system {

NewKeyframeLines add_keyframe_lines(map::Map& map, map::Id kf, const StereoLines& stereo_lines, map::Id reference,
                                    const std::vector<int>& reference_partner, const geometry::PinholeCamera& camera,
                                    const KeyframeLineParams& params) {
  NewKeyframeLines out;
  // The map keeps its keyframes in place while lines and observations are added.
  const map::KeyFrame& keyframe = *map.keyframe(kf);
  const map::KeyFrame* ref = reference == kf ? nullptr : map.keyframe(reference);
  const Eigen::Isometry3d& T = keyframe.T_world_camera;
  for (std::size_t l = 0; l < keyframe.lines.size(); ++l) {
    if (keyframe.line_ids[l] != map::kInvalidId) continue;  // tracked
    const geometry::LineObservation here{T, keyframe.lines[l].left};
    const int r = ref && l < reference_partner.size() ? reference_partner[l] : -1;
    std::optional<geometry::LineObservation> there;
    if (r >= 0 && static_cast<std::size_t>(r) < ref->lines.size() &&
        ref->line_ids[static_cast<std::size_t>(r)] == map::kInvalidId)
      there = geometry::LineObservation{ref->T_world_camera, ref->lines[static_cast<std::size_t>(r)].left};

    std::optional<geometry::PlueckerLine> L;
    bool from_two_views = false;
    if (l < stereo_lines.lines.size() && stereo_lines.lines[l]) {
      L = geometry::transform_line(T, *stereo_lines.lines[l]);
    } else if (there) {
      L = geometry::triangulate_two_view_line(camera, here, *there, params.triangulation);
      from_two_views = L.has_value();
    }
    if (!L) continue;
    const map::Id id = map.add_line(*L);
    map.add_line_observation(id, kf, static_cast<int>(l));
    if (there && geometry::line_reprojection_error(*L, camera, *there) <= params.max_reprojection_px) {
      map.add_line_observation(id, reference, r);
      ++out.seen_twice;
    }
    map.trim_line(id, camera);
    ++out.added;
    out.two_view += from_two_views;
  }
  return out;
}

}  // namespace vkvo::system
