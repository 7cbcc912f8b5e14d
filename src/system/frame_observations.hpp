#pragma once
// What the optimisation stage made of one frame's features, for whoever looks at the frame (the overlay video of
// `vkvo run --video`): the role of every left keypoint and line after tracking, in rectified left-image pixels.
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "geometry/line3d.hpp"

namespace vkvo::system {

enum class KeypointRole : std::uint8_t {
  inlier,     // matched to a map point and an inlier of the frame's pose
  outlier,    // matched to a map point by the reference matching, rejected by the pose
  new_point,  // a map point created by this frame (a keyframe's new stereo point)
  unmatched,  // none of these
};

enum class LineRole : std::uint8_t {
  matched,    // associated with a map line by the frame's pose
  unmatched,  // not (a keyframe may still have made a new map line of it)
};

struct FrameObservations {
  cv::Mat left;                               // the rectified left image (8-bit grey; shares the stage's pixels)
  std::vector<Eigen::Vector2d> keypoints;     // left image
  std::vector<KeypointRole> roles;            // one per keypoint
  std::vector<geometry::Segment2d> lines;     // left image, (x1, y1, x2, y2)
  std::vector<LineRole> line_roles;           // one per line
  std::vector<std::vector<int>> line_points;  // per line, the keypoints associated with it (empty without lines)
};

}  // namespace vkvo::system
