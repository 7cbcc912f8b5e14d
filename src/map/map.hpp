#pragma once
// The map: keyframes, map points and map lines with stable ids. The Map owns every object (by value, in ordered
// id -> object tables); objects refer to each other only by id, so there are no pointer cycles and erasing an
// object cannot leave a dangling reference (lookups of erased ids return nullptr).
//
// Observations are stored both ways: a keyframe holds the landmark id per feature (kInvalidId when none), a
// landmark holds keyframe id -> feature index. Map functions keep the two sides consistent.
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "geometry/line3d.hpp"

namespace vkvo::map {

using Id = std::uint64_t;
inline constexpr Id kInvalidId = std::numeric_limits<Id>::max();

// A line segment feature: left segment and, when stereo-matched, the right one (rectified pixels).
struct LineFeature {
  geometry::Segment2d left = geometry::Segment2d::Zero();
  std::optional<geometry::Segment2d> right;
};

// Everything measured in one stereo frame, plus its landmark associations. Used for the tracked frame and copied
// into a KeyFrame when the frame becomes one.
struct Frame {
  Id frame_id = kInvalidId;  // sequence index, set by the caller
  double timestamp = 0;
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();  // rectified left camera

  std::vector<Eigen::Vector2d> keypoints;  // left image
  std::vector<double> right_x;             // right-image x of the stereo match, or -1
  std::vector<float> scores;               // detector scores (optional, may be empty)
  cv::Mat descriptors;                     // one row per keypoint (optional)
  std::vector<LineFeature> lines;
  std::vector<std::vector<int>> line_points;  // keypoint indices associated with each line (optional)

  std::vector<Id> point_ids;  // map point per keypoint or kInvalidId; sized like keypoints
  std::vector<Id> line_ids;   // map line per line feature or kInvalidId; sized like lines

  // Sizes point_ids / line_ids (and right_x, when empty) to the feature counts, unassociated.
  void reset_associations();
  bool is_stereo(int keypoint) const { return right_x[keypoint] >= 0; }
};

struct KeyFrame : Frame {
  Id id = kInvalidId;  // keyframe id (0, 1, 2, ... in creation order)
  // The map segment it belongs to. A tracking loss that relocalisation cannot repair starts a new segment, whose
  // poses are anchored at a prediction; segments share one world frame only once merged (Map::merge_segment).
  int segment = 0;
};

struct MapPoint {
  Id id = kInvalidId;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world
  std::map<Id, int> observations;                      // keyframe id -> keypoint index
  Id first_keyframe = kInvalidId;
  bool bad = false;  // flagged for culling (e.g. by bundle adjustment)
};

struct MapLine {
  Id id = kInvalidId;
  geometry::PlueckerLine line;     // world, |v| = 1
  std::map<Id, int> observations;  // keyframe id -> line feature index
  Id first_keyframe = kInvalidId;
  bool bad = false;
  // Extent along the line seen so far (for output / visualisation), set with Map::trim_line.
  std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>> endpoints;
};

// Culling rules and which points are mapped. YAML keys: min_point_observations, min_line_observations,
// culling_grace_keyframes, mono_points, mono_point_min_parallax_deg.
struct MapParams {
  int min_point_observations = 2;  // a landmark seen by fewer keyframes ...
  int min_line_observations = 2;
  int culling_grace_keyframes = 2;  // ... is erased once this many newer keyframes exist after its first one
  // Points without a stereo match also mapped, from the reference keyframe's view (system/mono_points.hpp), when
  // the two rays meet at this angle or more.
  bool mono_points = false;
  double mono_point_min_parallax_deg = 1.0;
};
MapParams load_map_params(const YAML::Node& section);

class Map {
 public:
  // Stores the frame as a new keyframe (id assigned here) and registers the observations of every map point / line
  // id it already carries (ids that no longer exist are cleared).
  KeyFrame& add_keyframe(const Frame& frame);
  Id add_point(const Eigen::Vector3d& position_world);
  Id add_line(const geometry::PlueckerLine& line_world);

  // Associates feature `index` of keyframe `kf` with the landmark (replacing what the feature had) and back.
  void add_point_observation(Id point, Id kf, int index);
  void add_line_observation(Id line, Id kf, int index);
  void erase_point_observation(Id point, Id kf);
  void erase_line_observation(Id line, Id kf);
  void erase_point(Id point);  // and all its observations
  void erase_keyframe(Id kf);  // and its observations (its landmarks stay)

  // Joins segment `from` to segment `into`: every keyframe of `from`, and every landmark they observe, is moved by
  // T_into_from (the world of `from` -> the world of `into`), and the keyframes take segment `into`. Landmarks are
  // assumed to belong to one segment (a segment starts with landmarks of its own).
  void merge_segment(int from, int into, const Eigen::Isometry3d& T_into_from);
  // The same physical landmark mapped twice: every observation of `from` moves to `into` (a keyframe that observes
  // both keeps its observation of `into`), then `from` is erased.
  void fuse_point(Id from, Id into);
  void fuse_line(Id from, Id into);
  // Segments that have keyframes, ascending.
  std::vector<int> segments() const;

  // Erases bad landmarks, landmarks without observations, and those still seen by too few keyframes after the
  // grace period. Returns {points erased, lines erased}.
  std::pair<int, int> cull(const MapParams& params);

  // Keyframes sharing at least `min_shared` landmarks (points + lines) with `kf`, most shared first.
  std::vector<std::pair<Id, int>> covisible_keyframes(Id kf, int min_shared = 1) const;
  // The local window: `kf` followed by the most recent co-visible keyframes, at most `size` in total.
  std::vector<Id> local_window(Id kf, int size, int min_shared = 1) const;

  // Recomputes the stored endpoints of a map line from all its observations.
  void trim_line(Id line, const geometry::PinholeCamera& camera);

  KeyFrame* keyframe(Id id);
  const KeyFrame* keyframe(Id id) const;
  MapPoint* point(Id id);
  const MapPoint* point(Id id) const;
  MapLine* line(Id id);
  const MapLine* line(Id id) const;

  const std::map<Id, KeyFrame>& keyframes() const { return keyframes_; }
  const std::map<Id, MapPoint>& points() const { return points_; }
  const std::map<Id, MapLine>& lines() const { return lines_; }
  Id last_keyframe_id() const { return keyframes_.empty() ? kInvalidId : keyframes_.rbegin()->first; }

 private:
  std::map<Id, KeyFrame> keyframes_;
  std::map<Id, MapPoint> points_;
  std::map<Id, MapLine> lines_;
  Id next_keyframe_id_ = 0, next_point_id_ = 0, next_line_id_ = 0;
};

}  // namespace vkvo::map
