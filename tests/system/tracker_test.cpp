// The optimisation stage on an exact synthetic stereo scene (oracle features, no GPU): initialisation, tracking,
// keyframes, recovery from frames where nothing is seen, the motion prior through them, relocalisation, the
// merge of a young map segment into the old map, and frames carried by lines where points fall short.
#include <algorithm>
#include <array>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "features/lines/line_detector.hpp"
#include "system/oracle_frontend.hpp"
#include "system/tracker.hpp"

namespace vkvo::system {
namespace {

VoConfig points_only_config() {
  VoConfig config;
  config.tracking.use_lines = false;  // the oracle images have no lines
  config.triangulation.max_depth = 20.0;
  return config;
}

FrameInput make_input(test::OracleFrontend& oracle, int frame, const MatchReference& reference) {
  FrameInput in;
  in.index = static_cast<std::size_t>(frame);
  in.timestamp_s = 0.05 * frame;
  in.left = oracle.image(frame, false);
  in.right = oracle.image(frame, true);
  in.points = oracle.detect(in.left);
  if (reference.features) {
    in.matches = oracle.match(in.points, *reference.features);
    in.reference_keyframe = reference.keyframe;
    in.matched_against = reference.keyframe;
  }
  return in;
}

// A points-only tracker started at the true first pose of a synthetic scene, fed by the oracle front end.
struct OracleRun {
  OracleRun(int frames, int points, std::uint32_t scene_seed, double pixel_noise, std::uint32_t oracle_seed,
            const VoConfig& config = points_only_config())
      : scene(test::SyntheticScene::make(frames, points, scene_seed)),
        oracle(scene, pixel_noise, oracle_seed),
        tracker(config, scene.stereo, oracle, scene.T_world_left[0]) {}

  FrameInput input(int frame) { return make_input(oracle, frame, tracker.reference()); }
  TrackResult track(const FrameInput& in) { return tracker.track(in, timing); }
  // Distance of the tracked camera position from the truth.
  double position_error(const TrackResult& result, int frame) const {
    return (result.T_world_camera.translation() - scene.T_world_left[frame].translation()).norm();
  }

