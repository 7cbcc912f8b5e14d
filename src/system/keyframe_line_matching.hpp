#pragma once
// A new keyframe's lines paired with its reference keyframe's by appearance, for the lines that neither the stereo
// pair nor the point matches placed. Most of a keyframe's lines get no right partner (near-horizontal ones have no
// disparity to measure, others are detected differently in the right image) and share fewer than two matched
// points with the reference keyframe (paper eq. 2), so few become map lines. Between two keyframes of known
// pose every candidate pair triangulates to one 3D line (the planes' intersection, within the depth gates), which
// transfers each point of the new segment onto the reference image; the strips along the two images then correlate
// only if they are the same edge, and an overlap gate rejects pairs whose segments do not cover one another.
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "features/lines/line_params.hpp"
#include "geometry/camera.hpp"
#include "geometry/line3d.hpp"
#include "geometry/triangulation.hpp"

namespace vkvo::system {

// One keyframe's left image (8-bit grey), its line segments, which of them may be paired, and its pose.
struct KeyframeLineView {
  const cv::Mat& image;
  const std::vector<geometry::Segment2d>& segments;
  const std::vector<bool>& open;  // per segment
  Eigen::Isometry3d T_world_camera;
};

// Gives each open line l of `here` with partner[l] < 0 the open line of `reference`, not yet anyone's partner,
// that triangulates with it inside the depth gates, overlaps it by min_overlap both ways after the transfer and
// correlates best, when the correlation reaches min_zncc and beats both lines' second best by min_margin.
// `partner` is sized like here.segments.
void add_keyframe_partners_by_appearance(const geometry::PinholeCamera& camera, const KeyframeLineView& here,
                                         const KeyframeLineView& reference,
                                         const geometry::TriangulationParams& triangulation,
                                         const features::KeyframeLineMatchParams& params, std::vector<int>& partner);

}  // namespace vkvo::system
