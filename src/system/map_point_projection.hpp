#pragma once
// Tracking the points of the local map when the matches to the reference leave a frame short of them (ORB-SLAM's
// "search by projection"). The matcher pairs a frame with one image, the reference keyframe or the previous frame,
// by descriptors alone; in the dark, descriptors drift so far that few pairs pass its global test, and a frame
// after a lost one has no map points to inherit from its reference. Here the local window's map points are
// projected at the frame's pose (the points' estimate, or the prediction) and each takes the keypoint near its
// projection whose descriptor is closest to one of its views: the window leaves a handful of candidates, so a looser descriptor test
// (with a margin to the second closest) stays unambiguous.
#include <functional>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <Eigen/Geometry>

#include "features/point_features.hpp"
#include "geometry/camera.hpp"
#include "map/map.hpp"

namespace vkvo::system {

// YAML section tracking.point_projection.
struct PointProjectionParams {
  // Off by default: it tracks every frame of a 0.5-1 s stretch at 3 % of the light on both clips (10 untracked
  // before), but those poses and the dark keyframes' landmarks measured no better than bridging the stretch, and
  // cost 0-5 % on low-texture runs (docs/accuracy.md).
  bool enabled = false;
  // Run when the frame's pose has fewer point inliers than this: relocalisation.min_inliers, the support a pose
  // needs after a loss, so that frames that track well keep exactly the matcher's matches.
  int below_point_inliers = 30;
  // A keypoint within this distance of the projection is a candidate [px]: the constant-velocity prediction's
  // error over one frame (EuRoC 1-4 px, KITTI 2-6 px on the clean clips).
  double radius_px = 10.0;
  // 1 - cosine similarity of the unit descriptors: twice the NN matcher's 0.245, since position already narrows
  // the choice (ORB-SLAM loosens its projection threshold by the same factor).
  double max_cosine_distance = 0.5;
  // The closest candidate's distance at most this fraction of the second closest's.
  double max_ratio = 0.9;
};
PointProjectionParams load_point_projection_params(const YAML::Node& section);

struct ProjectedPointMatch {
  int keypoint = -1;
  map::Id map_point = map::kInvalidId;
  float descriptor_distance = 0;  // 1 - cosine similarity
};

// The keyframe's SuperPoint features (descriptors per keypoint index), or nullptr where none are kept.
using KeyframeFeatures = std::function<const features::PointFeatures*(map::Id)>;

// One-to-one matches between the frame's keypoints not in `taken` and the usable map points observed by the
// keyframes of `window` that the frame does not track yet (`tracked`). A keypoint's distance to a map point is the
// smallest to the point's views in the window; a keypoint claimed by several map points keeps the closest.
std::vector<ProjectedPointMatch> match_points_by_projection(const map::Map& map, const std::vector<map::Id>& window,
                                                            const KeyframeFeatures& keyframe_features,
                                                            const features::PointFeatures& frame,
                                                            const Eigen::Isometry3d& T_world_camera,
                                                            const std::vector<bool>& taken,
                                                            const std::vector<map::Id>& tracked,
                                                            const geometry::PinholeCamera& camera,
                                                            const PointProjectionParams& params);

}  // namespace vkvo::system
