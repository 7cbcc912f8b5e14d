#include "system/relocaliser.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <spdlog/spdlog.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "backend/pose_estimation.hpp"
#include "features/lines/line_matching.hpp"
#include "io/config.hpp"

namespace vkvo::system {
namespace {

bool usable(const map::MapPoint* p) { return p && !p->bad; }
bool usable(const map::MapLine* l) { return l && !l->bad; }

double rotation_angle(const Eigen::Matrix3d& R) { return Eigen::AngleAxisd(R).angle(); }

}  // namespace

RelocalisationParams load_relocalisation_params(const YAML::Node& section) {
  RelocalisationParams p;
  io::read_param(section, "enabled", p.enabled);
  io::read_param(section, "max_candidates", p.max_candidates);
  io::read_param(section, "max_candidates_young", p.max_candidates_young);
  io::read_param(section, "max_distance", p.max_distance);
  io::read_param(section, "max_angle", p.max_angle);
  io::read_param(section, "min_inliers", p.min_inliers);
  io::read_param(section, "min_point_inliers", p.min_point_inliers);
  io::read_param(section, "min_inlier_ratio", p.min_inlier_ratio);
  io::read_param(section, "pnp_iterations", p.pnp_iterations);
  if (p.max_candidates < 1 || p.max_candidates_young < 0)
    throw std::runtime_error("relocalisation.max_candidates must be at least 1 and max_candidates_young at least 0");
  if (!(p.max_distance >= 0) || !(p.max_angle >= 0))
    throw std::runtime_error("relocalisation.max_distance and max_angle must be non-negative numbers");
  if (p.min_inliers < 6) throw std::runtime_error("relocalisation.min_inliers must be at least 6");
  if (p.min_point_inliers < 3 || p.min_point_inliers > p.min_inliers)
    throw std::runtime_error("relocalisation.min_point_inliers must lie in [3, min_inliers]");
  if (!(p.min_inlier_ratio >= 0 && p.min_inlier_ratio <= 1))
    throw std::runtime_error("relocalisation.min_inlier_ratio must lie in [0, 1]");
  if (p.pnp_iterations < 1) throw std::runtime_error("relocalisation.pnp_iterations must be at least 1");
  return p;
}

features::PointLineAssociation association_of(const map::Frame& frame) {
  // A keyframe stores only the points of each line; the per-point side is derived.
  features::PointLineAssociation a;
  a.points_of_line = frame.line_points;
  a.points_of_line.resize(frame.lines.size());
  a.lines_of_point.resize(frame.keypoints.size());
  for (std::size_t l = 0; l < a.points_of_line.size(); ++l)
    for (int p : a.points_of_line[l]) a.lines_of_point[static_cast<std::size_t>(p)].push_back(static_cast<int>(l));
  return a;
}

Eigen::VectorXf global_descriptor(const features::PointFeatures& features) {
  if (features.size() == 0 || features.descriptors.rows() == 0) return {};
  Eigen::VectorXf sum = Eigen::VectorXf::Zero(features.descriptors.cols());
  for (Eigen::Index i = 0; i < features.descriptors.rows(); ++i) {
    const float weight = static_cast<std::size_t>(i) < features.scores.size() ? features.scores[i] : 1.0f;
    sum += weight * features.descriptors.row(i).transpose();
  }
  const float norm = sum.norm();
  if (!(norm > 0)) return {};
  return sum / norm;
}

Relocaliser::Relocaliser(const RelocalisationParams& params, const backend::OptimizationParams& optimization,
                         const features::LineMatchParams& line_matching, bool use_lines)
    : params_(params), optimization_(optimization), line_matching_(line_matching), use_lines_(use_lines) {}

void Relocaliser::add_keyframe(map::Id keyframe, std::shared_ptr<const features::PointFeatures> features) {
  Eigen::VectorXf global = global_descriptor(*features);
  entries_[keyframe] = {std::move(features), std::move(global)};
}

const features::PointFeatures* Relocaliser::features(map::Id keyframe) const {
  const auto it = entries_.find(keyframe);
  return it == entries_.end() ? nullptr : it->second.features.get();
}

std::vector<RelocalisationCandidate> Relocaliser::candidates(const RelocalisationQuery& query,
                                                             const map::Map& map) const {
  struct Scored {
    map::Id id;
    double score;  // higher first
  };
  std::vector<Scored> by_appearance, by_position, by_recency;
  const Eigen::VectorXf query_global = global_descriptor(*query.points);
  for (const auto& [id, kf] : map.keyframes()) {
    if (kf.segment == query.exclude_segment || !entries_.count(id)) continue;
    const Entry& entry = entries_.at(id);
    if (query_global.size() > 0 && entry.global.size() == query_global.size())
      by_appearance.push_back({id, static_cast<double>(query_global.dot(entry.global))});
    const Eigen::Isometry3d delta = query.T_world_predicted.inverse() * kf.T_world_camera;
    const double distance = delta.translation().norm(), angle = rotation_angle(delta.linear());
    if (distance <= params_.max_distance && angle <= params_.max_angle)
      by_position.push_back(
          {id, -(distance / std::max(params_.max_distance, 1e-9) + angle / std::max(params_.max_angle, 1e-9))});
    by_recency.push_back({id, static_cast<double>(id)});
  }
  const auto rank = [](std::vector<Scored>& list) {
    std::stable_sort(list.begin(), list.end(), [](const Scored& a, const Scored& b) { return a.score > b.score; });
  };
  rank(by_appearance);
  rank(by_position);
  rank(by_recency);

  // Interleaved, appearance first: each source gets a turn, so no single wrong guess (a prediction far off after a
  // kidnap, a look-alike place) can take the whole budget.
  std::vector<RelocalisationCandidate> out;
  const std::vector<std::pair<const std::vector<Scored>*, CandidateSource>> sources = {
      {&by_appearance, kByAppearance}, {&by_position, kByPosition}, {&by_recency, kByRecency}};
  std::vector<std::size_t> next(sources.size(), 0);
  const auto limit = static_cast<std::size_t>(std::max(0, query.max_candidates));
  for (bool progress = true; progress && out.size() < limit;) {
    progress = false;
    for (std::size_t s = 0; s < sources.size() && out.size() < limit; ++s) {
      const auto& list = *sources[s].first;
      while (next[s] < list.size()) {
        const map::Id id = list[next[s]++].id;
        const auto seen = std::find_if(out.begin(), out.end(), [&](const auto& c) { return c.keyframe == id; });
        if (seen != out.end()) {
          seen->sources |= sources[s].second;
          continue;
        }
        out.push_back({id, sources[s].second});
        progress = true;
        break;
      }
    }
  }
  // A candidate that another source ranks within the budget too counts for both (for the statistics).
  for (auto& c : out)
    for (std::size_t s = 0; s < sources.size(); ++s) {
      const auto& list = *sources[s].first;
      for (std::size_t i = 0; i < std::min(list.size(), limit); ++i)
        if (list[i].id == c.keyframe) c.sources |= sources[s].second;
    }
  return out;
}

namespace {

// The frame's matches to one keyframe, by what is known of them in 3D, and the poses of the frame (in the
// keyframe's world) that they propose and support. Three kinds of correspondence:
//   forward - the keyframe's map points seen in the frame (PnP gives the frame's pose);
//   reverse - the frame's own points (its segment's landmarks) seen in the keyframe (PnP gives the keyframe's pose
//             in the frame's world, hence the frame's in the keyframe's);
//   plain   - neither side has the point in 3D: an epipolar constraint. Their essential matrix gives the rotation
//             and the direction of motion between the two views, and the 3D correspondences give its length.
// A camera that moved on through the dark (a car) shares mostly far structure with the old keyframe, which the two
// maps hold in different parts or not at all (beyond the stereo depth gate); together the three find the link
// where any one alone does not.
class CandidateEvidence {
 public:
  struct Support {
    int forward = 0, reverse = 0, plain = 0;
    int points() const { return forward + reverse; }  // inliers with a 3D point: they fix the position
    int total() const { return forward + reverse + plain; }
  };

