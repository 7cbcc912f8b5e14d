#pragma once
// The optimisation stage of the VO (paper Fig. 2, right): point-line association and line matching against the
// reference, initial pose estimation, the keyframe decision, and for new keyframes the right-image features,
// stereo matching, triangulation and local bundle adjustment.
//
// Losing track is expected (a dark stretch, a covered lens); losing the map is not. After a loss every frame is
// first relocalised against the whole map (Relocaliser). Only when that fails does a frame that can carry one start
// a new map segment at the predicted pose, so that tracking goes on; every tracked frame of such a young segment
// then tries to relocalise against the older segments, and the first success merges the young segment into the
// old map (one rigid SE(3) transform: stereo has no scale drift), fuses the landmarks seen in both and runs a local
// bundle adjustment over the seam.
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include <Eigen/Geometry>

#include "backend/pose_estimation.hpp"
#include "features/lines/line_detector.hpp"
#include "features/lines/point_line_association.hpp"
#include "geometry/camera.hpp"
#include "map/map.hpp"
#include "system/frame_input.hpp"
#include "system/frame_observations.hpp"
#include "system/point_frontend.hpp"
#include "system/relocaliser.hpp"
#include "system/stereo_keyframe.hpp"
#include "system/timing.hpp"
#include "system/vo_config.hpp"

namespace vkvo::system {

// How a frame got its pose. (The pipeline adds `bridged` for untracked frames whose pose it interpolated.)
enum class FrameState {
  tracked,      // optimised against the map (or the start of a map segment)
  relocalised,  // found in the map by relocalisation (after a loss, or merging a young segment)
  lost,         // not tracked: the pose is a prediction
};
const char* to_string(FrameState state);

// A young segment joined to an older one: poses of segment `from` map into the world of `into` by T_into_from.
struct SegmentMerge {
  int from = 0, into = 0;
  Eigen::Isometry3d T_into_from = Eigen::Isometry3d::Identity();
};

struct TrackResult {
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();  // rectified left camera
  FrameState state = FrameState::lost;
  bool tracked = false;  // state != lost
  bool keyframe = false;
  bool new_segment = false;  // (re-)initialisation: a new map segment starts here
  int segment = 0;           // the map segment whose world frame the pose is in
  std::optional<SegmentMerge> merge;
  int tracked_points = 0, tracked_lines = 0;
  int matches = 0;                 // point matches to the reference
  bool rematched = false;          // the feature stage's reference was stale: matched again to the last keyframe
  std::string note;                // why a tracked frame made no keyframe, or what relocalisation did (status file)
  FrameObservations observations;  // the roles of the frame's keypoints and lines (without the image)
};

// The keyframe the feature stage matches new frames against.
struct MatchReference {
  map::Id keyframe = map::kInvalidId;
  std::shared_ptr<const features::PointFeatures> features;
};

// The point matches a frame is tracked from: to the reference keyframe, or to the previous frame when the keyframe
// gives fewer than `min_num_match` and the previous frame more.
struct ReferenceMatches {
  features::PointMatches matches;
  map::Id keyframe = map::kInvalidId;  // the keyframe they refer to; invalid when they refer to the previous frame
  bool previous_frame = false;
};
ReferenceMatches match_to_reference(PointFrontend& frontend, const features::PointFeatures& points,
                                    const MatchReference& reference, const features::PointFeatures* previous,
                                    int min_num_match);

class Tracker {
 public:
  // `stereo_frontend` runs the right-image network and the stereo matching of keyframes (and the matching of
  // relocalisation); `stereo` gives the rectified stereo camera; `T_world_first` is the pose the first keyframe gets.
  Tracker(const VoConfig& config, const geometry::StereoCamera& stereo, PointFrontend& stereo_frontend,
          const Eigen::Isometry3d& T_world_first = Eigen::Isometry3d::Identity());

  TrackResult track(const FrameInput& frame, TimingReport& timing);

  // Thread-safe: the feature stage reads it while this stage runs.
  MatchReference reference() const;

  const map::Map& map() const { return map_; }
  int keyframes() const { return static_cast<int>(map_.keyframes().size()); }
  int segments_started() const { return segments_started_; }
  // Segments with keyframes now (after merges).
  int segments() const { return static_cast<int>(map_.segments().size()); }
  int tracking_losses() const { return losses_; }
  int relocalisations() const { return relocalisations_; }
  int merges() const { return merges_; }
  int segments_rebuilt() const { return rebuilds_; }  // thin starts rebuilt (tracking.rebuild_thin_start)
  const RelocalisationStats& relocalisation_stats() const { return relocaliser_.stats(); }

 private:
  struct Tracked {
    map::Frame frame;
    features::PointLineAssociation association;
    // The keyframe the frame's points were matched against and, per line / keypoint of the frame, its partner
    // there (-1: none). Unset when the reference was the previous frame (and line partners when lines are off).
    map::Id reference_keyframe = map::kInvalidId;
    std::vector<int> reference_line_partner, reference_point_partner;
  };
  // Tracking against the reference: the estimate and which map landmark each inlier stands for.
  struct ReferenceTracking {
    bool success = false;
    Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();
    std::vector<std::pair<int, map::Id>> points, lines;  // inliers: feature of the frame -> landmark
    std::vector<int> map_matched;                        // keypoints matched to a map point, inliers or not
    int point_inliers = 0, line_inliers = 0;
    int matches = 0, map_point_matches = 0;
    int projected_points = 0;  // point matches found by projecting the local map (before outlier rejection)
    int projected_lines = 0;   // line matches found by projecting the local map (before outlier rejection)
    bool rematched = false, matched_previous_frame = false, used_pnp = false;
    map::Id reference_keyframe = map::kInvalidId;
  };

