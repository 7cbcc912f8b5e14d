#pragma once
// The picture at the end of `vkvo run --video`: the trajectory with the map's points and lines seen from above,
// i.e. projected onto the x-z plane of the first camera (x right, z forward: up in the picture), equal scale on
// both axes, with a scale bar. docs/video.md has the legend.
#include <opencv2/core.hpp>

#include "io/map_ply.hpp"

namespace vkvo::viz {

namespace topdown_colour {
inline const cv::Scalar background{255, 255, 255};
inline const cv::Scalar point{150, 150, 150};   // grey: map points
inline const cv::Scalar line{200, 120, 0};      // blue: map lines
inline const cv::Scalar trajectory{0, 0, 220};  // red: camera centres, joined in frame order
inline const cv::Scalar start{0, 160, 0};       // green disc: the first pose
}  // namespace topdown_colour

// 8-bit BGR, `size` pixels. The view spans the whole trajectory and the central 96 % of the map points along each
// axis (a few far, badly triangulated points would otherwise shrink everything else to a dot).
cv::Mat draw_topdown(const io::MapGeometry& map, cv::Size size = {900, 900});

}  // namespace vkvo::viz