  CandidateEvidence(const RelocalisationQuery& query, const map::KeyFrame& kf, const features::PointMatches& matches,
                    const map::Map& map, const geometry::PinholeCamera& camera, const backend::OptimizationParams& opt)
      : kf_(&kf),
        camera_(camera),
        reprojection_px_(opt.pixel_sigma * std::sqrt(opt.mono_point_chi2)),
        epipolar_px_(2.0 * opt.pixel_sigma),
        T_query_frame_world_(query.T_world_query.inverse()) {
    for (std::size_t i = 0; i < matches.matches0.size() && i < query.frame->keypoints.size(); ++i) {
      const int j = matches.matches0[i];
      if (j < 0 || static_cast<std::size_t>(j) >= kf.point_ids.size()) continue;
      const Eigen::Vector2d& kf_pixel = kf.keypoints[static_cast<std::size_t>(j)];
      const Eigen::Vector2d& frame_pixel = query.frame->keypoints[i];
      bool in_3d = false;
      if (i < query.keypoint_positions.size() && query.keypoint_positions[i]) {
        reverse.push_back({*query.keypoint_positions[i], {kf_pixel, -1.0}});
        reverse_in_frame.push_back(T_query_frame_world_ * *query.keypoint_positions[i]);
        in_3d = true;
      }
      const map::Id id = kf.point_ids[static_cast<std::size_t>(j)];
      if (const map::MapPoint* p = id == map::kInvalidId ? nullptr : map.point(id); usable(p)) {
        forward.push_back({p->position, {frame_pixel, -1.0}});
        forward_ids.emplace_back(static_cast<int>(i), id);
        in_3d = true;
      }
      if (!in_3d) plain.emplace_back(kf_pixel, frame_pixel);
      all_kf.emplace_back(kf_pixel.x(), kf_pixel.y());
      all_frame.emplace_back(frame_pixel.x(), frame_pixel.y());
    }
  }