  // The point matches of a frame to map points, and per match its keypoint and map point.
  struct PointMatchesOfFrame {
    const std::vector<backend::PointMatch>& matches;
    const std::vector<std::pair<int, map::Id>>& landmarks;
  };

  Tracked make_frame(const FrameInput& input, const Eigen::Isometry3d& pose, TimingReport& timing) const;
  TrackResult initialise(const FrameInput& input, Tracked& current, TimingReport& timing);
  ReferenceTracking track_reference(const FrameInput& input, Tracked& current, TimingReport& timing);
  // The segment's map points near their projections at `estimate` (or at the prediction where it failed), for a
  // frame whose points fall short (map_point_projection.hpp): they join the point matches and the pose is
  // estimated again; kept when it gains support. Returns how many joined (0: nothing changed).
  int add_projected_points(const FrameInput& input, const Tracked& current,
                           std::vector<backend::PointMatch>& point_matches,
                           std::vector<std::pair<int, map::Id>>& point_of_match,
                           const std::vector<backend::LineMatch>& line_matches, backend::PoseEstimate& estimate,
                           TimingReport& timing) const;
  // The local map's lines that the matching through points left out, found by projection at `estimate`
  // (map_line_projection.hpp): they join the line matches, the first estimate's outlier lines leave, and the pose
  // is refined with them. Returns how many were found (0: nothing changed).
  int add_projected_lines(const Tracked& current, const PointMatchesOfFrame& points, map::Id reference_keyframe,
                          std::vector<backend::LineMatch>& line_matches,
                          std::vector<std::pair<int, map::Id>>& line_of_match, backend::PoseEstimate& estimate,
                          TimingReport& timing) const;
  std::optional<Relocalisation> relocalise(const FrameInput& input, const Tracked& current, int exclude_segment,
                                           int max_candidates, TimingReport& timing);
  void apply_relocalisation(const Relocalisation& found, Tracked& current) const;
  // Joins the current (young) segment to the one `found` lies in; returns the merge for the caller's poses.
  SegmentMerge merge_into(const Relocalisation& found, Tracked& current, TimingReport& timing);
  // Right-image features + stereo triangulation, then the keyframe with its new landmarks and a local BA.
  // With `new_segment`, refuses frames with too few keypoints/stereo matches (returns false).
  bool add_keyframe(const FrameInput& input, Tracked& tracked, bool new_segment, TimingReport& timing);
  // Whether a frame has enough to start a map segment from: keypoints and stereo points, and with
  // init_counts_lines its detected lines and `stereo_lines` of them triangulated.
  bool can_start_segment(const FrameInput& input, int stereo_points, int stereo_lines) const;
  // The same with points alone (init_counts_lines aside).
  bool points_can_start_segment(const FrameInput& input, int stereo_points) const;
  // Drops the current segment's landmarks (tracking.rebuild_thin_start): the keyframe being added maps its own.
  void drop_segment_landmarks();
  // Per line of the new keyframe `kf`, its partner in the reference keyframe: the point matches' pairing, plus
  // pairs by appearance (keyframe_line_matching.hpp) for the lines neither those nor `stereo_lines` placed.
  std::vector<int> reference_line_partners(const map::KeyFrame& kf, const cv::Mat& image,
                                           const StereoLines& stereo_lines, const Tracked& tracked) const;
  // The constant-velocity prediction `steps` frame intervals after the last frame.
  Eigen::Isometry3d predicted_pose(double steps = 1.0) const;
  void publish_reference(map::Id keyframe, std::shared_ptr<const features::PointFeatures> features);

  VoConfig config_;
  geometry::StereoCamera stereo_;
  PointFrontend* frontend_;
  features::LineDetector right_line_detector_;
  Eigen::Isometry3d T_world_first_;
  Relocaliser relocaliser_;

  map::Map map_;
  // The left images of the newest keyframes, for pairing a new keyframe's lines with its reference's.
  std::map<map::Id, cv::Mat> keyframe_images_;
  bool initialised_ = false;
  std::optional<Tracked> last_frame_;
  Eigen::Isometry3d T_world_last_ = Eigen::Isometry3d::Identity();
  // The constant-velocity prior: the motion (T_last^-1 T_current) between the last two well-tracked frames. It is
  // kept through untracked frames, so a dark stretch is bridged by extrapolation rather than by standing still.
  std::optional<Eigen::Isometry3d> velocity_;
  int tracked_previous_ = 0;
  int frames_since_keyframe_ = 0;
  int lost_frames_ = 0;  // consecutive untracked frames just before this one
  std::optional<double> last_timestamp_s_;
  double frame_interval_s_ = 0;  // the input's usual time between frames
  int segment_ = 0;              // the segment the current pose is in
  // The current segment was started on lines counted as points and has not been rebuilt or merged since.
  bool segment_started_thin_ = false;
  int segments_started_ = 0, losses_ = 0, relocalisations_ = 0, merges_ = 0, rebuilds_ = 0;

  mutable std::mutex reference_mutex_;
  MatchReference reference_;
};

}  // namespace vkvo::system
