#pragma once
// Map lines for a new keyframe: each of its lines that tracks no map line gets one, from the stereo pair's
// triangulation (StereoLines) or else from the reference keyframe's view of the same line. The reference view is
// the line that the frame-to-keyframe line matching (through the point matches, paper eq. 2) paired with it, when
// that line has no map line either: the same unmapped line seen from two poses. Such a line gets an observation in
// both keyframes, so two poses constrain it from the start and it outlives the map's culling of lines seen once.
#include <vector>

#include "geometry/camera.hpp"
#include "geometry/triangulation.hpp"
#include "map/map.hpp"
#include "system/stereo_keyframe.hpp"

namespace vkvo::system {

struct KeyframeLineParams {
  geometry::TriangulationParams triangulation;
  // The reference keyframe's segment must lie this close (both endpoints, pixels) to the projection of the new
  // line to be taken as another view of it.
  double max_reprojection_px = 5.66;  // pixel_sigma 0.8 * sqrt(mono_line_chi2 50)
};

struct NewKeyframeLines {
  int added = 0;       // map lines created
  int two_view = 0;    // ... of which triangulated from the two keyframes (the stereo pair could not)
  int seen_twice = 0;  // ... of which observed by the reference keyframe too
};

// `stereo_lines` is per line of keyframe `kf`, in its camera frame; `reference_partner` per line of `kf` the
// partner line index in keyframe `reference` or -1 (`reference` kInvalidId: none, e.g. in a new map segment,
// whose pose is only predicted).
NewKeyframeLines add_keyframe_lines(map::Map& map, map::Id kf, const StereoLines& stereo_lines, map::Id reference,
                                    const std::vector<int>& reference_partner, const geometry::PinholeCamera& camera,
                                    const KeyframeLineParams& params);

}  // namespace vkvo::system
