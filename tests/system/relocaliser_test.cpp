// Relocaliser: the global descriptor, the candidate sources and their interleaving, and a verified pose from an
// exact synthetic scene (oracle matches) when the prediction is far off.
#include "system/relocaliser.hpp"

#include <gtest/gtest.h>

#include "system/oracle_frontend.hpp"
#include "system/stereo_keyframe.hpp"

namespace vkvo::system {
namespace {

// Features whose descriptors all point along `direction` (unit), with unit scores.
features::PointFeatures features_along(const Eigen::VectorXf& direction, int count = 4) {
  features::PointFeatures f;
  f.image_width = 752;
  f.image_height = 480;
  for (int i = 0; i < count; ++i) {
    f.keypoints.emplace_back(10.0f * i, 10.0f);
    f.scores.push_back(1.0f);
  }
  f.descriptors.resize(count, direction.size());
  for (int i = 0; i < count; ++i) f.descriptors.row(i) = direction.normalized().transpose();
  return f;
}

Eigen::VectorXf axis(int i, int dim = 8) { return Eigen::VectorXf::Unit(dim, i); }

TEST(GlobalDescriptor, ScoreWeightedMeanOfTheDescriptorsNormalised) {
  features::PointFeatures f;
  f.keypoints = {{0, 0}, {1, 1}};
  f.scores = {3.0f, 1.0f};
  f.descriptors.resize(2, 2);
  f.descriptors << 1, 0, 0, 1;
  const Eigen::VectorXf g = global_descriptor(f);
  ASSERT_EQ(g.size(), 2);
  EXPECT_NEAR(g(0), 3.0 / std::sqrt(10.0), 1e-6);
  EXPECT_NEAR(g(1), 1.0 / std::sqrt(10.0), 1e-6);
  EXPECT_EQ(global_descriptor(features::PointFeatures{}).size(), 0);
}

struct CandidateMap {
  // Keyframes 0-5 along x every 1 m; keyframe k looks along descriptor axis k; 4 and 5 are in segment 1.
  CandidateMap() : relocaliser({}, {}, {}, false) {
    for (int k = 0; k < 6; ++k) {
      map::Frame f;
      f.T_world_camera.translation() = Eigen::Vector3d(k, 0, 0);
      f.reset_associations();
      map::KeyFrame& kf = map.add_keyframe(f);
      kf.segment = k >= 4 ? 1 : 0;
      relocaliser.add_keyframe(kf.id, std::make_shared<const features::PointFeatures>(features_along(axis(k))));
    }
  }
  map::Map map;
  Relocaliser relocaliser;
};

TEST(Relocaliser, CandidatesInterleaveAppearancePositionAndRecency) {
  CandidateMap scene;
  const features::PointFeatures query_points = features_along(axis(1) + 0.5f * axis(2));
  map::Frame query_frame;
  RelocalisationQuery query{.points = &query_points, .frame = &query_frame};
  query.T_world_predicted.translation() = Eigen::Vector3d(3.2, 0, 0);
  query.max_candidates = 6;
  const auto candidates = scene.relocaliser.candidates(query, scene.map);
  // Appearance ranks 1 then 2; position (within 3 m of x = 3.2) ranks 3, 4, 2, 5, 1 ...; recency 5, 4, 3, ...
  std::vector<map::Id> order;
  for (const auto& c : candidates) order.push_back(c.keyframe);
  EXPECT_EQ(order, (std::vector<map::Id>{1, 3, 5, 2, 4, 0}));
  EXPECT_TRUE(candidates[0].sources & kByAppearance);
  EXPECT_TRUE(candidates[1].sources & kByPosition);
  EXPECT_TRUE(candidates[2].sources & kByRecency);

  // A budget of two: the best of the first two sources. Excluding segment 1 drops keyframes 4 and 5.
  query.max_candidates = 2;
  EXPECT_EQ(scene.relocaliser.candidates(query, scene.map).size(), 2u);
  query.max_candidates = 6;
  query.exclude_segment = 1;
  for (const auto& c : scene.relocaliser.candidates(query, scene.map)) EXPECT_LT(c.keyframe, 4u);
}

// Two keyframes of an exact scene; the query frame is predicted 2 m and 30 deg away from where it is, and its
// matches to the reference are gone. Relocalisation finds it to a millimetre by PnP on the keyframes' map points.
TEST(Relocaliser, SolvesAFarOffFrameFromAKeyframesMapPoints) {
  const auto scene = test::SyntheticScene::make(40, 600, 29);
  test::OracleFrontend oracle(scene, 0.0, 7);
  map::Map map;
  backend::OptimizationParams optimization;
  RelocalisationParams params;
  Relocaliser relocaliser(params, optimization, {}, false);
  for (int frame : {0, 10}) {
    const auto left = oracle.detect(oracle.image(frame, false));
    const auto right = oracle.detect(oracle.image(frame, true));
    geometry::TriangulationParams triangulation;
    triangulation.max_depth = 20.0;  // the scene reaches 9 m
    const StereoPoints stereo =
        triangulate_stereo_points(scene.stereo, left, right, oracle.match(left, right), triangulation);
    map::Frame f;
    f.T_world_camera = scene.T_world_left[frame];
    for (const auto& k : left.keypoints) f.keypoints.push_back(k.cast<double>());
    f.reset_associations();
    const map::Id kf = map.add_keyframe(f).id;
    for (std::size_t i = 0; i < stereo.positions.size(); ++i)
      if (stereo.positions[i])
        map.add_point_observation(map.add_point(f.T_world_camera * *stereo.positions[i]), kf, static_cast<int>(i));
    relocaliser.add_keyframe(kf, std::make_shared<const features::PointFeatures>(left));
  }
  const int frame = 16;
  const auto points = oracle.detect(oracle.image(frame, false));
  map::Frame query_frame;
  for (const auto& k : points.keypoints) query_frame.keypoints.push_back(k.cast<double>());
  query_frame.reset_associations();
  RelocalisationQuery query{.points = &points, .frame = &query_frame};
  query.T_world_predicted = scene.T_world_left[frame];
  query.T_world_predicted.translate(Eigen::Vector3d(2, 0, 0));
  query.T_world_predicted.rotate(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()));
  const auto found = relocaliser.relocalise(query, map, scene.stereo, oracle);
  ASSERT_TRUE(found.has_value());
  EXPECT_LT((found->T_world_camera.translation() - scene.T_world_left[frame].translation()).norm(), 1e-3);
  EXPECT_GE(found->inliers, params.min_inliers);
  EXPECT_GE(static_cast<int>(found->points.size()), params.min_inliers);
  EXPECT_EQ(relocaliser.stats().successes, 1);

  // Disabled, or a frame with nothing in it: nothing found, nothing matched.
  const features::PointFeatures nothing;
  query.points = &nothing;
  EXPECT_FALSE(relocaliser.relocalise(query, map, scene.stereo, oracle).has_value());
  params.enabled = false;
  Relocaliser disabled(params, optimization, {}, false);
  query.points = &points;
  EXPECT_FALSE(disabled.relocalise(query, map, scene.stereo, oracle).has_value());
}

}  // namespace
}  // namespace vkvo::system
