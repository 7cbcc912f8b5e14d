// Matching a frame's keypoints to the local map's points by projection (system/map_point_projection.hpp), on exact
// synthetic geometry: two keyframes that mapped a grid of 3D points, each with a random unit descriptor per view,
// and a frame 0.2 m away that sees them again with descriptors moved further than the NN matcher accepts.
#include <algorithm>
#include <random>

#include <gtest/gtest.h>

#include "geometry/scene.hpp"  // tests/geometry: test_stereo_camera
#include "system/map_point_projection.hpp"
#include "system/vo_config.hpp"

namespace vkvo::system {
namespace {

constexpr int kDim = 32;
using Descriptor = Eigen::Matrix<float, 1, kDim>;

Descriptor random_descriptor(std::mt19937& rng) {
  std::normal_distribution<float> n(0.0f, 1.0f);
  Descriptor d;
  for (int c = 0; c < kDim; ++c) d[c] = n(rng);
  return d.normalized();
}

// `d` moved to cosine distance `distance` (1 - cos) in a random direction orthogonal to it.
Descriptor moved(const Descriptor& d, float distance, std::mt19937& rng) {
  Descriptor away = random_descriptor(rng);
  away = (away - away.dot(d) * d).normalized();
  const float cosine = 1.0f - distance;
  return cosine * d + std::sqrt(1.0f - cosine * cosine) * away;
}

features::PointFeatures features_of(const std::vector<Eigen::Vector2d>& pixels,
                                    const std::vector<Descriptor>& descriptors) {
  features::PointFeatures f;
  f.image_width = 752;
  f.image_height = 480;
  f.descriptors.resize(static_cast<Eigen::Index>(pixels.size()), kDim);
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    f.keypoints.push_back(pixels[i].cast<float>());
    f.scores.push_back(1.0f);
    f.descriptors.row(static_cast<Eigen::Index>(i)) = descriptors[i];
  }
  return f;
}

// Keyframe `old` at the origin and keyframe `recent` 0.1 m to the right see 24 points on a wall 3-4 m away; each
// view has its own descriptor (`old_view`, `recent_view` 0.8 from it: the light changed between them). The frame
// is at T_frame.
struct MappedPoints {
  MappedPoints() {
    T_frame.linear() = Eigen::AngleAxisd(0.04, Eigen::Vector3d::UnitY()).toRotationMatrix();
    T_frame.translation() = Eigen::Vector3d(0.2, -0.03, 0.1);
    T_recent.translation() = Eigen::Vector3d(0.1, 0.0, 0.0);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> depth(3.0, 4.0);
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 6; ++c) {
        positions.push_back(Eigen::Vector3d(-1.2 + 0.45 * c, -0.6 + 0.4 * r, depth(rng)));
        old_view.push_back(random_descriptor(rng));
        recent_view.push_back(moved(old_view.back(), 0.8f, rng));
      }
    old = add_keyframe(Eigen::Isometry3d::Identity(), old_view);
    recent = add_keyframe(T_recent, recent_view);
    for (std::size_t k = 0; k < positions.size(); ++k) {
      points.push_back(map.add_point(positions[k]));
      map.add_point_observation(points.back(), old, static_cast<int>(k));
      map.add_point_observation(points.back(), recent, static_cast<int>(k));
    }
  }
  map::Id add_keyframe(const Eigen::Isometry3d& T, const std::vector<Descriptor>& descriptors) {
    map::Frame f;
    for (const Eigen::Vector3d& X : positions) f.keypoints.push_back(camera.project(T.inverse() * X));
    f.T_world_camera = T;
    f.reset_associations();
    const map::Id id = map.add_keyframe(f).id;
    kept.emplace(id, features_of(f.keypoints, descriptors));
    return id;
  }
  // The frame's view of point k at a pixel offset.
  Eigen::Vector2d seen(std::size_t k, const Eigen::Vector2d& offset = Eigen::Vector2d::Zero()) const {
    return camera.project(T_frame.inverse() * positions[k]) + offset;
  }
  std::vector<ProjectedPointMatch> match(const features::PointFeatures& frame, const std::vector<bool>& taken = {},
                                         const std::vector<map::Id>& tracked = {},
                                         std::vector<map::Id> keyframes = {}) const {
    if (keyframes.empty()) keyframes = {recent};  // the old view only where a test names it
    const KeyframeFeatures features = [this](map::Id kf) {
      const auto it = kept.find(kf);
      return it == kept.end() ? nullptr : &it->second;
    };
    return match_points_by_projection(map, keyframes, features, {T_frame, frame, taken, tracked}, camera, params);
  }
  // Map point of each keypoint in `matches` (kInvalidId: none), for a frame of n keypoints.
  static std::vector<map::Id> by_keypoint(const std::vector<ProjectedPointMatch>& matches, std::size_t n) {
    std::vector<map::Id> out(n, map::kInvalidId);
    for (const ProjectedPointMatch& m : matches) out[static_cast<std::size_t>(m.keypoint)] = m.map_point;
    return out;
  }

