#pragma once
// Mono multi-view map points: a keypoint that the stereo pair could not place (no right-image match, or beyond the
// stereo depth gate) but that the frame-to-keyframe matching paired with an unmapped keypoint of the reference
// keyframe is the same 3D point seen from two poses. Triangulated from the two keyframes, it gets an observation in
// both, so the map keeps points where stereo fails: far scenes (stereo depth is capped), one camera darker, thin
// texture.
#include <vector>

#include "geometry/camera.hpp"
#include "map/map.hpp"

namespace vkvo::system {

struct MonoPointParams {
  // The two rays must meet at least at this angle: below it the depth is mostly noise.
  double min_parallax_deg = 1.0;
  // Both views must reproject within this many pixels: pixel_sigma 0.8 * sqrt(5.991), the 95 % gate of a 2-D error.
  double max_reprojection_px = 1.96;
  double min_depth = 0.1;  // m, in both views
};

struct NewMonoPoints {
  int candidates = 0;  // keypoints matched to the reference with a map point on neither side and no stereo match
  int added = 0;       // ... that passed the parallax, depth and reprojection gates and became map points
};

// For keyframe `kf`: `reference_partner` holds, per keypoint of `kf`, the index of its matched keypoint in keyframe
// `reference` or -1. Keypoints of `kf` with a stereo match or a map point are left alone (the stereo pair maps them).
NewMonoPoints add_mono_points(map::Map& map, map::Id kf, map::Id reference, const std::vector<int>& reference_partner,
                              const geometry::PinholeCamera& camera, const MonoPointParams& params);

}  // namespace vkvo::system
