#pragma once
// Tracking the lines of the local map (AirVO's and PL-SLAM's "track local map" for lines). Matching through the
// point matches (paper eq. 2) only pairs a frame line with the reference keyframe's lines, and only when both
// carry several matched keypoints: most lines stay unmatched. Once the frame's pose is estimated, the map lines
// of the local window are projected into it, and a frame line without a map line takes the one whose projection
// it lies on (both endpoints within max_distance pixels, the two segments overlapping along the line).
//
// Point support ranks the candidates: the map points that the frame line's associated keypoints track, shared with
// those associated with the map line in the keyframes that observe it. Geometry alone decides only when a single
// map line fits; parallel neighbours without support are left alone.
#include <vector>

#include <yaml-cpp/yaml.h>
#include <Eigen/Geometry>

#include "geometry/camera.hpp"
#include "map/map.hpp"

namespace vkvo::system {

// YAML section lines.projection.
struct LineProjectionParams {
  // Twice the tracked lines: on three low-texture synthetic scenes it cuts the ATE where the points are few, on the
  // shared clips it changes it within their noise (docs/accuracy.md).
  bool enabled = true;
  // Both endpoints of the frame's segment within this distance of the projected map line [px]: the association's
  // point-to-line distance (lines.association.max_distance), i.e. the detector's localisation noise.
  double max_distance = 3.0;
  // The segments' common extent along the line, as a fraction of the shorter one: a collinear segment elsewhere
  // on the same image line (a second door frame edge further along a wall) is another 3D segment.
  double min_overlap = 0.5;
};
LineProjectionParams load_line_projection_params(const YAML::Node& section);

// The frame side of the matching. The vectors are indexed like the frame's lines resp. keypoints.
struct LineProjectionQuery {
  const Eigen::Isometry3d& T_world_camera;
  const std::vector<map::LineFeature>& lines;
  const std::vector<std::vector<int>>& points_of_line;  // keypoints associated with each line
  const std::vector<map::Id>& point_ids;                // map point each keypoint tracks, or kInvalidId
  const std::vector<map::Id>& line_ids;  // map line each line already tracks (such lines are skipped), or kInvalidId
};

struct ProjectedLineMatch {
  int line = -1;  // frame line
  map::Id map_line = map::kInvalidId;
  int support = 0;         // map points shared through the associated keypoints
  double distance_px = 0;  // the farther endpoint's distance to the projected map line
};

// The usable map lines observed by the keyframes of `window`, each once (ascending ids).
std::vector<map::Id> lines_observed_by(const map::Map& map, const std::vector<map::Id>& window);

// One-to-one matches between the query's untracked lines and the `candidates` (map lines already tracked by the
// query are skipped), best supported first. Map lines without stored endpoints need point support.
std::vector<ProjectedLineMatch> match_lines_by_projection(const map::Map& map, const std::vector<map::Id>& candidates,
                                                          const LineProjectionQuery& query,
                                                          const geometry::PinholeCamera& camera,
                                                          const LineProjectionParams& params);

}  // namespace vkvo::system