  const geometry::PinholeCamera camera = test::test_stereo_camera().camera;
  Eigen::Isometry3d T_frame = Eigen::Isometry3d::Identity(), T_recent = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Vector3d> positions;
  std::vector<Descriptor> old_view, recent_view;
  map::Map map;
  map::Id old = map::kInvalidId, recent = map::kInvalidId;
  std::vector<map::Id> points;
  std::map<map::Id, features::PointFeatures> kept;
  PointProjectionParams params;
};

TEST(MapPointProjection, EachMapPointFindsItsKeypointNearItsProjection) {
  MappedPoints s;
  // The frame sees the points in reverse order, 1-3 px from their projections (a prediction's error), with
  // descriptors 0.35 from the recent view: beyond the NN matcher's 0.245, within the projection's 0.5. Twelve
  // distractor keypoints lie 20-40 px away from every projection, with unrelated descriptors.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> offset(-2.0, 2.0);
  std::vector<Eigen::Vector2d> pixels;
  std::vector<Descriptor> descriptors;
  std::vector<std::size_t> truth;  // point index per keypoint, or SIZE_MAX
  for (std::size_t k = s.positions.size(); k-- > 0;) {
    pixels.push_back(s.seen(k, {offset(rng), offset(rng)}));
    descriptors.push_back(moved(s.recent_view[k], 0.35f, rng));
    truth.push_back(k);
  }
  for (int d = 0; d < 12; ++d) {
    pixels.push_back(s.seen(static_cast<std::size_t>(d), {25.0, 20.0 + d}));
    descriptors.push_back(random_descriptor(rng));
    truth.push_back(SIZE_MAX);
  }
  const auto matches = s.match(features_of(pixels, descriptors));
  const auto point_of = MappedPoints::by_keypoint(matches, pixels.size());
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    if (truth[i] == SIZE_MAX)
      EXPECT_EQ(point_of[i], map::kInvalidId) << "distractor " << i;
    else
      EXPECT_EQ(point_of[i], s.points[truth[i]]) << "keypoint " << i;
  }
  for (const ProjectedPointMatch& m : matches) EXPECT_NEAR(m.descriptor_distance, 0.35f, 1e-4f);
}

TEST(MapPointProjection, FarDescriptorsAmbiguousPairsAndOutOfRadiusKeypointsStayUnmatched) {
  MappedPoints s;
  std::mt19937 rng(4);
  std::vector<Eigen::Vector2d> pixels;
  std::vector<Descriptor> descriptors;
  // Point 0: its keypoint's descriptor is 0.7 from both views (the projection's threshold is 0.5).
  pixels.push_back(s.seen(0));
  descriptors.push_back(moved(s.recent_view[0], 0.7f, rng));
  // Point 1: two keypoints 2 px apart at distances 0.30 and 0.31: no margin (0.30 > 0.9 x 0.31).
  pixels.push_back(s.seen(1, {1.0, 0.0}));
  descriptors.push_back(moved(s.recent_view[1], 0.30f, rng));
  pixels.push_back(s.seen(1, {-1.0, 0.0}));
  descriptors.push_back(moved(s.recent_view[1], 0.31f, rng));
  // Point 2: its keypoint lies 12 px from the projection, outside the 10 px radius.
  pixels.push_back(s.seen(2, {12.0, 0.0}));
  descriptors.push_back(s.recent_view[2]);
  // Point 3: a clear winner (0.2 against 0.6) beside an unrelated neighbour.
  pixels.push_back(s.seen(3, {1.0, 1.0}));
  descriptors.push_back(moved(s.recent_view[3], 0.2f, rng));
  pixels.push_back(s.seen(3, {-2.0, 1.0}));
  descriptors.push_back(moved(s.recent_view[3], 0.6f, rng));

  const auto point_of = MappedPoints::by_keypoint(s.match(features_of(pixels, descriptors)), pixels.size());
  const std::vector<map::Id> expected = {map::kInvalidId, map::kInvalidId, map::kInvalidId,
                                         map::kInvalidId, s.points[3],     map::kInvalidId};
  EXPECT_EQ(point_of, expected);

  // A wider radius takes point 2's keypoint; a looser threshold point 0's.
  s.params.radius_px = 15.0;
  s.params.max_cosine_distance = 0.8;
  const auto loose = MappedPoints::by_keypoint(s.match(features_of(pixels, descriptors)), pixels.size());
  EXPECT_EQ(loose[0], s.points[0]);
  EXPECT_EQ(loose[3], s.points[2]);
  EXPECT_EQ(loose[1], map::kInvalidId);
}

