#pragma once
// One frame of the overlay video (`vkvo run --video`): the rectified left image with the frame's keypoints and
// lines coloured by what tracking made of them (system::FrameObservations), under a text band with the frame's
// index, time, state, inlier counts and keyframe flag. docs/video.md has the legend.
#include <opencv2/core.hpp>

#include "system/stereo_odometry.hpp"

namespace vkvo::viz {

// BGR colours of the overlay (docs/video.md).
namespace colour {
inline const cv::Scalar inlier{0, 255, 0};            // green: tracked map point, inlier of the pose
inline const cv::Scalar outlier{0, 0, 255};           // red: matched to a map point, rejected
inline const cv::Scalar new_point{255, 255, 0};       // cyan: map point created by this keyframe
inline const cv::Scalar unmatched{0, 255, 255};       // yellow (small): detected, not matched to the map
inline const cv::Scalar matched_line{255, 0, 255};    // magenta: line associated with a map line
inline const cv::Scalar unmatched_line{0, 128, 255};  // orange: line without a map line
// Tags at the right of the text band (black text on these).
inline const cv::Scalar tracked{0, 255, 0};        // green: TRACKED
inline const cv::Scalar relocalised{255, 128, 0};  // blue: RELOCALISED
inline const cv::Scalar lost{0, 0, 255};           // red: LOST
inline const cv::Scalar keyframe{255, 255, 0};     // cyan: KEYFRAME
}  // namespace colour

inline constexpr int kTextBandHeight = 44;    // pixels above the image: two lines of text
inline constexpr int kPointRadius = 3;        // inliers, outliers, new points (unmatched ones: 1)
inline constexpr int kAssociationRadius = 6;  // ring around a keypoint associated with a line, in the line's colour

// The size of every overlay frame for images of `image_size`: the text band added, both sides rounded up to even
// (MPEG-4 encoders need even sizes).
cv::Size overlay_size(cv::Size image_size);

// The overlay of one processed frame, 8-bit BGR of overlay_size(the image's size). A pose without observations
// (or with an empty image) gets a black image of `image_size` under its text band.
cv::Mat draw_overlay(const system::OdometryPose& pose, cv::Size image_size);

}  // namespace vkvo::viz
