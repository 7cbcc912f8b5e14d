#pragma once
// Tracking the map's points when the matches to the reference leave a frame short of them (ORB-SLAM's
// "search by projection"). The matcher pairs a frame with one image, the reference keyframe or the previous frame,
// by descriptors alone; in the dark, descriptors drift so far that few pairs pass its global test, and a frame
// after a lost one has no map points to inherit from its reference. Here the map points of the frame's segment are
// projected at the frame's pose (the points' estimate, or the prediction) and each takes the keypoint near its
// projection whose descriptor is closest to one of its views: the radius leaves a handful of candidates, so a
// looser descriptor test (with a margin to the second closest) stays unambiguous.
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
  // On, for frames whose points alone could not carry a pose: that keeps every frame of a 0.5-2 s stretch at 3 %
  // of the light tracked and KITTI's 1 s on one map. Run on frames with fewer inliers (30), it cost the clean
  // low-texture runs (docs/accuracy.md).
  bool enabled = true;
  // Run when the frame's pose has fewer point inliers than this: optimization.min_pose_inliers, so that only frames
  // that points alone would lose are searched, and frames that track keep exactly the matcher's matches.
  int below_point_inliers = 10;
  // A keypoint within this distance of the projection is a candidate [px] (not tuned).
  double radius_px = 10.0;
  // 1 - cosine similarity of the unit descriptors: twice the NN matcher's 0.245, since position already narrows
  // the choice (ORB-SLAM's projection search likewise accepts twice its BoW matching's Hamming distance).
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

// The frame side of the matching: its pose, its features, and per keypoint whether it is already matched
// (`taken`, indexed like the features; shorter: the rest are free); the map points it already tracks.
struct PointProjectionQuery {
  const Eigen::Isometry3d& T_world_camera;
  const features::PointFeatures& features;
  const std::vector<bool>& taken;
  const std::vector<map::Id>& tracked;
};

// One-to-one matches between the query's free keypoints and the usable map points observed by the keyframes of
// `keyframes` that it does not track yet. A keypoint's distance to a map point is the smallest to the point's views
// in those keyframes; a keypoint claimed by several map points keeps the closest.
std::vector<ProjectedPointMatch> match_points_by_projection(const map::Map& map, const std::vector<map::Id>& keyframes,
                                                            const KeyframeFeatures& keyframe_features,
                                                            const PointProjectionQuery& query,
                                                            const geometry::PinholeCamera& camera,
                                                            const PointProjectionParams& params);

}  // namespace vkvo::system