TEST(MapPointProjection, TakenKeypointsTrackedPointsAndPointsOutOfViewAreSkipped) {
  MappedPoints s;
  std::vector<Eigen::Vector2d> pixels;
  std::vector<Descriptor> descriptors;
  for (std::size_t k = 0; k < 4; ++k) {
    pixels.push_back(s.seen(k));
    descriptors.push_back(s.recent_view[k]);
  }
  const auto frame = features_of(pixels, descriptors);
  // Keypoint 0 is already matched; map point 1 is already tracked.
  const auto point_of = MappedPoints::by_keypoint(s.match(frame, {true, false, false, false}, {s.points[1]}), 4);
  EXPECT_EQ(point_of, (std::vector<map::Id>{map::kInvalidId, map::kInvalidId, s.points[2], s.points[3]}));

  // Turned round, the camera sees none of them (all behind it) even with every keypoint at hand.
  s.T_frame.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix();
  EXPECT_TRUE(s.match(frame).empty());
}

TEST(MapPointProjection, APointIsRecognisedByAnyOfItsViews) {
  MappedPoints s;
  // The frame's descriptors resemble the old view (0.05 from it) and lie over 0.5 from the recent one: with both
  // keyframes given every point matches; with the recent keyframe alone none does.
  std::mt19937 rng(5);
  std::vector<Eigen::Vector2d> pixels;
  std::vector<Descriptor> descriptors;
  for (std::size_t k = 0; k < s.positions.size(); ++k) {
    pixels.push_back(s.seen(k));
    descriptors.push_back(moved(s.old_view[k], 0.05f, rng));
  }
  const auto frame = features_of(pixels, descriptors);
  for (std::size_t k = 0; k < s.positions.size(); ++k)
    ASSERT_GT(1.0f - frame.descriptors.row(static_cast<Eigen::Index>(k)).dot(s.recent_view[k]), 0.5f) << k;
  EXPECT_EQ(s.match(frame, {}, {}, {s.recent, s.old}).size(), s.positions.size());
  EXPECT_TRUE(s.match(frame).empty());
}

TEST(MapPointProjection, AKeypointClaimedTwiceGoesToTheCloserDescriptor) {
  MappedPoints s;
  // Points 0 and 1 moved to project within 4 px of each other, one keypoint between them whose descriptor is
  // 0.2 from point 1's and 0.4 from point 0's.
  s.map.point(s.points[0])->position = s.positions[1] + Eigen::Vector3d(0.01, 0.0, 0.0);
  std::mt19937 rng(6);
  const Eigen::Vector2d pixel = s.seen(1, {1.0, 0.0});
  const Descriptor d = moved(s.recent_view[1], 0.2f, rng);
  s.recent_view[0] = moved(d, 0.4f, rng);  // point 0's recent view, 0.4 from the keypoint
  s.kept[s.recent].descriptors.row(0) = s.recent_view[0];
  const auto matches = s.match(features_of({pixel}, {d}));
  ASSERT_EQ(matches.size(), 1u);
  EXPECT_EQ(matches[0].map_point, s.points[1]);
}

TEST(MapPointProjection, ConfigKeysAndErrors) {
  const auto p = load_point_projection_params(
      YAML::Load("{enabled: false, below_point_inliers: 20, radius_px: 6, max_cosine_distance: 0.4, max_ratio: 0.8}"));
  EXPECT_FALSE(p.enabled);
  EXPECT_EQ(p.below_point_inliers, 20);
  EXPECT_DOUBLE_EQ(p.radius_px, 6.0);
  EXPECT_DOUBLE_EQ(p.max_cosine_distance, 0.4);
  EXPECT_DOUBLE_EQ(p.max_ratio, 0.8);
  const PointProjectionParams defaults = load_tracking_params(YAML::Load("{}")).point_projection;
  EXPECT_TRUE(defaults.enabled);
  EXPECT_EQ(defaults.below_point_inliers, 10);
  EXPECT_EQ(load_tracking_params(YAML::Load("{point_projection: {radius_px: 4}}")).point_projection.radius_px, 4.0);
  for (const char* bad : {"{radius_px: 0}", "{max_cosine_distance: 0}", "{max_cosine_distance: 2.5}", "{max_ratio: 0}",
                          "{max_ratio: 1.5}", "{below_point_inliers: -1}", "[1, 2]"})
    EXPECT_THROW(load_point_projection_params(YAML::Load(bad)), std::runtime_error) << bad;
}

}  // namespace
}  // namespace vkvo::system
