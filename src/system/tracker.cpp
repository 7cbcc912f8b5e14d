#include "system/tracker.hpp"

#include <cmath>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "backend/keyframe_decision.hpp"
#include "backend/local_ba.hpp"
#include "backend/pose_estimation.hpp"
#include "features/lines/line_matching.hpp"
#include "system/keyframe_line_matching.hpp"
#include "system/keyframe_lines.hpp"
#include "system/map_line_projection.hpp"
#include "system/map_point_projection.hpp"
#include "system/mono_points.hpp"
#include "system/stereo_keyframe.hpp"

namespace vkvo::system {
namespace {

bool usable(const map::MapPoint* p) { return p && !p->bad; }
bool usable(const map::MapLine* l) { return l && !l->bad; }

std::string describe_sources(unsigned sources) {
  std::string text;
  for (const auto& [bit, name] :
       {std::pair{kByAppearance, "appearance"}, std::pair{kByPosition, "position"}, std::pair{kByRecency, "recency"}})
    if (sources & bit) text += text.empty() ? name : std::string("+") + name;
  return text;
}

// The roles of the frame's features. `tracked_points` / `tracked_lines` are its landmark ids once its pose was
// found, before a keyframe added new ones (empty: none); `map_matched` the keypoints matched to map points.
FrameObservations observations_of(const map::Frame& frame, const std::vector<map::Id>& tracked_points,
                                  const std::vector<map::Id>& tracked_lines, const std::vector<int>& map_matched) {
  const auto has = [](const std::vector<map::Id>& ids, std::size_t i) {
    return i < ids.size() && ids[i] != map::kInvalidId;
  };
  FrameObservations o;
  o.keypoints = frame.keypoints;
  o.roles.assign(frame.keypoints.size(), KeypointRole::unmatched);
  for (const int i : map_matched) o.roles[static_cast<std::size_t>(i)] = KeypointRole::outlier;
  for (std::size_t i = 0; i < o.roles.size(); ++i) {
    if (has(tracked_points, i))
      o.roles[i] = KeypointRole::inlier;
    else if (has(frame.point_ids, i))
      o.roles[i] = KeypointRole::new_point;
  }
  for (std::size_t l = 0; l < frame.lines.size(); ++l) {
    o.lines.push_back(frame.lines[l].left);
    o.line_roles.push_back(has(tracked_lines, l) ? LineRole::matched : LineRole::unmatched);
  }
  o.line_points = frame.line_points;
  return o;
}

}  // namespace

const char* to_string(FrameState state) {
  switch (state) {
    case FrameState::tracked: return "tracked";
    case FrameState::relocalised: return "relocalised";
    case FrameState::lost: return "lost";
  }
  return "?";
}

Tracker::Tracker(const VoConfig& config, const geometry::StereoCamera& stereo, PointFrontend& stereo_frontend,
                 const Eigen::Isometry3d& T_world_first)
    : config_(scale_to_image(config, stereo.camera.width, stereo.camera.height)),
      stereo_(stereo),
      frontend_(&stereo_frontend),
      right_line_detector_(config.lines.detector),
      T_world_first_(T_world_first),
      relocaliser_(config.relocalisation, config.optimization, config.lines.matching, config.tracking.use_lines),
      T_world_last_(T_world_first) {
  if (config_.tracking.init_min_keypoints != config.tracking.init_min_keypoints ||
      config_.tracking.init_min_stereo != config.tracking.init_min_stereo)
    spdlog::info(
        "{}x{} images: a map segment starts with {} keypoints / {} stereo points (configured {} / {} for "
        "{:.0f} pixels)",
        stereo.camera.width, stereo.camera.height, config_.tracking.init_min_keypoints,
        config_.tracking.init_min_stereo, config.tracking.init_min_keypoints, config.tracking.init_min_stereo,
        config.tracking.reference_image_area);
}

ReferenceMatches match_to_reference(PointFrontend& frontend, const features::PointFeatures& points,
                                    const MatchReference& reference, const features::PointFeatures* previous,
                                    int min_num_match) {
  ReferenceMatches out;
  if (reference.features) {
    out.matches = frontend.match(points, *reference.features);
    out.keyframe = reference.keyframe;
  }
  if (previous && static_cast<int>(out.matches.count()) < min_num_match) {
    auto to_previous = frontend.match(points, *previous);
    if (to_previous.count() > out.matches.count()) {
      out.matches = std::move(to_previous);
      out.keyframe = map::kInvalidId;
      out.previous_frame = true;
    }
  }
  return out;
}

MatchReference Tracker::reference() const {
  std::lock_guard lock(reference_mutex_);
  return reference_;
}

void Tracker::publish_reference(map::Id keyframe, std::shared_ptr<const features::PointFeatures> features) {
  std::lock_guard lock(reference_mutex_);
  reference_ = {keyframe, std::move(features)};
}

Eigen::Isometry3d Tracker::predicted_pose(double steps) const {
  // Constant velocity, carried on through untracked frames: a camera on a car or a drone keeps moving when the
  // image goes black, and standing still there costs a metre a frame on KITTI.
  if (!velocity_) return T_world_last_;
  Eigen::AngleAxisd rotation(velocity_->linear());
  rotation.angle() *= steps;
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  motion.linear() = rotation.toRotationMatrix();
  motion.translation() = steps * velocity_->translation();
  return T_world_last_ * motion;
}

Tracker::Tracked Tracker::make_frame(const FrameInput& input, const Eigen::Isometry3d& pose,
                                     TimingReport& timing) const {
  Tracked t;
  map::Frame& f = t.frame;
  f.frame_id = input.index;
  f.timestamp = input.timestamp_s;
  f.T_world_camera = pose;
  f.keypoints.reserve(input.points.size());
  for (const auto& k : input.points.keypoints) f.keypoints.push_back(k.cast<double>());
  f.scores = input.points.scores;
  for (const auto& line : input.lines) f.lines.push_back({to_segment(line), std::nullopt});
  f.reset_associations();
  if (config_.tracking.use_lines && !input.lines.empty()) {
    const Stopwatch watch;
    t.association = features::associate_points_to_lines(input.points.keypoints, input.lines, config_.lines.association);
    f.line_points = t.association.points_of_line;
    timing.add(Module::LM, watch.ms());
  } else {
    t.association = association_of(f);
  }
  return t;
}

TrackResult Tracker::initialise(const FrameInput& input, Tracked& current, TimingReport& timing) {
  TrackResult result;
  current.frame.T_world_camera = T_world_last_;
  if (add_keyframe(input, current, true, timing)) {
    initialised_ = true;
    result.keyframe = result.new_segment = result.tracked = true;
    result.state = FrameState::tracked;
    spdlog::info("frame {}: map initialised with {} points, {} lines", input.index, map_.points().size(),
                 map_.lines().size());
  }
  result.segment = segment_;
  result.T_world_camera = current.frame.T_world_camera;
  result.observations = observations_of(current.frame, {}, {}, {});
  T_world_last_ = result.T_world_camera;
  tracked_previous_ = result.tracked ? config_.keyframe.max_tracked : 0;
  frames_since_keyframe_ = 0;
  last_frame_ = std::move(current);
  return result;
}

Tracker::ReferenceTracking Tracker::track_reference(const FrameInput& input, Tracked& current, TimingReport& timing) {
  ReferenceTracking out;
  // The feature stage runs up to queue_capacity frames ahead, so it may have matched against a keyframe that is
  // no longer the last one. The landmarks of such a keyframe are stale (the newer keyframes hold the tracked points
  // and map culling removes the older keyframe's unconfirmed points), and which keyframe it met depends on thread
  // timing: match against the last keyframe here, with the same fallback, so that every run gives the same poses.
  const features::PointMatches* matches = &input.matches;
  out.reference_keyframe = input.reference_keyframe;
  out.matched_previous_frame = input.matched_previous_frame;
  ReferenceMatches rematched;
  if (const MatchReference latest = reference(); latest.keyframe != input.matched_against) {
    const Stopwatch watch;
    rematched = match_to_reference(*frontend_, input.points, latest, input.previous_points.get(),
                                   config_.tracking.min_num_match);
    timing.add(Module::PM, watch.ms());
    matches = &rematched.matches;
    out.reference_keyframe = rematched.keyframe;
    out.matched_previous_frame = rematched.previous_frame;
    out.rematched = true;
  }

  // The reference the matches refer to: the keyframe, or the previous frame.
  const map::Frame* reference = nullptr;
  features::PointLineAssociation keyframe_association;
  const features::PointLineAssociation* reference_association = nullptr;
  if (const map::KeyFrame* kf =
          out.reference_keyframe != map::kInvalidId ? map_.keyframe(out.reference_keyframe) : nullptr) {
    reference = kf;
    current.reference_keyframe = kf->id;
    current.reference_point_partner = matches->matches0;
    keyframe_association = association_of(*kf);
    reference_association = &keyframe_association;
  } else if (out.matched_previous_frame && last_frame_) {
    reference = &last_frame_->frame;
    reference_association = &last_frame_->association;
  }

  std::vector<backend::PointMatch> point_matches;
  std::vector<std::pair<int, map::Id>> point_of_match;  // current keypoint, map point
  std::vector<backend::LineMatch> line_matches;
  std::vector<std::pair<int, map::Id>> line_of_match;
  if (reference) {
    const auto& m = matches->matches0;
    for (std::size_t i = 0; i < m.size(); ++i) {
      if (m[i] < 0) continue;
      ++out.matches;
      const auto j = static_cast<std::size_t>(m[i]);
      if (j >= reference->point_ids.size()) continue;
      const map::Id id = reference->point_ids[j];
      const map::MapPoint* p = id == map::kInvalidId ? nullptr : map_.point(id);
      if (!usable(p)) continue;
      point_matches.push_back({p->position, {current.frame.keypoints[i], -1.0}});
      point_of_match.emplace_back(static_cast<int>(i), id);
    }
    if (config_.tracking.use_lines && !current.frame.lines.empty() && !reference->lines.empty()) {
      const Stopwatch watch;
      const auto line_partner =
          features::match_lines(current.association, *reference_association, m, config_.lines.matching);
      if (current.reference_keyframe != map::kInvalidId) current.reference_line_partner = line_partner;
      for (std::size_t l = 0; l < line_partner.size(); ++l) {
        if (line_partner[l] < 0) continue;
        const map::Id id = reference->line_ids[static_cast<std::size_t>(line_partner[l])];
        const map::MapLine* line = id == map::kInvalidId ? nullptr : map_.line(id);
        if (!usable(line)) continue;
        line_matches.push_back({line->line, {current.frame.lines[l].left, std::nullopt}});
        line_of_match.emplace_back(static_cast<int>(l), id);
      }
      timing.add(Module::LM, watch.ms());
    }
  }
  out.map_point_matches = static_cast<int>(point_matches.size());

  const Stopwatch ipe_watch;
  auto estimate =
      backend::estimate_pose(stereo_, current.frame.T_world_camera, point_matches, line_matches, config_.optimization);
  timing.add(Module::IPE, ipe_watch.ms());
  if (config_.tracking.point_projection.enabled &&
      estimate.num_point_inliers < config_.tracking.point_projection.below_point_inliers)
    out.projected_points =
        add_projected_points(input, current, point_matches, point_of_match, line_matches, estimate, timing);
  for (const auto& [keypoint, point] : point_of_match) out.map_matched.push_back(keypoint);
  if ((estimate.success || config_.tracking.lines_carry_frames) && config_.tracking.use_lines &&
      config_.line_projection.enabled && !current.frame.lines.empty())
    out.projected_lines = add_projected_lines(current, {point_matches, point_of_match}, out.reference_keyframe,
                                              line_matches, line_of_match, estimate, timing);
  out.success = estimate.success;
  out.used_pnp = estimate.used_pnp;
  out.T_world_camera = estimate.T_world_camera;
  out.point_inliers = estimate.num_point_inliers;
  out.line_inliers = estimate.num_line_inliers;
  for (std::size_t k = 0; k < point_of_match.size(); ++k)
    if (estimate.point_inliers[k]) out.points.push_back(point_of_match[k]);
  for (std::size_t k = 0; k < line_of_match.size(); ++k)
    if (estimate.line_inliers[k]) out.lines.push_back(line_of_match[k]);
  return out;
}

int Tracker::add_projected_points(const FrameInput& input, const Tracked& current,
                                  std::vector<backend::PointMatch>& point_matches,
                                  std::vector<std::pair<int, map::Id>>& point_of_match,
                                  const std::vector<backend::LineMatch>& line_matches, backend::PoseEstimate& estimate,
                                  TimingReport& timing) const {
  const Stopwatch watch;
  std::vector<bool> taken(current.frame.keypoints.size(), false);
  std::vector<map::Id> tracked;
  for (const auto& [keypoint, point] : point_of_match) {
    taken[static_cast<std::size_t>(keypoint)] = true;
    tracked.push_back(point);
  }
  const Eigen::Isometry3d pose = estimate.success ? estimate.T_world_camera : current.frame.T_world_camera;
  // The whole segment's keyframes, not only the co-visible window: after a dark stretch the keyframes that saw the
  // scene in the light are no longer co-visible with the dark ones (a window left KITTI's 1 s at 3 % split).
  std::vector<map::Id> keyframes;
  for (const auto& [id, keyframe] : map_.keyframes())
    if (keyframe.segment == segment_) keyframes.push_back(id);
  const auto projected = match_points_by_projection(
      map_, keyframes, [this](map::Id kf) { return relocaliser_.features(kf); }, {pose, input.points, taken, tracked},
      stereo_.camera, config_.tracking.point_projection);
  timing.add(Module::PM, watch.ms());
  if (projected.empty()) return 0;

  std::vector<backend::PointMatch> points = point_matches;
  std::vector<std::pair<int, map::Id>> landmarks = point_of_match;
  for (const ProjectedPointMatch& m : projected) {
    points.push_back(
        {map_.point(m.map_point)->position, {current.frame.keypoints[static_cast<std::size_t>(m.keypoint)], -1.0}});
    landmarks.emplace_back(m.keypoint, m.map_point);
  }
  const Stopwatch refine_watch;
  auto refined = backend::estimate_pose(stereo_, pose, points, line_matches, config_.optimization);
  timing.add(Module::IPE, refine_watch.ms());
  if (refined.num_point_inliers + refined.num_line_inliers <= estimate.num_point_inliers + estimate.num_line_inliers)
    return 0;
  estimate = std::move(refined);
  point_matches = std::move(points);
  point_of_match = std::move(landmarks);
  return static_cast<int>(projected.size());
}

int Tracker::add_projected_lines(const Tracked& current, const PointMatchesOfFrame& points, map::Id reference_keyframe,
                                 std::vector<backend::LineMatch>& line_matches,
                                 std::vector<std::pair<int, map::Id>>& line_of_match, backend::PoseEstimate& estimate,
                                 TimingReport& timing) const {
  const Stopwatch watch;
  // The frame's associations at the estimate: inlier points, and the inlier lines, which keep their map lines.
  std::vector<map::Id> point_ids(current.frame.keypoints.size(), map::kInvalidId);
  for (std::size_t k = 0; k < points.landmarks.size(); ++k)
    if (estimate.point_inliers[k])
      point_ids[static_cast<std::size_t>(points.landmarks[k].first)] = points.landmarks[k].second;
  std::vector<map::Id> line_ids(current.frame.lines.size(), map::kInvalidId);
  std::vector<backend::LineMatch> lines;
  std::vector<std::pair<int, map::Id>> line_landmarks;
  for (std::size_t k = 0; k < line_of_match.size(); ++k) {
    if (!estimate.line_inliers[k]) continue;
    line_ids[static_cast<std::size_t>(line_of_match[k].first)] = line_of_match[k].second;
    lines.push_back(line_matches[k]);
    line_landmarks.push_back(line_of_match[k]);
  }
  const map::Id anchor = map_.keyframe(reference_keyframe) ? reference_keyframe : map_.last_keyframe_id();
  const auto projected = match_lines_by_projection(
      map_, lines_observed_by(map_, map_.local_window(anchor, config_.optimization.window_size)),
      {estimate.T_world_camera, current.frame.lines, current.association.points_of_line, point_ids, line_ids},
      stereo_.camera, config_.line_projection);
  timing.add(Module::LM, watch.ms());
  if (projected.empty()) return 0;

  for (const ProjectedLineMatch& m : projected) {
    lines.push_back(
        {map_.line(m.map_line)->line, {current.frame.lines[static_cast<std::size_t>(m.line)].left, std::nullopt}});
    line_landmarks.emplace_back(m.line, m.map_line);
  }
  const Stopwatch refine_watch;
  auto refined = backend::estimate_pose(stereo_, estimate.T_world_camera, points.matches, lines, config_.optimization);
  timing.add(Module::IPE, refine_watch.ms());
  if (!refined.success) return 0;
  estimate = std::move(refined);
  line_matches = std::move(lines);
  line_of_match = std::move(line_landmarks);
  return static_cast<int>(projected.size());
}

std::optional<Relocalisation> Tracker::relocalise(const FrameInput& input, const Tracked& current, int exclude_segment,
                                                  int max_candidates, TimingReport& timing) {
  if (!config_.relocalisation.enabled || max_candidates <= 0) return std::nullopt;
  const Stopwatch watch;
  RelocalisationQuery query;
  query.points = &input.points;
  query.frame = &current.frame;
  query.association = &current.association;
  query.T_world_predicted = current.frame.T_world_camera;
  query.exclude_segment = exclude_segment;
  query.max_candidates = max_candidates;
  // The frame's landmarks in its own segment (tracked ones, or a new segment's stereo points) for the reverse solve.
  query.T_world_query = current.frame.T_world_camera;
  query.keypoint_positions.resize(current.frame.point_ids.size());
  for (std::size_t i = 0; i < current.frame.point_ids.size(); ++i)
    if (const map::MapPoint* p = map_.point(current.frame.point_ids[i]); usable(p))
      query.keypoint_positions[i] = p->position;
  auto found = relocaliser_.relocalise(query, map_, stereo_, *frontend_);
  timing.add(Module::RL, watch.ms());
  return found;
}

void Tracker::apply_relocalisation(const Relocalisation& found, Tracked& current) const {
  current.frame.T_world_camera = found.T_world_camera;
  current.frame.reset_associations();
  for (const auto& [keypoint, point] : found.points) current.frame.point_ids[keypoint] = point;
  for (const auto& [line, map_line] : found.lines) current.frame.line_ids[line] = map_line;
  current.reference_keyframe = found.keyframe;
  current.reference_line_partner = found.line_partner;
  current.reference_point_partner.clear();  // relocalisation keeps only the inliers with map points
}

SegmentMerge Tracker::merge_into(const Relocalisation& found, Tracked& current, TimingReport& timing) {
  const Stopwatch watch;
  // The younger segment (the higher id) moves into the older one's world, whichever of the two the frame is in.
  const int found_segment = map_.keyframe(found.keyframe)->segment;
  const Eigen::Isometry3d T_found_current = found.T_world_camera * current.frame.T_world_camera.inverse();
  SegmentMerge merge;
  if (found_segment < segment_) {
    merge = {.from = segment_, .into = found_segment, .T_into_from = T_found_current};
    current.frame.T_world_camera = found.T_world_camera;
  } else {
    merge = {.from = found_segment, .into = segment_, .T_into_from = T_found_current.inverse()};
  }
  map_.merge_segment(merge.from, merge.into, merge.T_into_from);
  segment_ = merge.into;
  segment_started_thin_ = false;  // the segment now holds the older map's landmarks too

  // The frame's own landmarks that relocalisation found in the other segment are one landmark mapped twice: fuse
  // them into the other one.
  int fused_points = 0, fused_lines = 0;
  for (const auto& [keypoint, old_point] : found.points) {
    map::Id& id = current.frame.point_ids[keypoint];
    if (id != map::kInvalidId && id != old_point && map_.point(id)) {
      map_.fuse_point(id, old_point);
      ++fused_points;
    }
    id = old_point;
  }
  for (const auto& [line, old_line] : found.lines) {
    map::Id& id = current.frame.line_ids[line];
    if (id != map::kInvalidId && id != old_line && map_.line(id)) {
      map_.fuse_line(id, old_line);
      ++fused_lines;
    }
    id = old_line;
  }
  // The pose from both sets of correspondences at once.
  std::vector<backend::PointMatch> points;
  std::vector<backend::LineMatch> lines;
  for (std::size_t i = 0; i < current.frame.point_ids.size(); ++i)
    if (const map::MapPoint* p = map_.point(current.frame.point_ids[i]); usable(p))
      points.push_back({p->position, {current.frame.keypoints[i], -1.0}});
  for (std::size_t l = 0; l < current.frame.line_ids.size(); ++l)
    if (const map::MapLine* line = map_.line(current.frame.line_ids[l]); usable(line))
      lines.push_back({line->line, {current.frame.lines[l].left, std::nullopt}});
  const auto joint = backend::estimate_pose(stereo_, current.frame.T_world_camera, points, lines, config_.optimization);
  if (joint.success) current.frame.T_world_camera = joint.T_world_camera;
  current.reference_keyframe = found.keyframe;
  current.reference_line_partner = found.line_partner;
  current.reference_point_partner.clear();  // relocalisation keeps only the inliers with map points
  spdlog::info(
      "frame {}: map segment {} merged into segment {} (keyframe {}, {} point / {} line inliers; moved "
      "{:.3f} m, {:.2f} deg; fused {} points, {} lines)",
      current.frame.frame_id, merge.from, merge.into, found.keyframe, found.points.size(), found.lines.size(),
      merge.T_into_from.translation().norm(), Eigen::AngleAxisd(merge.T_into_from.linear()).angle() * 180.0 / M_PI,
      fused_points, fused_lines);
  timing.add(Module::RL, watch.ms());
  return merge;
}

TrackResult Tracker::track(const FrameInput& input, TimingReport& timing) {
  // Frames since the previous one, in units of the usual frame interval (more than 1 when the input dropped some).
  const double steps = last_timestamp_s_ && frame_interval_s_ > 0
                           ? std::max(1.0, (input.timestamp_s - *last_timestamp_s_) / frame_interval_s_)
                           : 1.0;
  if (last_timestamp_s_ && input.timestamp_s > *last_timestamp_s_) {
    const double dt = input.timestamp_s - *last_timestamp_s_;
    // The usual interval, averaged over the intervals that are not drops of frames.
    if (frame_interval_s_ <= 0)
      frame_interval_s_ = dt;
    else if (dt < 2 * frame_interval_s_)
      frame_interval_s_ = 0.9 * frame_interval_s_ + 0.1 * dt;
  }
  last_timestamp_s_ = input.timestamp_s;
  Tracked current = make_frame(input, predicted_pose(steps), timing);
  if (!initialised_) return initialise(input, current, timing);

  TrackResult result;
  const ReferenceTracking reference = track_reference(input, current, timing);
  result.matches = reference.matches;
  result.rematched = reference.rematched;
  // After a gap (frames lost, or missing from the input: a jump in time) the prior is a dead reckoning and the
  // reference an old keyframe: the frame is relocalised as well, the better supported pose wins, and either has to
  // pass what relocalisation asks of a pose.
  const bool after_gap = lost_frames_ > 0 || steps > 3.0;
  const int reference_inliers = reference.point_inliers + reference.line_inliers;
  const bool relocalising = config_.relocalisation.enabled;
  bool tracked =
      reference.success && (!after_gap || !relocalising || reference_inliers >= config_.relocalisation.min_inliers);
  std::optional<Relocalisation> found;
  if (!tracked || after_gap) found = relocalise(input, current, -1, config_.relocalisation.max_candidates, timing);
  if (found && tracked && found->inliers <= reference_inliers) found.reset();

  bool force_keyframe = false;
  if (found) {
    apply_relocalisation(*found, current);
    const int from = segment_;
    segment_ = map_.keyframe(found->keyframe)->segment;
    tracked = true;
    ++relocalisations_;
    result.state = FrameState::relocalised;
    result.tracked_points = static_cast<int>(found->points.size());
    result.tracked_lines = static_cast<int>(found->lines.size());
    result.note = fmt::format("relocalised at keyframe {} ({})", found->keyframe, describe_sources(found->sources));
    spdlog::info(
        "frame {}: relocalised in segment {}{} at keyframe {} (by {}; {} of {} correspondences inliers, {} "
        "point / {} line inliers in the keyframe's map)",
        input.index, segment_, from != segment_ ? fmt::format(" (lost in segment {})", from) : "", found->keyframe,
        describe_sources(found->sources), found->inliers, found->matches, found->points.size(), found->lines.size());
  } else if (tracked) {
    current.frame.T_world_camera = reference.T_world_camera;
    for (const auto& [keypoint, point] : reference.points) current.frame.point_ids[keypoint] = point;
    for (const auto& [line, map_line] : reference.lines) current.frame.line_ids[line] = map_line;
    result.state = FrameState::tracked;
    result.tracked_points = reference.point_inliers;
    result.tracked_lines = reference.line_inliers;
  }
  if (result.state == FrameState::tracked && map_.segments().size() > 1) {
    // A tracked frame of a segment that has others beside it: look for the other map.
    if (auto other = relocalise(input, current, segment_, config_.relocalisation.max_candidates_young, timing)) {
      const Relocalisation& found = *other;
      result.merge = merge_into(found, current, timing);
      ++relocalisations_;
      ++merges_;
      force_keyframe = true;
      result.state = FrameState::relocalised;
      result.note = fmt::format("merged segment {} into {} at keyframe {} ({}{})", result.merge->from,
                                result.merge->into, found.keyframe, describe_sources(found.sources),
                                found.reverse ? ", from the frame's own points" : "");
    }
  }

  // The frame's landmarks as tracking found them; a keyframe adds its new ones below.
  const std::vector<map::Id> tracked_points = current.frame.point_ids, tracked_lines = current.frame.line_ids;
  const map::KeyFrame* last_keyframe = map_.keyframe(map_.last_keyframe_id());
  const backend::KeyframeDecisionInput decision{
      .T_world_last_keyframe = last_keyframe ? last_keyframe->T_world_camera : T_world_first_,
      .T_world_current = current.frame.T_world_camera,
      .tracked = tracked ? result.tracked_points : 0,
      .tracked_lines = tracked && config_.tracking.lines_carry_frames ? result.tracked_lines : 0,
      .tracked_previous = tracked_previous_,
      .frames_since_keyframe = frames_since_keyframe_ + 1};
  if (!tracked) {
    ++losses_;
    spdlog::warn(
        "frame {}: tracking lost ({} matches, {} map points, {} point / {} line inliers{}); no "
        "relocalisation; starting map segment {} at the predicted pose if the frame can carry one",
        input.index, result.matches, reference.map_point_matches, reference.point_inliers, reference.line_inliers,
        reference.success ? fmt::format(", below the {} asked after a loss", config_.relocalisation.min_inliers) : "",
        segments_started_);
    current.frame.reset_associations();
    const int previous_segment = segment_;
    segment_ = segments_started_;
    if (add_keyframe(input, current, true, timing)) {
      // The frame anchors the new segment: its pose is a prediction, but the segment's poses are exact relative to
      // it, and a merge later moves it with them. Its own stereo points may find the old map at once.
      result.keyframe = result.new_segment = tracked = true;
      result.state = FrameState::tracked;
      result.note = fmt::format("new map segment {}", segment_);
      if (auto other = relocalise(input, current, segment_, config_.relocalisation.max_candidates_young, timing)) {
        result.merge = merge_into(*other, current, timing);
        ++relocalisations_;
        ++merges_;
        result.state = FrameState::relocalised;
        result.note = fmt::format("new map segment {} merged into {} at keyframe {} ({}{})", result.merge->from,
                                  result.merge->into, other->keyframe, describe_sources(other->sources),
                                  other->reverse ? ", from its own stereo points" : "");
        const map::Id kf = map_.last_keyframe_id();
        map_.keyframe(kf)->T_world_camera = current.frame.T_world_camera;
        backend::local_bundle_adjustment(map_, kf, stereo_, config_.optimization);
        map_.cull(config_.map);
        current.frame.T_world_camera = map_.keyframe(kf)->T_world_camera;
      }
    } else {
      segment_ = previous_segment;
      result.note = "no keyframe: too few keypoints or stereo points for a map segment";
    }
  } else {
    const backend::KeyframeReason reason = backend::keyframe_reason(config_.keyframe, decision);
    if (force_keyframe || backend::need_new_keyframe(config_.keyframe, decision)) {
      const int rebuilds_before = rebuilds_;
      result.keyframe = add_keyframe(input, current, false, timing);
      if (rebuilds_ != rebuilds_before) result.note = fmt::format("map segment {} rebuilt from here", segment_);
    } else if (reason == backend::KeyframeReason::tracking_failed && result.note.empty())
      result.note = fmt::format("no keyframe: {} tracked points, fewer than {}", result.tracked_points,
                                config_.keyframe.min_tracked);
  }
  frames_since_keyframe_ = result.keyframe ? 0 : frames_since_keyframe_ + 1;
  spdlog::debug(
      "frame {}: {} keypoints, {} matches to {} {} ({} with map points), {} point / {} line inliers ({} points / "
      "{} lines by projection){}{}{}{}",
      input.index, input.points.size(), result.matches,
      reference.matched_previous_frame ? "previous frame"
      : reference.rematched            ? "(re-matched) keyframe"
                                       : "keyframe",
      reference.matched_previous_frame ? input.index - 1 : reference.reference_keyframe, reference.map_point_matches,
      result.tracked_points, result.tracked_lines, reference.projected_points, reference.projected_lines,
      reference.used_pnp ? ", PnP" : "", result.keyframe ? ", keyframe" : "",
      result.state == FrameState::relocalised ? ", RELOCALISED" : "", tracked ? "" : ", LOST");

  result.T_world_camera = current.frame.T_world_camera;
  result.segment = segment_;
  result.observations = observations_of(current.frame, tracked_points, tracked_lines, reference.map_matched);
  // Only a pair of well-tracked frames gives a velocity; a frame after a loss moves from a predicted pose, and a
  // merge moves the world under the previous pose.
  const int min_tracked = config_.keyframe.min_tracked;
  if (result.state == FrameState::tracked && result.tracked_points >= min_tracked && tracked_previous_ >= min_tracked)
    velocity_ = T_world_last_.inverse() * result.T_world_camera;
  result.tracked = tracked;
  T_world_last_ = result.T_world_camera;
  tracked_previous_ = result.new_segment ? config_.keyframe.max_tracked : tracked ? result.tracked_points : 0;
  lost_frames_ = tracked ? 0 : lost_frames_ + 1;
  last_frame_ = std::move(current);
  return result;
}

bool Tracker::can_start_segment(const FrameInput& input, int stereo_points, int stereo_lines) const {
  const bool count_lines = config_.tracking.init_counts_lines && config_.tracking.use_lines;
  const int lines = count_lines ? static_cast<int>(input.lines.size()) : 0;
  const int keypoints = static_cast<int>(input.points.size());
  const int stereo = stereo_points + (lines > 0 ? stereo_lines : 0);
  if (keypoints + lines >= config_.tracking.init_min_keypoints && stereo >= config_.tracking.init_min_stereo)
    return true;
  spdlog::debug(
      "frame {}: cannot start a map segment ({} keypoints, {} stereo points, {} lines, {} stereo lines; "
      "need {} / {})",
      input.index, keypoints, stereo_points, lines, lines > 0 ? stereo_lines : 0, config_.tracking.init_min_keypoints,
      config_.tracking.init_min_stereo);
  return false;
}

bool Tracker::points_can_start_segment(const FrameInput& input, int stereo_points) const {
  return static_cast<int>(input.points.size()) >= config_.tracking.init_min_keypoints &&
         stereo_points >= config_.tracking.init_min_stereo;
}

void Tracker::drop_segment_landmarks() {
  for (const auto& [id, kf] : map_.keyframes()) {
    if (kf.segment != segment_) continue;
    for (const map::Id p : kf.point_ids)
      if (map::MapPoint* point = map_.point(p)) point->bad = true;
    for (const map::Id l : kf.line_ids)
      if (map::MapLine* line = map_.line(l)) line->bad = true;
  }
  map_.cull(config_.map);
}

bool Tracker::add_keyframe(const FrameInput& input, Tracked& tracked, bool new_segment, TimingReport& timing) {
  // The right image's detection, stereo matching and right-image lines are timed under PE, PM and LE, so BA is
  // the keyframe's own work (triangulation, map update, local BA) as in the paper's table.
  Stopwatch watch;
  const features::PointFeatures right = frontend_->detect(input.right);
  timing.add(Module::PE, watch.lap());
  const features::PointMatches stereo_matches = frontend_->match(input.points, right);
  timing.add(Module::PM, watch.lap());
  const StereoPoints stereo_points =
      triangulate_stereo_points(stereo_, input.points, right, stereo_matches, config_.triangulation);
  const bool use_lines = config_.tracking.use_lines && !input.lines.empty();
  // Before the lines' triangulation, every detected line counts as a possible stereo line.
  if (new_segment && !can_start_segment(input, stereo_points.count, static_cast<int>(input.lines.size()))) {
    timing.add(Module::BA, watch.lap());
    return false;
  }
  map::Frame& frame = tracked.frame;
  // A segment started thin (on lines counted as points) is rebuilt from the first keyframe whose points alone could
  // start it: the landmarks mapped from the thin start are dropped and this keyframe maps its own, as a start would.
  const bool rebuild = !new_segment && segment_started_thin_ && config_.tracking.rebuild_thin_start &&
                       points_can_start_segment(input, stereo_points.count);
  if (rebuild) {
    drop_segment_landmarks();
    frame.reset_associations();
    segment_started_thin_ = false;
    ++rebuilds_;
    spdlog::info("frame {}: map segment {} rebuilt from this frame's {} stereo points (it started on lines)",
                 input.index, segment_, stereo_points.count);
  }
  const bool fresh = new_segment || rebuild;  // the keyframe maps from its own stereo pair alone

  StereoLines stereo_lines;
  const double keyframe_ms = watch.lap();  // triangulation; the rest of the keyframe's work is added below
  if (use_lines) {
    const auto right_lines = right_line_detector_.detect(input.right);
    timing.add(Module::LE, watch.lap());
    const auto right_association =
        features::associate_points_to_lines(right.keypoints, right_lines, config_.lines.association);
    std::vector<int> gated(stereo_matches.matches0.size(), -1);  // only matches that passed the stereo gates
    for (std::size_t i = 0; i < gated.size(); ++i)
      if (stereo_points.positions[i]) gated[i] = stereo_matches.matches0[i];
    // The two-point fallback may use tracked map points as well as this keyframe's stereo points.
    std::vector<std::optional<Eigen::Vector3d>> tracked_world(frame.point_ids.size());
    for (std::size_t i = 0; i < tracked_world.size(); ++i)
      if (const map::MapPoint* p = map_.point(frame.point_ids[i]); usable(p)) tracked_world[i] = p->position;
    const auto known_positions = known_points_in_camera(stereo_points, tracked_world, frame.T_world_camera);
    const AssociatedLines left_side{input.lines, tracked.association}, right_side{right_lines, right_association};
    const std::vector<int> partner = match_stereo_lines(stereo_, left_side, right_side, {input.left, input.right},
                                                        gated, config_.lines, config_.triangulation);
    stereo_lines = triangulate_stereo_lines(stereo_, left_side, right_side, {input.points.keypoints, known_positions},
                                            partner, config_.triangulation);
  }
  if (new_segment && config_.tracking.init_counts_lines &&
      !can_start_segment(input, stereo_points.count, stereo_lines.planes + stereo_lines.points)) {
    timing.add(Module::BA, keyframe_ms + watch.lap());  // both triangulations (the lines' detection is LE)
    return false;
  }
  frame.right_x = stereo_points.right_x;
  for (std::size_t l = 0; l < stereo_lines.right.size() && l < frame.lines.size(); ++l)
    frame.lines[l].right = stereo_lines.right[l];

  map::KeyFrame& added = map_.add_keyframe(frame);
  added.segment = segment_;
  const map::Id kf_id = added.id;
  if (new_segment) {
    ++segments_started_;
    segment_started_thin_ = !points_can_start_segment(input, stereo_points.count);
  }
  const Eigen::Isometry3d T = map_.keyframe(kf_id)->T_world_camera;
  int new_points = 0;
  for (std::size_t i = 0; i < stereo_points.positions.size(); ++i) {
    if (!stereo_points.positions[i] || map_.keyframe(kf_id)->point_ids[i] != map::kInvalidId) continue;
    const map::Id id = map_.add_point(T * *stereo_points.positions[i]);
    map_.add_point_observation(id, kf_id, static_cast<int>(i));
    ++new_points;
  }
  NewMonoPoints mono;
  if (config_.map.mono_points && !fresh) {
    const MonoPointParams mono_params{config_.map.mono_point_min_parallax_deg,
                                      config_.optimization.pixel_sigma * std::sqrt(5.991),
                                      config_.triangulation.min_depth};
    mono = add_mono_points(map_, kf_id, tracked.reference_keyframe, tracked.reference_point_partner, stereo_.camera,
                           mono_params);
  }
  const KeyframeLineParams line_params{
      config_.triangulation, config_.optimization.pixel_sigma * std::sqrt(config_.optimization.mono_line_chi2)};
  const std::vector<int> reference_partner =
      fresh ? std::vector<int>{} : reference_line_partners(*map_.keyframe(kf_id), input.left, stereo_lines, tracked);
  const NewKeyframeLines new_lines =
      add_keyframe_lines(map_, kf_id, stereo_lines, fresh ? map::kInvalidId : tracked.reference_keyframe,
                         reference_partner, stereo_.camera, line_params);
  if (!fresh) {
    const auto ba = backend::local_bundle_adjustment(map_, kf_id, stereo_, config_.optimization);
    const auto [culled_points, culled_lines] = map_.cull(config_.map);
    spdlog::debug(
        "keyframe {} (frame {}): {} stereo matches, {} triangulated; +{} points, +{} mono points (of {}), +{} "
        "lines ({} from two keyframes, {} seen by both); BA window {} ({} fixed), outliers {}/{}, culled {}/{}",
        kf_id, input.index, stereo_matches.count(), stereo_points.count, new_points, mono.added, mono.candidates,
        new_lines.added, new_lines.two_view, new_lines.seen_twice, ba.window.size(), ba.fixed.size(), ba.point_outliers,
        ba.line_outliers, culled_points, culled_lines);
  }
  // The extents of the lines it sees grow with each view (and move with BA): the map's outputs draw them and
  // projection matching checks overlap against them.
  for (const map::Id id : map_.keyframe(kf_id)->line_ids)
    if (map_.line(id)) map_.trim_line(id, stereo_.camera);
  tracked.frame = *map_.keyframe(kf_id);  // BA may have moved it; associations now include the new landmarks
  if (use_lines && config_.lines.keyframe_matching.by_appearance) {
    // A frame's reference is the newest keyframe, but after a relocalisation the one it was found at: an older
    // reference than these gets no line pairing.
    constexpr std::size_t kKeptImages = 4;
    keyframe_images_[kf_id] = input.left.clone();
    while (keyframe_images_.size() > kKeptImages) keyframe_images_.erase(keyframe_images_.begin());
  }
  auto features = std::make_shared<const features::PointFeatures>(input.points);
  relocaliser_.add_keyframe(kf_id, features);
  publish_reference(kf_id, std::move(features));
  timing.add(Module::BA, keyframe_ms + watch.lap());
  return true;
}

std::vector<int> Tracker::reference_line_partners(const map::KeyFrame& kf, const cv::Mat& image,
                                                  const StereoLines& stereo_lines, const Tracked& tracked) const {
  std::vector<int> partner = tracked.reference_line_partner;
  partner.resize(kf.lines.size(), -1);
  const map::KeyFrame* reference = map_.keyframe(tracked.reference_keyframe);
  const auto reference_image = keyframe_images_.find(tracked.reference_keyframe);
  if (!reference || reference->id == kf.id || reference_image == keyframe_images_.end() ||
      !config_.lines.keyframe_matching.by_appearance)
    return partner;
  const auto segments_of = [](const map::KeyFrame& k) {
    std::vector<geometry::Segment2d> segments;
    for (const auto& line : k.lines) segments.push_back(line.left);
    return segments;
  };
  // Open: lines without a map line, and here also without a stereo triangulation.
  std::vector<bool> open_here(kf.lines.size()), open_reference(reference->lines.size());
  for (std::size_t l = 0; l < open_here.size(); ++l)
    open_here[l] = kf.line_ids[l] == map::kInvalidId && !(l < stereo_lines.lines.size() && stereo_lines.lines[l]);
  for (std::size_t r = 0; r < open_reference.size(); ++r) open_reference[r] = reference->line_ids[r] == map::kInvalidId;
  const auto here_segments = segments_of(kf), reference_segments = segments_of(*reference);
  add_keyframe_partners_by_appearance(
      stereo_.camera, {image, here_segments, open_here, kf.T_world_camera},
      {reference_image->second, reference_segments, open_reference, reference->T_world_camera}, config_.triangulation,
      config_.lines.keyframe_matching, partner);
  return partner;
}

}  // namespace vkvo::system
