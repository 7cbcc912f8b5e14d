// Matching frame lines to the local map's lines by projection (system/map_line_projection.hpp), on exact synthetic
// geometry: a keyframe that mapped five 3D segments, and a frame 0.3 m away that sees them again.
#include <algorithm>
#include <map>
#include <random>

#include <gtest/gtest.h>

#include "geometry/scene.hpp"  // tests/geometry: test_stereo_camera
#include "system/map_line_projection.hpp"
#include "system/vo_config.hpp"

namespace vkvo::system {
namespace {

using geometry::PlueckerLine;

// A keyframe at the origin that mapped `segments` (lines 0..n-1, map lines with their extents) and, optionally,
// map points at `points` seen as `keypoints`, associated with its lines by `line_points`; then a frame at T_frame.
struct MappedLines {
  MappedLines() {
    T_frame.linear() = Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY()).toRotationMatrix();
    T_frame.translation() = Eigen::Vector3d(0.3, -0.05, 0.1);
  }
  void build() {
    map::Frame f;
    for (const auto& [A, B] : segments)
      f.lines.push_back({test::observe_segment(camera, Eigen::Isometry3d::Identity(), A, B), {}});
    for (const Eigen::Vector3d& X : points) f.keypoints.push_back(camera.project(X));
    f.line_points = line_points;
    f.line_points.resize(f.lines.size());
    f.reset_associations();
    keyframe = map.add_keyframe(f).id;
    for (std::size_t k = 0; k < points.size(); ++k) {
      point_of_keypoint.push_back(map.add_point(points[k]));
      map.add_point_observation(point_of_keypoint.back(), keyframe, static_cast<int>(k));
    }
    for (std::size_t i = 0; i < segments.size(); ++i) {
      map_lines.push_back(map.add_line(PlueckerLine::from_points(segments[i].first, segments[i].second)));
      map.add_line_observation(map_lines.back(), keyframe, static_cast<int>(i));
      map.line(map_lines.back())->endpoints = segments[i];
    }
  }
  // The frame's view of segment i, the part [from, to] of it (fractions of its length).
  map::LineFeature seen(int i, double from = 0.0, double to = 1.0) const {
    const auto& [A, B] = segments[static_cast<std::size_t>(i)];
    return {test::observe_segment(camera, T_frame, A + from * (B - A), A + to * (B - A)), {}};
  }
  // `points_of_line`: the frame's keypoints per line; `point_ids`: the map point each tracks.
  std::vector<ProjectedLineMatch> match(const std::vector<map::LineFeature>& lines, std::vector<map::Id> line_ids = {},
                                        std::vector<std::vector<int>> points_of_line = {},
                                        const std::vector<map::Id>& point_ids = {}) const {
    line_ids.resize(lines.size(), map::kInvalidId);
    points_of_line.resize(lines.size());
    return match_lines_by_projection(map, lines_observed_by(map, {keyframe}),
                                     {T_frame, lines, points_of_line, point_ids, line_ids}, camera, params);
  }

  const geometry::PinholeCamera camera = test::test_stereo_camera().camera;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segments = {{{-1.0, -0.5, 4.0}, {-0.6, 0.6, 4.5}},
                                                                       {{0.2, -0.8, 3.0}, {0.5, 0.7, 3.5}},
                                                                       {{1.0, -0.3, 5.0}, {1.2, 0.8, 5.5}},
                                                                       {{-0.3, 0.2, 2.5}, {0.1, 0.9, 2.8}},
                                                                       {{0.6, -0.9, 6.0}, {0.9, -0.2, 6.5}}};
  std::vector<Eigen::Vector3d> points;
  std::vector<std::vector<int>> line_points;
  Eigen::Isometry3d T_frame = Eigen::Isometry3d::Identity();
  map::Map map;
  map::Id keyframe = map::kInvalidId;
  std::vector<map::Id> map_lines, point_of_keypoint;
  LineProjectionParams params;
};

TEST(MapLineProjection, EachUntrackedLineFindsItsMapLine) {
  MappedLines s;
  s.build();
  // The frame sees the segments in another order, partly (70 % of segment 4), with 0.8 px of detector noise.
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.8);
  std::vector<map::LineFeature> lines;
  for (const int i : {3, 0, 4, 1, 2}) lines.push_back(i == 4 ? s.seen(4, 0.1, 0.8) : s.seen(i));
  for (auto& line : lines)
    for (int c = 0; c < 4; ++c) line.left[c] += std::clamp(noise(rng), -2.0, 2.0);
  // Frame line 3 (segment 1) already tracks its map line through the point matches.
  std::vector<map::Id> line_ids(lines.size(), map::kInvalidId);
  line_ids[3] = s.map_lines[1];