  int matches() const { return static_cast<int>(all_kf.size()); }

  bool reprojects(const Eigen::Vector3d& X_camera, const Eigen::Vector2d& pixel) const {
    return X_camera.z() > 0 && (camera_.project(X_camera) - pixel).norm() <= reprojection_px_;
  }

  Support support(const Eigen::Isometry3d& T_world_frame) const {
    Support s;
    const Eigen::Isometry3d T_frame_world = T_world_frame.inverse();
    for (const auto& m : forward) s.forward += reprojects(T_frame_world * m.position_world, m.measurement.pixel);
    const Eigen::Isometry3d T_keyframe_frame = kf_->T_world_camera.inverse() * T_world_frame;
    for (std::size_t k = 0; k < reverse.size(); ++k)
      s.reverse += reprojects(T_keyframe_frame * reverse_in_frame[k], reverse[k].measurement.pixel);
    // Sampson distance of the plain matches to the epipolar geometry of the pose.
    const Eigen::Isometry3d T_frame_keyframe = T_keyframe_frame.inverse();
    const Eigen::Vector3d t = T_frame_keyframe.translation();
    if (t.norm() > 1e-9) {
      Eigen::Matrix3d t_cross;
      t_cross << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
      const Eigen::Matrix3d K = camera_.K();
      const Eigen::Matrix3d F = K.inverse().transpose() * t_cross * T_frame_keyframe.linear() * K.inverse();
      for (const auto& [kf_pixel, frame_pixel] : plain) {
        const Eigen::Vector3d x1 = kf_pixel.homogeneous(), x2 = frame_pixel.homogeneous();
        const Eigen::Vector3d Fx1 = F * x1, Ftx2 = F.transpose() * x2;
        const double sampson =
            std::abs(x2.dot(Fx1)) / std::sqrt(Fx1.head<2>().squaredNorm() + Ftx2.head<2>().squaredNorm());
        s.plain += sampson <= epipolar_px_;
      }
    }
    return s;
  }

  // The frame's pose in the keyframe's world from each kind of evidence that has enough of itself.
  std::vector<Eigen::Isometry3d> hypotheses(const backend::OptimizationParams& opt, int iterations,
                                            const Eigen::Isometry3d& T_world_query) const {
    std::vector<Eigen::Isometry3d> out;
    if (forward.size() >= 6)
      if (const auto pnp = backend::solve_pnp_ransac(camera_, forward, opt, iterations))
        out.push_back(pnp->T_world_camera);
    if (reverse.size() >= 6)
      if (const auto pnp = backend::solve_pnp_ransac(camera_, reverse, opt, iterations))
        out.push_back(kf_->T_world_camera * pnp->T_world_camera.inverse() * T_world_query);
    if (const auto two_view = essential_with_scale()) out.push_back(kf_->T_world_camera * two_view->inverse());
    return out;
  }

