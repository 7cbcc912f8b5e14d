#pragma once
// The stereo half of keyframe creation: right-image features, left<->right point and line matching, and
// triangulation of the matches in the rectified left camera frame.
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "features/lines/line_params.hpp"
#include "features/lines/line_segment.hpp"
#include "features/lines/point_line_association.hpp"
#include "features/point_features.hpp"
#include "geometry/camera.hpp"
#include "geometry/line3d.hpp"
#include "geometry/triangulation.hpp"

namespace vkvo::system {

struct StereoPoints {
  std::vector<double> right_x;                            // per left keypoint, -1 when not stereo-matched
  std::vector<std::optional<Eigen::Vector3d>> positions;  // per left keypoint, left camera frame
  int count = 0;                                          // triangulated keypoints
};

// Keeps the left<->right matches that pass the row and depth gates and triangulates them.
StereoPoints triangulate_stereo_points(const geometry::StereoCamera& stereo, const features::PointFeatures& left,
                                       const features::PointFeatures& right, const features::PointMatches& matches,
                                       const geometry::TriangulationParams& params);

// Per left keypoint, its 3D position in the left camera frame where one is known: the tracked map point's
// (`tracked_world`, world frame, refined by earlier bundle adjustments) or else this keyframe's stereo one.
std::vector<std::optional<Eigen::Vector3d>> known_points_in_camera(
    const StereoPoints& stereo, const std::vector<std::optional<Eigen::Vector3d>>& tracked_world,
    const Eigen::Isometry3d& T_world_camera);

struct StereoLines {
  std::vector<std::optional<geometry::Segment2d>> right;     // per left line
  std::vector<std::optional<geometry::PlueckerLine>> lines;  // per left line, left camera frame
  int planes = 0, points = 0;                                // lines per triangulation method
};

// One image's line segments and the keypoints associated to each (features::associate_points_to_lines).
struct AssociatedLines {
  const std::vector<features::LineSegment>& segments;
  const features::PointLineAssociation& association;
};

// The rectified 8-bit grey pair.
struct StereoImages {
  const cv::Mat& left;
  const cv::Mat& right;
};

// What line triangulation needs to know of the left image's keypoints, per keypoint.
struct LeftKeypoints {
  const std::vector<Eigen::Vector2f>& pixels;
  const std::vector<std::optional<Eigen::Vector3d>>& known_positions;  // left camera frame (known_points_in_camera)
};

// Per left line, its right line or -1: through the stereo point matches (paper eq. 2; `right_matches`: per left
// keypoint the index of its right keypoint, a match that passed the stereo gates, or -1), then, with
// params.stereo_matching.by_appearance, the remaining lines by the correlation of the image strips along them
// within the depth gates' disparities (features::add_stereo_partners_by_appearance).
std::vector<int> match_stereo_lines(const geometry::StereoCamera& stereo, const AssociatedLines& left,
                                    const AssociatedLines& right, const StereoImages& images,
                                    const std::vector<int>& right_matches, const features::LinePipelineParams& params,
                                    const geometry::TriangulationParams& gates);

// Triangulates each left line: from the two back-projected planes when it has a right partner (`right_partner`,
// from match_stereo_lines), else (or when the planes are degenerate) from two of its keypoints with known positions
// (the two nearest the segment, as the paper prescribes).
StereoLines triangulate_stereo_lines(const geometry::StereoCamera& stereo, const AssociatedLines& left,
                                     const AssociatedLines& right, const LeftKeypoints& keypoints,
                                     const std::vector<int>& right_partner,
                                     const geometry::TriangulationParams& params);

geometry::Segment2d to_segment(const features::LineSegment& line);

}  // namespace vkvo::system