  const auto matches = s.match(lines, line_ids);
  ASSERT_EQ(matches.size(), 4u);
  std::map<int, map::Id> found;
  for (const auto& m : matches) {
    found[m.line] = m.map_line;
    EXPECT_EQ(m.support, 0);
    EXPECT_LE(m.distance_px, s.params.max_distance);
  }
  EXPECT_EQ(found.count(3), 0u);  // tracked already
  EXPECT_EQ(found[0], s.map_lines[3]);
  EXPECT_EQ(found[1], s.map_lines[0]);
  EXPECT_EQ(found[2], s.map_lines[4]);
  EXPECT_EQ(found[4], s.map_lines[2]);
}

TEST(MapLineProjection, LinesOffTheProjectionOrOutsideItsExtentStayUnmatched) {
  MappedLines s;
  s.build();
  // Segment 0 seen 5 px to the side (beyond max_distance 3 px): another image line.
  map::LineFeature shifted = s.seen(0);
  shifted.left[0] += 5.0;
  shifted.left[2] += 5.0;
  EXPECT_TRUE(s.match({shifted}).empty());
  // Segment 1's image line beyond its mapped end: [1.2, 2.0] of its length.
  EXPECT_TRUE(s.match({s.seen(1, 1.2, 2.0)}).empty());
  // [0.7, 1.3] shares [0.7, 1.0] with the map line: in the image about half of the shorter extent (perspective
  // shifts it a little), accepted at min_overlap 0.4, refused at 0.6.
  const map::LineFeature partly = s.seen(1, 0.7, 1.3);
  s.params.min_overlap = 0.4;
  EXPECT_EQ(s.match({partly}).size(), 1u);
  s.params.min_overlap = 0.6;
  EXPECT_TRUE(s.match({partly}).empty());
}

TEST(MapLineProjection, PointSupportDecidesBetweenParallelNeighbours) {
  MappedLines s;
  // Map line 5 lies 1 cm beside segment 2 (about 1 px apart in the frame): geometry alone cannot choose. The
  // keyframe associated two keypoints, whose map points the frame tracks, with line 5.
  const Eigen::Vector3d offset(0.01, 0.0, 0.0);
  s.segments.push_back({s.segments[2].first + offset, s.segments[2].second + offset});
  s.points = {{1.05, 0.0, 5.1}, {1.1, 0.3, 5.2}};
  s.line_points.assign(6, {});
  s.line_points[5] = {0, 1};
  s.build();
  const std::vector<map::LineFeature> lines = {s.seen(2)};
  EXPECT_TRUE(s.match(lines).empty());

  // Frame line 0 has keypoints 0-2; 1 and 2 track the map points of the keyframe's keypoints 1 and 0.
  const std::vector<map::Id> point_ids = {map::kInvalidId, s.point_of_keypoint[1], s.point_of_keypoint[0]};
  const auto matches = s.match(lines, {}, {{0, 1, 2}}, point_ids);
  ASSERT_EQ(matches.size(), 1u);
  EXPECT_EQ(matches[0].map_line, s.map_lines[5]);
  EXPECT_EQ(matches[0].support, 2);
}

TEST(MapLineProjection, AMapLineWithoutExtentNeedsPointSupport) {
  MappedLines s;
  s.points = {{-0.1, 0.55, 2.65}};
  s.line_points.assign(5, {});
  s.line_points[3] = {0};
  s.build();
  s.map.line(s.map_lines[3])->endpoints.reset();
  EXPECT_TRUE(s.match({s.seen(3)}).empty());
  const auto matches = s.match({s.seen(3)}, {}, {{0}}, {s.point_of_keypoint[0]});
  ASSERT_EQ(matches.size(), 1u);
  EXPECT_EQ(matches[0].map_line, s.map_lines[3]);
}

TEST(MapLineProjection, ConfigKeysAndTheirRanges) {
  const auto config = [](const std::string& yaml) { return io::Config::from_string(yaml, "test.yaml"); };
  const VoConfig vo =
      load_vo_config(config("lines: {projection: {enabled: true, max_distance: 2.5, min_overlap: 0.25}}\n"));
  EXPECT_TRUE(vo.line_projection.enabled);
  EXPECT_DOUBLE_EQ(vo.line_projection.max_distance, 2.5);
  EXPECT_DOUBLE_EQ(vo.line_projection.min_overlap, 0.25);
  EXPECT_TRUE(load_vo_config(config("lines: {}\n")).line_projection.enabled);  // on by default
  EXPECT_FALSE(load_vo_config(config("lines: {projection: {enabled: false}}\n")).line_projection.enabled);
  for (const char* bad : {"lines: {projection: {min_overlap: 1.5}}\n", "lines: {projection: {max_distance: -1}}\n",
                          "lines: {projection: {max_distanse: 2}}\n", "lines: {projection: 3}\n"})
    EXPECT_THROW(load_vo_config(config(bad)), std::runtime_error) << bad;
}

}  // namespace
}  // namespace vkvo::system