  const test::SyntheticScene scene;
  test::OracleFrontend oracle;
  Tracker tracker;
  TimingReport timing;
};

TEST(Tracker, TracksAnExactSceneToMillimetresWithKeyframes) {
  OracleRun run(60, 600, 7, 0.0, 1);
  int keyframes = 0;
  for (int f = 0; f < 60; ++f) {
    const auto r = run.track(run.input(f));
    ASSERT_TRUE(r.tracked) << "frame " << f;
    keyframes += r.keyframe;
    EXPECT_LT(run.position_error(r, f), 1e-3) << "frame " << f;
    const Eigen::AngleAxisd rotation_error(r.T_world_camera.linear().transpose() * run.scene.T_world_left[f].linear());
    EXPECT_LT(rotation_error.angle(), 1e-4) << "frame " << f;
  }
  EXPECT_GE(keyframes, 2) << "the rig moves 0.9 m: the 0.5 m rule must fire";
  EXPECT_EQ(run.tracker.tracking_losses(), 0);
  EXPECT_EQ(run.tracker.segments(), 1);
  EXPECT_GT(run.tracker.map().points().size(), 100u);
  EXPECT_GT(run.timing.stats(Module::IPE).samples, 50u);
  EXPECT_EQ(run.timing.stats(Module::BA).samples, static_cast<std::size_t>(keyframes));
  // Frames come without their detection here: PE's samples are the keyframes' right images, and every keyframe
  // adds its stereo matching to PM.
  EXPECT_EQ(run.timing.stats(Module::PE).samples, static_cast<std::size_t>(keyframes));
  EXPECT_GE(run.timing.stats(Module::PM).samples, static_cast<std::size_t>(keyframes));
}

// What the overlay video draws: every keypoint's role after tracking. The first frame's stereo points are the new
// map; later, the inliers are the tracked points, and only keyframes add new points.
TEST(Tracker, ObservationsGiveEveryKeypointItsRole) {
  OracleRun run(40, 500, 7, 0.0, 1);  // 0.6 m: the 0.5 m keyframe rule fires
  const auto count = [](const FrameObservations& o, KeypointRole role) {
    return static_cast<int>(std::count(o.roles.begin(), o.roles.end(), role));
  };
  int keyframes_seen = 0;
  for (int f = 0; f < 40; ++f) {
    const FrameInput in = run.input(f);
    const auto r = run.track(in);
    const FrameObservations& o = r.observations;
    ASSERT_EQ(o.keypoints.size(), in.points.size()) << "frame " << f;
    ASSERT_EQ(o.roles.size(), in.points.size()) << "frame " << f;
    EXPECT_EQ(o.keypoints[0].cast<float>(), in.points.keypoints[0]) << "frame " << f;
    EXPECT_EQ(count(o, KeypointRole::inlier), f == 0 ? 0 : r.tracked_points) << "frame " << f;
    if (f == 0) {
      EXPECT_EQ(count(o, KeypointRole::new_point), static_cast<int>(run.tracker.map().points().size()));
      EXPECT_EQ(count(o, KeypointRole::outlier), 0);
    } else if (r.keyframe) {
      ++keyframes_seen;
      EXPECT_GT(count(o, KeypointRole::new_point), 0) << "frame " << f;
    } else {
      EXPECT_EQ(count(o, KeypointRole::new_point), 0) << "frame " << f;
    }
    EXPECT_TRUE(o.lines.empty() && o.line_roles.empty());
  }
  EXPECT_GE(keyframes_seen, 1);
}

TEST(Tracker, NoisyKeypointsStayWithinCentimetres) {
  OracleRun run(40, 500, 11, 0.5, 2);
  for (int f = 0; f < 40; ++f) {
    const auto r = run.track(run.input(f));
    ASSERT_TRUE(r.tracked) << "frame " << f;
    // 0.5 px on a 0.11 m baseline is ~0.3 m of depth noise at 6 m: before the first BA the map carries that, so
    // a few percent of the 0.6 m travelled is the expected error, not millimetres.
    EXPECT_LT(run.position_error(r, f), 0.05) << "frame " << f;
  }
}

// A black frame (nothing detected) loses tracking; the next frames match the map again.
TEST(Tracker, ABlackFrameIsLostAndTrackingResumes) {
  OracleRun run(30, 500, 13, 0.0, 3);
  for (int f = 0; f < 30; ++f) {
    FrameInput in = run.input(f);
    if (f == 15) {  // black frame: no points in either image
      in.points = {};
      in.matches = {};
      in.right = cv::Mat(480, 752, CV_8UC1, cv::Scalar(0));
    }
    const auto r = run.track(in);
    EXPECT_EQ(r.tracked, f != 15) << "frame " << f;
    if (f != 15) {
      EXPECT_LT(run.position_error(r, f), 1e-3) << "frame " << f;
    }
  }
  EXPECT_EQ(run.tracker.tracking_losses(), 1);
  EXPECT_EQ(run.tracker.segments(), 1) << "no segment can start on a frame without features";
}

// Through a dark stretch the predicted poses carry on at the last tracked velocity: on this smooth path they stay
// close to the truth, where standing still at the last tracked pose would fall behind by a step per frame.
TEST(Tracker, BlackFramesArePredictedAtTheLastVelocity) {
  OracleRun run(30, 500, 13, 0.0, 3);
  for (int f = 0; f < 30; ++f) {
    FrameInput in = run.input(f);
    const bool black = f >= 14 && f <= 16;
    if (black) {
      in.points = {};
      in.matches = {};
      in.right = cv::Mat(480, 752, CV_8UC1, cv::Scalar(0));
    }
    const auto r = run.track(in);
    EXPECT_EQ(r.tracked, !black) << "frame " << f;
    if (!black) continue;
    const double step = (run.scene.T_world_left[f].translation() - run.scene.T_world_left[13].translation()).norm();
    EXPECT_LT(run.position_error(r, f), 0.2 * step) << "frame " << f << " (" << step << " m from the last tracked)";
  }
  EXPECT_EQ(run.tracker.tracking_losses(), 3);
}

// When the reference keyframe cannot be matched (here: the feature stage's matches are lost), relocalisation finds
// the frame in the map from its own matches to the map's keyframes: no new segment, the pose as exact as tracking.
TEST(Tracker, UnmatchableReferenceIsRelocalisedInTheMap) {
  OracleRun run(30, 500, 17, 0.0, 4);
  for (int f = 0; f < 30; ++f) {
    FrameInput in = run.input(f);
    if (f == 12) in.matches = {};
    const auto r = run.track(in);
    EXPECT_TRUE(r.tracked) << "frame " << f;
    EXPECT_EQ(r.state, f == 12 ? FrameState::relocalised : FrameState::tracked) << "frame " << f;
    EXPECT_LT(run.position_error(r, f), 1e-3) << "frame " << f;
  }
  EXPECT_EQ(run.tracker.tracking_losses(), 0);
  EXPECT_EQ(run.tracker.relocalisations(), 1);
  EXPECT_EQ(run.tracker.segments(), 1);
  EXPECT_GT(run.timing.stats(Module::RL).samples, 0u);
}

// Without relocalisation, an unmatchable frame starts a new map segment at the predicted pose from its own stereo
// pair: the trajectory stays continuous and tracking goes on.
TEST(Tracker, WithoutRelocalisationAnUnmatchableFrameStartsANewSegment) {
  VoConfig config = points_only_config();
  config.relocalisation.enabled = false;
  OracleRun run(30, 500, 17, 0.0, 4, config);
  for (int f = 0; f < 30; ++f) {
    FrameInput in = run.input(f);
    if (f == 12) in.matches = {};
    const auto r = run.track(in);
    // The frame that starts the new segment anchors it: tracked there, at the predicted pose.
    EXPECT_TRUE(r.tracked) << "frame " << f;
    EXPECT_EQ(r.new_segment, f == 0 || f == 12) << "frame " << f;
    EXPECT_EQ(r.segment, f < 12 ? 0 : 1) << "frame " << f;
    // Constant-velocity prediction over one frame of this smooth path is good to a few millimetres.
    EXPECT_LT(run.position_error(r, f), 0.02) << "frame " << f;
  }
  EXPECT_EQ(run.tracker.tracking_losses(), 1);
  EXPECT_EQ(run.tracker.segments(), 2);
  EXPECT_EQ(run.tracker.relocalisations(), 0);
}

// A kidnap: frames 20-39 never reach the tracker, so frame 40 appears 0.3 m and several degrees from where the
// motion prior puts it, beyond what tracking against the last keyframe with that prior recovers on its own only by
// chance. Relocalisation puts it back in the same map.
TEST(Tracker, KidnappedCameraIsRelocalisedInTheSameMap) {
  OracleRun run(60, 600, 19, 0.0, 5);
  for (int f = 0; f < 60; ++f) {
    if (f >= 20 && f < 40) continue;
    FrameInput in = run.input(f);
    if (f == 40) in.matches = {};  // the feature stage matched a stale reference: nothing usable
    const auto r = run.track(in);
    EXPECT_TRUE(r.tracked) << "frame " << f;
    EXPECT_LT(run.position_error(r, f), 1e-3) << "frame " << f;
    if (f == 40) {
      EXPECT_EQ(r.state, FrameState::relocalised);
    }
  }
  EXPECT_EQ(run.tracker.segments(), 1);
  EXPECT_EQ(run.tracker.segments_started(), 1);
}

// Matches between a frame of the "dark" stretch's far side and the map made before it are refused while `blocked`
// is set (the frames' indices ride in the oracle features' one-column descriptors), as when the scene looks too
// different to match at first.
class BlockingFrontend : public PointFrontend {
 public:
  explicit BlockingFrontend(PointFrontend& inner) : inner_(&inner) {}
  // Tags the features with the frame of the image (the oracle writes it in the image's first row).
  features::PointFeatures detect(const cv::Mat& gray) override {
    features::PointFeatures f = inner_->detect(gray);
    f.descriptors.setConstant(static_cast<float>(gray.at<unsigned char>(0, 1) + 256 * gray.at<unsigned char>(0, 2)));
    return f;
  }
  features::PointMatches match(const features::PointFeatures& a, const features::PointFeatures& b) override {
    features::PointMatches m = inner_->match(a, b);
    if (blocked && frame_of(a) >= after && frame_of(b) < before) {
      m.matches0.assign(a.size(), -1);
      m.scores0.assign(a.size(), 0.0f);
    }
    return m;
  }
  static int frame_of(const features::PointFeatures& f) {
    return f.descriptors.size() ? static_cast<int>(f.descriptors(0, 0)) : -1;
  }
  bool blocked = true;
  int before = 0, after = 0;

