#pragma once
// Relocalisation: finding the camera in the map again, after tracking was lost or from a map segment that had to
// be started after a loss. It does not depend on the predicted pose being right (a dark stretch, a covered lens, a
// kidnap leave the prediction arbitrarily wrong):
//   candidates - keyframes from three sources, interleaved: similar appearance (a global descriptor, the frame's
//                SuperPoint descriptors pooled), closeness to the predicted pose, and recency (the camera is most
//                often near where it lost track);
//   match      - the configured point matcher between the frame and each candidate (at most max_candidates per
//                frame, which bounds the cost);
//   solve      - poses from the frame's matches to the candidate: PnP + RANSAC on the candidate's map points seen
//                in the frame; PnP the other way round where the frame has 3D points of its own (a frame of a
//                young segment, or one that just started a segment from its stereo pair); and the essential matrix
//                of all the matches scaled by the 3D ones. Each pose is scored on all the matches and verified by
//                inlier count and ratio (see RelocalisationParams);
//   refine     - the motion-only optimisation with the candidate's points and lines (lines matched through the
//                points, as in tracking), verified again.
#include <memory>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "backend/params.hpp"
#include "features/lines/line_params.hpp"
#include "features/lines/point_line_association.hpp"
#include "features/point_features.hpp"
#include "geometry/camera.hpp"
#include "map/map.hpp"
#include "system/point_frontend.hpp"

namespace vkvo::system {

// YAML section `relocalisation`.
struct RelocalisationParams {
  bool enabled = true;
  int max_candidates = 3;        // keyframes matched per frame while tracking is lost
  int max_candidates_young = 2;  // ... per tracked frame of a segment that started after a loss
  // A keyframe this close to the predicted pose (both limits) is a candidate by position.
  double max_distance = 3.0;  // m
  double max_angle = 0.8;     // rad
  // Verification of a pose: at least min_inliers of the frame's matches to the keyframe agree with it, and so do
  // min_inlier_ratio of all its matches. A frame with 3D points of its own (a young segment's) counts every kind of
  // match (a 3D point that reprojects, or a match without 3D on its epipolar line) but needs min_point_inliers with
  // a 3D point (they fix the position along the motion); a frame without counts 3D points only.
  int min_inliers = 30;
  double min_inlier_ratio = 0.3;
  int min_point_inliers = 12;
  int pnp_iterations = 300;
};
RelocalisationParams load_relocalisation_params(const YAML::Node& section);

// Where a candidate keyframe came from (a bit set: one keyframe may come from several sources).
enum CandidateSource : unsigned { kByAppearance = 1u, kByPosition = 2u, kByRecency = 4u };

struct RelocalisationCandidate {
  map::Id keyframe = map::kInvalidId;
  unsigned sources = 0;
};

// The frame to localise: its features, its lines with their point association, and where tracking predicts it.
struct RelocalisationQuery {
  const features::PointFeatures* points = nullptr;
  const map::Frame* frame = nullptr;  // keypoints and line segments (left image)
  const features::PointLineAssociation* association = nullptr;
  Eigen::Isometry3d T_world_predicted = Eigen::Isometry3d::Identity();
  int exclude_segment = -1;  // keyframes of this segment are not candidates (-1: none excluded)
  int max_candidates = 3;
  // The frame's own 3D points, per keypoint, in its segment's world (empty or nullopt: none), with the frame's pose
  // there: the reverse direction of the solve.
  std::vector<std::optional<Eigen::Vector3d>> keypoint_positions;
  Eigen::Isometry3d T_world_query = Eigen::Isometry3d::Identity();
};

struct Relocalisation {
  map::Id keyframe = map::kInvalidId;  // the candidate it succeeded with
  unsigned sources = 0;
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();
  std::vector<std::pair<int, map::Id>> points;  // inliers: keypoint of the frame -> map point
  std::vector<std::pair<int, map::Id>> lines;   // inliers: line of the frame -> map line
  std::vector<int> line_partner;                // per line of the frame: its partner line in `keyframe`, or -1
  int inliers = 0;                              // the frame's matches to the keyframe that agree with the pose
  int matches = 0;                              // ... of all its matches to the keyframe
  bool reverse = false;                         // positioned by the frame's own points (too few of the keyframe's)
};

struct RelocalisationStats {
  int attempts = 0;  // frames it ran on
  int candidates_matched = 0;
  int successes = 0;
  int successes_by_source[3] = {0, 0, 0};  // appearance, position, recency (a keyframe may count for several)
  int successes_reverse = 0;               // solved from the frame's own points (see RelocalisationQuery)
};

class Relocaliser {
 public:
  Relocaliser(const RelocalisationParams& params, const backend::OptimizationParams& optimization,
              const features::LineMatchParams& line_matching, bool use_lines);

  // Keeps a keyframe's features (matched against later) and its global descriptor.
  void add_keyframe(map::Id keyframe, std::shared_ptr<const features::PointFeatures> features);
  const features::PointFeatures* features(map::Id keyframe) const;

  // Ranked candidates for the query (at most query.max_candidates), from the map's keyframes.
  std::vector<RelocalisationCandidate> candidates(const RelocalisationQuery& query, const map::Map& map) const;

  // Matches the query against its candidates in turn and returns the first verified pose, or nullopt.
  std::optional<Relocalisation> relocalise(const RelocalisationQuery& query, const map::Map& map,
                                           const geometry::StereoCamera& stereo, PointFrontend& matcher);

  const RelocalisationParams& params() const { return params_; }
  const RelocalisationStats& stats() const { return stats_; }

 private:
  std::optional<Relocalisation> try_candidate(const RelocalisationQuery& query,
                                              const RelocalisationCandidate& candidate, const map::Map& map,
                                              const geometry::StereoCamera& stereo, PointFrontend& matcher) const;

  struct Entry {
    std::shared_ptr<const features::PointFeatures> features;
    Eigen::VectorXf global;  // unit length, or empty when the keyframe had no keypoints
  };

  RelocalisationParams params_;
  backend::OptimizationParams optimization_;
  features::LineMatchParams line_matching_;
  bool use_lines_;
  std::unordered_map<map::Id, Entry> entries_;
  RelocalisationStats stats_;
};

// The point-line association of a frame or keyframe, rebuilt from the points it keeps per line.
features::PointLineAssociation association_of(const map::Frame& frame);

// The global descriptor of an image: its keypoint descriptors averaged with their scores as weights, L2-normalised
// (empty when there are no keypoints). SuperPoint's descriptors are unit vectors, so two views of one scene share
// many nearby descriptors and their means point the same way.
Eigen::VectorXf global_descriptor(const features::PointFeatures& features);

}  // namespace vkvo::system