  std::vector<backend::PointMatch> forward, reverse;
  std::vector<std::pair<int, map::Id>> forward_ids;  // per forward correspondence: frame keypoint, map point
  std::vector<Eigen::Vector3d> reverse_in_frame;     // per reverse correspondence: the point in the frame's camera
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> plain;  // keyframe pixel, frame pixel

 private:
  // T_frame_keyframe from the essential matrix of all matches (rotation, direction of motion) and the median of the
  // lengths that the 3D correspondences ask for.
  std::optional<Eigen::Isometry3d> essential_with_scale() const {
    if (all_kf.size() < 8 || forward.size() + reverse.size() < 3) return std::nullopt;
    cv::Mat K;
    cv::eigen2cv(camera_.K(), K);
    cv::Mat mask;
    const cv::Mat E = cv::findEssentialMat(all_kf, all_frame, K, cv::RANSAC, 0.999, epipolar_px_, mask);
    if (E.rows != 3 || E.cols != 3) return std::nullopt;
    cv::Mat R_cv, t_cv;
    if (cv::recoverPose(E, all_kf, all_frame, K, R_cv, t_cv, mask) < 8) return std::nullopt;
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    cv::cv2eigen(R_cv, R);
    cv::cv2eigen(t_cv, t);  // x_frame = R x_keyframe + s t, |t| = 1
    // Each correspondence's two image equations are linear in s; each gives its own least-squares s.
    std::vector<double> scales;
    const auto solve = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector2d& pixel) {
      // pixel = project(a + s b): (u - cx)(a_z + s b_z) = fx (a_x + s b_x), and likewise in v.
      const double du = pixel.x() - camera_.cx, dv = pixel.y() - camera_.cy;
      const Eigen::Vector2d coefficient(du * b.z() - camera_.fx * b.x(), dv * b.z() - camera_.fy * b.y());
      const Eigen::Vector2d rhs(camera_.fx * a.x() - du * a.z(), camera_.fy * a.y() - dv * a.z());
      if (coefficient.squaredNorm() < 1e-12) return;
      if (const double s = coefficient.dot(rhs) / coefficient.squaredNorm(); s > 0) scales.push_back(s);
    };
    const Eigen::Isometry3d T_keyframe_world = kf_->T_world_camera.inverse();
    for (const auto& m : forward) solve(R * (T_keyframe_world * m.position_world), t, m.measurement.pixel);
    for (std::size_t k = 0; k < reverse.size(); ++k)  // X_keyframe = R^T (X_frame - s t)
      solve(R.transpose() * reverse_in_frame[k], -(R.transpose() * t), reverse[k].measurement.pixel);
    if (scales.size() < 3) return std::nullopt;
    std::nth_element(scales.begin(), scales.begin() + static_cast<std::ptrdiff_t>(scales.size() / 2), scales.end());
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = R;
    T.translation() = scales[scales.size() / 2] * t;
    return T;
  }

  const map::KeyFrame* kf_;
  geometry::PinholeCamera camera_;
  double reprojection_px_, epipolar_px_;
  Eigen::Isometry3d T_query_frame_world_;
  std::vector<cv::Point2d> all_kf, all_frame;
};

}  // namespace

