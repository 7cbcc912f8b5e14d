#include "system/tracker.hpp"

#include <cmath>

#include <spdlog/spdlog.h>

#include "backend/keyframe_decision.hpp"
#include "backend/local_ba.hpp"
#include "backend/pose_estimation.hpp"
#include "features/lines/line_matching.hpp"
#include "system/keyframe_lines.hpp"
#include "system/stereo_keyframe.hpp"

namespace vkvo::system {
namespace {

// A keyframe stores only the points of each line; the per-point side is derived.
features::PointLineAssociation association_of(const map::Frame& frame) {
  features::PointLineAssociation a;
  a.points_of_line = frame.line_points;
  a.points_of_line.resize(frame.lines.size());
  a.lines_of_point.resize(frame.keypoints.size());
  for (std::size_t l = 0; l < a.points_of_line.size(); ++l)
    for (int p : a.points_of_line[l]) a.lines_of_point[static_cast<std::size_t>(p)].push_back(static_cast<int>(l));
  return a;
}

bool usable(const map::MapPoint* p) { return p && !p->bad; }
bool usable(const map::MapLine* l) { return l && !l->bad; }

}  // namespace

Tracker::Tracker(const VoConfig& config, const geometry::StereoCamera& stereo, PointFrontend& stereo_frontend,
                 const Eigen::Isometry3d& T_world_first)
    : config_(scale_to_image(config, stereo.camera.width, stereo.camera.height)),
      stereo_(stereo),
      frontend_(&stereo_frontend),
      right_line_detector_(config.lines.detector),
      T_world_first_(T_world_first),
      T_world_last_(T_world_first) {
  if (config_.tracking.init_min_keypoints != config.tracking.init_min_keypoints ||
      config_.tracking.init_min_stereo != config.tracking.init_min_stereo)
    spdlog::info("{}x{} images: a map segment starts with {} keypoints / {} stereo points (configured {} / {} for "
                 "{:.0f} pixels)",
                 stereo.camera.width, stereo.camera.height, config_.tracking.init_min_keypoints,
                 config_.tracking.init_min_stereo, config.tracking.init_min_keypoints, config.tracking.init_min_stereo,
                 config.tracking.reference_image_area);
}

MatchReference Tracker::reference() const {
  std::lock_guard lock(reference_mutex_);
  return reference_;
}

void Tracker::publish_reference(map::Id keyframe, const features::PointFeatures& features) {
  auto shared = std::make_shared<const features::PointFeatures>(features);
  std::lock_guard lock(reference_mutex_);
  reference_ = {keyframe, std::move(shared)};
}

Eigen::Isometry3d Tracker::predicted_pose() const {
  // Constant velocity, carried on through untracked frames: a camera on a car or a drone keeps moving when the
  // image goes black, and standing still there costs a metre a frame on KITTI.
  if (!velocity_) return T_world_last_;
  return T_world_last_ * *velocity_;
}

Tracker::Tracked Tracker::make_frame(const FrameInput& input, const Eigen::Isometry3d& pose, TimingReport& timing) const {
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

TrackResult Tracker::track(const FrameInput& input, TimingReport& timing) {
  TrackResult result;
  Tracked current = make_frame(input, predicted_pose(), timing);

  if (!initialised_) {
    current.frame.T_world_camera = T_world_last_;
    if (add_keyframe(input, current, true, timing)) {
      initialised_ = true;
      ++segments_;
      result.keyframe = result.new_segment = result.tracked = true;
      spdlog::info("frame {}: map initialised with {} points, {} lines", input.index, map_.points().size(),
                   map_.lines().size());
    }
    result.T_world_camera = current.frame.T_world_camera;
    T_world_last_ = result.T_world_camera;
    tracked_previous_ = result.tracked ? config_.keyframe.max_tracked : 0;
    frames_since_keyframe_ = 0;
    last_frame_ = std::move(current);
    return result;
  }

  // The feature stage runs up to queue_capacity frames ahead, so it may have matched against a keyframe that is
  // no longer the last one (or one of an earlier map segment, or the previous frame while a keyframe was being
  // made). The landmarks of such a keyframe are stale: the newer keyframes hold the tracked points and map
  // culling removes the older keyframe's unconfirmed points. Match against the last keyframe here instead.
  const features::PointMatches* matches = &input.matches;
  map::Id reference_keyframe = input.reference_keyframe;
  bool matched_previous_frame = input.matched_previous_frame;
  features::PointMatches rematched;
  if (const MatchReference latest = reference();
      latest.features && latest.keyframe != map::kInvalidId && latest.keyframe != input.reference_keyframe) {
    const Stopwatch watch;
    rematched = frontend_->match(input.points, *latest.features);
    timing.add(Module::PM, watch.ms());
    if (static_cast<int>(rematched.count()) >= config_.tracking.min_num_match ||
        rematched.count() > input.matches.count()) {
      matches = &rematched;
      reference_keyframe = latest.keyframe;
      matched_previous_frame = false;
      result.rematched = true;
    }
  }

  // The reference the matches refer to: the keyframe, or the previous frame.
  const map::Frame* reference = nullptr;
  features::PointLineAssociation keyframe_association;
  const features::PointLineAssociation* reference_association = nullptr;
  if (const map::KeyFrame* kf = reference_keyframe != map::kInvalidId ? map_.keyframe(reference_keyframe) : nullptr) {
    reference = kf;
    current.reference_keyframe = kf->id;
    keyframe_association = association_of(*kf);
    reference_association = &keyframe_association;
  } else if (matched_previous_frame && last_frame_) {
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
      ++result.matches;
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
      const auto line_partner = features::match_lines(current.association, *reference_association, m,
                                                      config_.lines.matching);
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

  const Stopwatch ipe_watch;
  const auto estimate = backend::estimate_pose(stereo_, current.frame.T_world_camera, point_matches, line_matches,
                                               config_.optimization);
  timing.add(Module::IPE, ipe_watch.ms());
  if (estimate.success) {
    current.frame.T_world_camera = estimate.T_world_camera;
    for (std::size_t k = 0; k < point_of_match.size(); ++k)
      if (estimate.point_inliers[k]) current.frame.point_ids[point_of_match[k].first] = point_of_match[k].second;
    for (std::size_t k = 0; k < line_of_match.size(); ++k)
      if (estimate.line_inliers[k]) current.frame.line_ids[line_of_match[k].first] = line_of_match[k].second;
    result.tracked = true;
  }
  result.tracked_points = estimate.num_point_inliers;
  result.tracked_lines = estimate.num_line_inliers;

  const map::KeyFrame* last_keyframe = map_.keyframe(map_.last_keyframe_id());
  const backend::KeyframeDecisionInput decision{
      .T_world_last_keyframe = last_keyframe ? last_keyframe->T_world_camera : T_world_first_,
      .T_world_current = current.frame.T_world_camera,
      .tracked = result.tracked ? result.tracked_points : 0,
      .tracked_previous = tracked_previous_,
      .frames_since_keyframe = frames_since_keyframe_ + 1};
  if (!result.tracked) {
    ++losses_;
    spdlog::warn("frame {}: tracking lost ({} matches, {} map points, {} point / {} line inliers); "
                 "starting map segment {} at the predicted pose",
                 input.index, result.matches, point_matches.size(), estimate.num_point_inliers,
                 estimate.num_line_inliers, segments_ + 1);
    current.frame.reset_associations();
    if (add_keyframe(input, current, true, timing)) {
      ++segments_;
      result.keyframe = result.new_segment = true;
    }
  } else if (backend::need_new_keyframe(config_.keyframe, decision)) {
    result.keyframe = add_keyframe(input, current, false, timing);
  }
  frames_since_keyframe_ = result.keyframe ? 0 : frames_since_keyframe_ + 1;
  spdlog::debug("frame {}: {} keypoints, {} matches to {} {} ({} with map points), {} point / {} line inliers{}{}{}",
                input.index, input.points.size(), result.matches,
                matched_previous_frame ? "previous frame" : result.rematched ? "(re-matched) keyframe" : "keyframe",
                matched_previous_frame ? input.index - 1 : reference_keyframe, point_matches.size(),
                estimate.num_point_inliers, estimate.num_line_inliers, estimate.used_pnp ? ", PnP" : "",
                result.keyframe ? ", keyframe" : "", result.tracked ? "" : ", LOST");

  result.T_world_camera = current.frame.T_world_camera;
  // Only a pair of well-tracked frames gives a velocity; a frame after a loss moves from a predicted pose.
  const int min_tracked = config_.keyframe.min_tracked;
  if (result.tracked && result.tracked_points >= min_tracked && tracked_previous_ >= min_tracked)
    velocity_ = T_world_last_.inverse() * result.T_world_camera;
  T_world_last_ = result.T_world_camera;
  tracked_previous_ = result.tracked ? result.tracked_points : 0;
  last_frame_ = std::move(current);
  return result;
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
  if (new_segment && (static_cast<int>(input.points.size()) < config_.tracking.init_min_keypoints ||
                      stereo_points.count < config_.tracking.init_min_stereo)) {
    spdlog::debug("frame {}: cannot start a map segment ({} keypoints, {} stereo matches, {} pass the stereo gates; "
                  "need {} / {})",
                  input.index, input.points.size(), stereo_matches.count(), stereo_points.count,
                  config_.tracking.init_min_keypoints, config_.tracking.init_min_stereo);
    timing.add(Module::BA, watch.lap());
    return false;
  }
  map::Frame& frame = tracked.frame;
  frame.right_x = stereo_points.right_x;

  StereoLines stereo_lines;
  const double keyframe_ms = watch.lap();  // triangulation; the rest of the keyframe's work is added below
  if (config_.tracking.use_lines && !input.lines.empty()) {
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
    stereo_lines = triangulate_stereo_lines(stereo_, {input.lines, tracked.association},
                                            {right_lines, right_association},
                                            {input.points.keypoints, gated, known_positions},
                                            config_.lines.matching, config_.triangulation);
    for (std::size_t l = 0; l < frame.lines.size(); ++l) frame.lines[l].right = stereo_lines.right[l];
  }

  const map::Id kf_id = map_.add_keyframe(frame).id;
  const Eigen::Isometry3d T = map_.keyframe(kf_id)->T_world_camera;
  int new_points = 0;
  for (std::size_t i = 0; i < stereo_points.positions.size(); ++i) {
    if (!stereo_points.positions[i] || map_.keyframe(kf_id)->point_ids[i] != map::kInvalidId) continue;
    const map::Id id = map_.add_point(T * *stereo_points.positions[i]);
    map_.add_point_observation(id, kf_id, static_cast<int>(i));
    ++new_points;
  }
  const KeyframeLineParams line_params{
      config_.triangulation, config_.optimization.pixel_sigma * std::sqrt(config_.optimization.mono_line_chi2)};
  const NewKeyframeLines new_lines =
      add_keyframe_lines(map_, kf_id, stereo_lines, new_segment ? map::kInvalidId : tracked.reference_keyframe,
                         tracked.reference_line_partner, stereo_.camera, line_params);
  if (!new_segment) {
    const auto ba = backend::local_bundle_adjustment(map_, kf_id, stereo_, config_.optimization);
    const auto [culled_points, culled_lines] = map_.cull(config_.map);
    spdlog::debug("keyframe {} (frame {}): {} stereo matches, {} triangulated; +{} points, +{} lines ({} from two "
                  "keyframes, {} seen by both); BA window {} ({} fixed), outliers {}/{}, culled {}/{}",
                  kf_id, input.index, stereo_matches.count(), stereo_points.count, new_points, new_lines.added,
                  new_lines.two_view, new_lines.seen_twice, ba.window.size(), ba.fixed.size(), ba.point_outliers,
                  ba.line_outliers, culled_points, culled_lines);
  }
  tracked.frame = *map_.keyframe(kf_id);  // BA may have moved it; associations now include the new landmarks
  publish_reference(kf_id, input.points);
  timing.add(Module::BA, keyframe_ms + watch.lap());
  return true;
}

}  // namespace vkvo::system