 private:
  PointFrontend* inner_;
};

// Lights off for frames 14-20; at 21 the map cannot be matched at first (BlockingFrontend), so a young segment
// starts at the predicted pose, a few centimetres off. From frame 26 the old map matches again: the first tracked
// frame there merges the young segment into the old map, and every later pose, and every keyframe of the young
// segment, is back within millimetres of the truth.
TEST(Tracker, YoungSegmentMergesIntoTheOldMap) {
  const auto scene = test::SyntheticScene::make(45, 600, 23);
  test::OracleFrontend oracle(scene, 0.0, 6);
  BlockingFrontend frontend(oracle);
  frontend.before = 14;
  frontend.after = 21;
  Tracker tracker(points_only_config(), scene.stereo, frontend, scene.T_world_left[0]);
  TimingReport timing;
  std::optional<SegmentMerge> merge;
  for (int f = 0; f < 45; ++f) {
    frontend.blocked = f < 26;
    const bool dark = f >= 14 && f <= 20;
    FrameInput in;
    in.index = static_cast<std::size_t>(f);
    in.timestamp_s = 0.05 * f;
    in.left = dark ? cv::Mat(480, 752, CV_8UC1, cv::Scalar(0)) : oracle.image(f, false);
    in.right = dark ? cv::Mat(480, 752, CV_8UC1, cv::Scalar(0)) : oracle.image(f, true);
    in.points = frontend.detect(in.left);
    if (const MatchReference reference = tracker.reference(); reference.features) {
      in.matches = frontend.match(in.points, *reference.features);
      in.reference_keyframe = reference.keyframe;
      in.matched_against = reference.keyframe;
    }
    const auto r = tracker.track(in, timing);
    const double error = (r.T_world_camera.translation() - scene.T_world_left[f].translation()).norm();
    EXPECT_EQ(r.tracked, !dark) << "frame " << f;
    if (f == 21) {
      EXPECT_TRUE(r.new_segment);
      EXPECT_EQ(r.segment, 1);
      EXPECT_GT(error, 0.005) << "the young segment starts at a prediction";
    }
    if (r.merge) {
      EXPECT_EQ(f, 26);
      EXPECT_EQ(r.state, FrameState::relocalised);
      EXPECT_EQ(r.merge->from, 1);
      EXPECT_EQ(r.merge->into, 0);
      merge = r.merge;
    }
    if (f >= 26) {
      EXPECT_EQ(r.segment, 0) << "frame " << f;
      EXPECT_LT(error, 2e-3) << "frame " << f;
    }
  }
  ASSERT_TRUE(merge.has_value());
  EXPECT_EQ(tracker.segments(), 1);
  EXPECT_EQ(tracker.segments_started(), 2);
  EXPECT_EQ(tracker.merges(), 1);
  for (const auto& [id, kf] : tracker.map().keyframes()) {
    EXPECT_EQ(kf.segment, 0) << "keyframe " << id;
    const auto frame = static_cast<std::size_t>(kf.frame_id);
    EXPECT_LT((kf.T_world_camera.translation() - scene.T_world_left[frame].translation()).norm(), 2e-3)
        << "keyframe " << id << " (frame " << frame << ")";
  }
}

// Posters facing the rig, drawn into the oracle's images (black but for their tag) so that the line detector finds
// their edges: the scene's lines. Each carries its own horizontal stripes, as print does, so that its edges'
// image strips tell one poster from another.
struct Poster {
  std::array<Eigen::Vector3d, 4> corners;  // world: bottom left, bottom right, top right, top left
  cv::Mat texture;
};

std::vector<Poster> make_posters(int count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Poster> posters;
  for (int i = 0; i < count; ++i) {
    // 2.5-3.5 m away: at 0.11 m of baseline a farther line's two back-projected planes meet at about 1 degree,
    // the triangulation's degeneracy gate.
    const Eigen::Vector3d centre(1.6 * u(rng), 0.6 * u(rng), 3.0 + 0.5 * u(rng));
    const double tilt = 0.3 * u(rng);  // about the optical axis, so that the edges' slopes differ
    const Eigen::Vector3d up = 0.35 * (1.0 + 0.3 * u(rng)) * Eigen::Vector3d(std::sin(tilt), std::cos(tilt), 0.0);
    const Eigen::Vector3d across = 0.12 * (1.0 + 0.5 * u(rng)) * Eigen::Vector3d(std::cos(tilt), -std::sin(tilt), 0.0);
    cv::Mat texture(240, 80, CV_8UC1);
    const double base = 150 + 40 * u(rng), period = 30 + 20 * u(rng), phase = 3 * u(rng);
    for (int row = 0; row < texture.rows; ++row)
      texture.row(row).setTo(base + 50 * std::sin(2 * M_PI * row / period + phase));
    posters.push_back(
        {{centre - across - up, centre + across - up, centre + across + up, centre - across + up}, texture});
  }
  return posters;
}

void draw_posters(cv::Mat& image, const std::vector<Poster>& posters, const geometry::PinholeCamera& camera,
                  const Eigen::Isometry3d& T_camera_world) {
  std::vector<std::pair<double, const Poster*>> by_depth;
  for (const Poster& p : posters) by_depth.emplace_back((T_camera_world * p.corners[0]).z(), &p);
  std::sort(by_depth.rbegin(), by_depth.rend());  // the farthest first: nearer posters cover it
  cv::Mat canvas;
  image.convertTo(canvas, CV_32F);
  for (const auto& [depth, poster] : by_depth) {
    const float w = static_cast<float>(poster->texture.cols), h = static_cast<float>(poster->texture.rows);
    const std::vector<cv::Point2f> texture_corners = {{0, h}, {w, h}, {w, 0}, {0, 0}};
    std::vector<cv::Point2f> image_corners;
    for (const Eigen::Vector3d& corner : poster->corners) {
      const Eigen::Vector2d px = camera.project(T_camera_world * corner);
      image_corners.emplace_back(static_cast<float>(px.x()), static_cast<float>(px.y()));
    }
    const cv::Mat H = cv::getPerspectiveTransform(texture_corners, image_corners);
    cv::Mat warped, coverage, texture;
    poster->texture.convertTo(texture, CV_32F);
    cv::warpPerspective(texture, warped, H, image.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
    cv::warpPerspective(cv::Mat(texture.size(), CV_32F, cv::Scalar(1)), coverage, H, image.size(), cv::INTER_LINEAR,
                        cv::BORDER_CONSTANT, 0);
    canvas = canvas.mul(1.0 - coverage) + warped;  // `warped` is already weighted by the coverage
  }
  const cv::Mat tag = image.row(0).clone();
  canvas.convertTo(image, CV_8U);
  tag.colRange(0, 4).copyTo(image.row(0).colRange(0, 4));
}

void keep_strongest(features::PointFeatures& points, std::size_t count) {
  count = std::min(count, points.size());
  points.keypoints.resize(count);
  points.scores.resize(count);
  points.descriptors.conservativeResize(static_cast<Eigen::Index>(count), points.descriptors.cols());
}

// Frames 12-17 keep five keypoints each, as in the dark: too few for a pose (min_pose_inliers 10). With
// tracking.lines_carry_frames the posters' edges, matched to the local map by projection, carry them to
// centimetres and the frames become keyframes; with points alone they are lost.
TEST(Tracker, LinesCarryFramesWhosePointsFallShort) {
  constexpr int kFrames = 30;
  const auto scene = test::SyntheticScene::make(kFrames, 300, 13);
  const geometry::StereoCamera& stereo = scene.stereo;
  const std::vector<Poster> posters = make_posters(10, 5);
  test::OracleFrontend renderer(scene, 0.0, 3);
  std::vector<std::pair<cv::Mat, cv::Mat>> images;
  for (int f = 0; f < kFrames; ++f) {
    const Eigen::Isometry3d T_left_world = scene.T_world_left[static_cast<std::size_t>(f)].inverse();
    images.emplace_back(renderer.image(f, false), renderer.image(f, true));
    draw_posters(images.back().first, posters, stereo.camera, T_left_world);
    draw_posters(images.back().second, posters, stereo.camera, stereo.T_left_right().inverse() * T_left_world);
  }

  for (const bool carry : {true, false}) {
    SCOPED_TRACE(carry ? "lines carry frames" : "points alone");
    VoConfig config;
    config.triangulation.max_depth = 20.0;
    config.tracking.lines_carry_frames = carry;
    OracleRun run(kFrames, 300, 13, 0.0, 3, config);
    const features::LineDetector detector(config.lines.detector);
    double worst_carried = 0;
    for (int f = 0; f < kFrames; ++f) {
      const bool thin = f >= 12 && f <= 17;
      FrameInput in;
      in.index = static_cast<std::size_t>(f);
      in.timestamp_s = 0.05 * f;
      std::tie(in.left, in.right) = images[static_cast<std::size_t>(f)];
      in.points = run.oracle.detect(in.left);
      if (thin) keep_strongest(in.points, 5);
      in.lines = detector.detect(in.left);
      if (const MatchReference reference = run.tracker.reference(); reference.features) {
        in.matches = run.oracle.match(in.points, *reference.features);
        in.reference_keyframe = in.matched_against = reference.keyframe;
      }
      const auto r = run.track(in);
      if (!thin) {
        EXPECT_TRUE(r.tracked) << "frame " << f;
        continue;
      }
      EXPECT_EQ(r.tracked, carry) << "frame " << f;
      if (!carry) continue;
      EXPECT_LE(r.tracked_points, 5) << "frame " << f;
      EXPECT_GE(r.tracked_lines, 5) << "frame " << f;
      // Stereo lines at 3 m on 0.11 m of baseline are placed to several centimetres in depth before BA refines them.
      EXPECT_LT(run.position_error(r, f), 0.02) << "frame " << f;
      worst_carried = std::max(worst_carried, run.position_error(r, f));
    }
    if (carry) RecordProperty("worst_carried_position_error_m", fmt::format("{:.4f}", worst_carried));
  }
}

}  // namespace
}  // namespace vkvo::system