std::optional<Relocalisation> Relocaliser::try_candidate(const RelocalisationQuery& query,
                                                         const RelocalisationCandidate& candidate, const map::Map& map,
                                                         const geometry::StereoCamera& stereo,
                                                         PointFrontend& matcher) const {
  const map::KeyFrame* kf = map.keyframe(candidate.keyframe);
  const features::PointFeatures* kf_features = features(candidate.keyframe);
  if (!kf || !kf_features) return std::nullopt;
  const features::PointMatches matches = matcher.match(*query.points, *kf_features);
  const CandidateEvidence evidence(query, *kf, matches, map, stereo.camera, optimization_);

  // A frame without 3D points of its own (tracking lost, no segment of its own yet) has to be placed by the map's
  // points alone, the classic PnP verification; one with them (a young segment) is checked against all its
  // matches, where the epipolar ones carry a large motion's rotation and direction.
  const bool own_points = std::any_of(query.keypoint_positions.begin(), query.keypoint_positions.end(),
                                      [](const auto& p) { return p.has_value(); });
  const auto score = [&](const CandidateEvidence::Support& s) { return own_points ? s.total() : s.points(); };
  std::optional<Eigen::Isometry3d> best;
  CandidateEvidence::Support best_support;
  for (const Eigen::Isometry3d& T : evidence.hypotheses(optimization_, params_.pnp_iterations, query.T_world_query))
    if (const auto s = evidence.support(T); s.points() >= params_.min_point_inliers && score(s) > score(best_support))
      best = T, best_support = s;
  spdlog::debug(
      "relocalisation: keyframe {} ({}): {} matches ({} with its map points, {} with the frame's, {} "
      "without 3D); inliers {} + {} + {}",
      candidate.keyframe, candidate.sources, evidence.matches(), evidence.forward.size(), evidence.reverse.size(),
      evidence.plain.size(), best_support.forward, best_support.reverse, best_support.plain);
  const int support = score(best_support);
  if (!best || support < params_.min_inliers || support < params_.min_inlier_ratio * evidence.matches())
    return std::nullopt;

  Relocalisation out;
  out.keyframe = candidate.keyframe;
  out.sources = candidate.sources;
  out.reverse = best_support.forward < params_.min_point_inliers;
  out.inliers = support;
  out.matches = evidence.matches();
  out.line_partner.assign(query.frame->lines.size(), -1);
  std::vector<backend::LineMatch> line_matches;
  std::vector<std::pair<int, map::Id>> line_of_match;
  if (use_lines_ && query.association && !query.frame->lines.empty() && !kf->lines.empty()) {
    out.line_partner = features::match_lines(*query.association, association_of(*kf), matches.matches0, line_matching_);
    for (std::size_t l = 0; l < out.line_partner.size(); ++l) {
      if (out.line_partner[l] < 0) continue;
      const map::Id id = kf->line_ids[static_cast<std::size_t>(out.line_partner[l])];
      const map::MapLine* line = id == map::kInvalidId ? nullptr : map.line(id);
      if (!usable(line)) continue;
      line_matches.push_back({line->line, {query.frame->lines[l].left, std::nullopt}});
      line_of_match.emplace_back(static_cast<int>(l), id);
    }
  }
  // Refined with the keyframe's points and lines seen in the frame where they hold the pose on their own; kept
  // when the refinement would lose support of the other kinds.
  out.T_world_camera = *best;
  const auto refined = backend::estimate_pose(stereo, *best, evidence.forward, line_matches, optimization_);
  if (refined.num_point_inliers >= params_.min_point_inliers &&
      score(evidence.support(refined.T_world_camera)) >= support) {
    out.T_world_camera = refined.T_world_camera;
    for (std::size_t k = 0; k < evidence.forward_ids.size(); ++k)
      if (refined.point_inliers[k]) out.points.push_back(evidence.forward_ids[k]);
    for (std::size_t k = 0; k < line_of_match.size(); ++k)
      if (refined.line_inliers[k]) out.lines.push_back(line_of_match[k]);
    return out;
  }
  const Eigen::Isometry3d T_frame_world = out.T_world_camera.inverse();
  for (std::size_t k = 0; k < evidence.forward.size(); ++k)
    if (evidence.reprojects(T_frame_world * evidence.forward[k].position_world, evidence.forward[k].measurement.pixel))
      out.points.push_back(evidence.forward_ids[k]);
  return out;
}

std::optional<Relocalisation> Relocaliser::relocalise(const RelocalisationQuery& query, const map::Map& map,
                                                      const geometry::StereoCamera& stereo, PointFrontend& matcher) {
  if (!params_.enabled || !query.points || !query.frame || query.points->size() == 0) return std::nullopt;
  ++stats_.attempts;
  // Every candidate within the budget is tried and the best supported pose wins: after a kidnap the first keyframe
  // that verifies may see the place from afar while another sees it up close.
  std::optional<Relocalisation> best;
  unsigned best_sources = 0;
  for (const RelocalisationCandidate& candidate : candidates(query, map)) {
    ++stats_.candidates_matched;
    auto found = try_candidate(query, candidate, map, stereo, matcher);
    if (found && (!best || found->inliers > best->inliers)) {
      best = std::move(found);
      best_sources = candidate.sources;
    }
  }
  if (!best) return std::nullopt;
  ++stats_.successes;
  stats_.successes_reverse += best->reverse;
  for (int s = 0; s < 3; ++s)
    if (best_sources & (1u << s)) ++stats_.successes_by_source[s];
  return best;
}

}  // namespace vkvo::system
