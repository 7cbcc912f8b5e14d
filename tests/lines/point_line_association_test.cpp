// Point-to-line association (paper eq. 1): the distance and extent boundaries, the "and"/"or" extent rules, and
// the grid implementation against the brute-force reference on random layouts.
#include <random>

#include "common/test_support.hpp"
#include "features/lines/point_line_association.hpp"

namespace vkvo::features {
namespace {

const AssociationParams kParams{};  // 3 px distance, 3 px margin, both extents

TEST(PointLineAssociation, DistanceBoundaryIsStrict) {
  const LineSegment horizontal{{100, 50}, {200, 50}};
  EXPECT_TRUE(point_belongs_to_segment({150, 52.99f}, horizontal, kParams));
  EXPECT_FALSE(point_belongs_to_segment({150, 53.0f}, horizontal, kParams));  // d < 3 is required
  EXPECT_FALSE(point_belongs_to_segment({150, 46.9f}, horizontal, kParams));
  // Oblique line y = x: distance of (x, x + t) is t / sqrt(2).
  const LineSegment diagonal{{0, 0}, {100, 100}};
  EXPECT_TRUE(point_belongs_to_segment({50, 54.2f}, diagonal, kParams));   // 2.97 px
  EXPECT_FALSE(point_belongs_to_segment({50, 54.3f}, diagonal, kParams));  // 3.04 px
}

TEST(PointLineAssociation, ExtentMarginAtSegmentEnds) {
  const LineSegment horizontal{{100, 50}, {200, 50}};
  EXPECT_TRUE(point_belongs_to_segment({97.0f, 50}, horizontal, kParams));  // margin is inclusive
  EXPECT_FALSE(point_belongs_to_segment({96.9f, 50}, horizontal, kParams));
  EXPECT_TRUE(point_belongs_to_segment({203.0f, 51}, horizontal, kParams));
  EXPECT_FALSE(point_belongs_to_segment({203.1f, 51}, horizontal, kParams));
  AssociationParams no_margin = kParams;
  no_margin.extent_margin = 0.0f;
  EXPECT_TRUE(point_belongs_to_segment({100.0f, 50}, horizontal, no_margin));
  EXPECT_FALSE(point_belongs_to_segment({99.9f, 50}, horizontal, no_margin));
  // Without margin the box rule leaves no slack across an axis-aligned segment: the default margin matters.
  EXPECT_FALSE(point_belongs_to_segment({150.0f, 51}, horizontal, no_margin));
}

TEST(PointLineAssociation, PaperOrRuleAcceptsTheExtensionOfAnAxisAlignedSegment) {
  // With the literal "x within x-extent OR y within y-extent", a point on the infinite extension of a horizontal
  // segment passes on y; the default box rule rejects it. Away from the segment ends both rules agree.
  const LineSegment horizontal{{100, 50}, {200, 50}};
  AssociationParams paper = kParams;
  paper.require_both_extents = false;
  EXPECT_TRUE(point_belongs_to_segment({400, 51}, horizontal, paper));
  EXPECT_FALSE(point_belongs_to_segment({400, 51}, horizontal, kParams));
  const LineSegment oblique{{0, 0}, {100, 60}};
  for (const Eigen::Vector2f& p : {Eigen::Vector2f(150, 90), Eigen::Vector2f(50, 31), Eigen::Vector2f(-20, -12)})
    EXPECT_EQ(point_belongs_to_segment(p, oblique, paper), point_belongs_to_segment(p, oblique, kParams));
}

TEST(PointLineAssociation, PointsMayBelongToSeveralLines) {
  // A corner: the point at the shared endpoint belongs to both lines, the others to one each, one to none.
  const std::vector<LineSegment> lines = {{{100, 100}, {300, 100}}, {{100, 100}, {100, 300}}};
  const std::vector<Eigen::Vector2f> points = {{101, 101}, {200, 99}, {99, 250}, {200, 200}};
  const PointLineAssociation a = associate_points_to_lines(points, lines, kParams);
  EXPECT_EQ(a.points_of_line[0], (std::vector<int>{0, 1}));
  EXPECT_EQ(a.points_of_line[1], (std::vector<int>{0, 2}));
  EXPECT_EQ(a.lines_of_point[0], (std::vector<int>{0, 1}));
  EXPECT_EQ(a.lines_of_point[1], (std::vector<int>{0}));
  EXPECT_EQ(a.lines_of_point[2], (std::vector<int>{1}));
  EXPECT_TRUE(a.lines_of_point[3].empty());
}

TEST(PointLineAssociation, EmptyInputs) {
  const std::vector<LineSegment> lines = {{{0, 0}, {10, 0}}};
  const PointLineAssociation no_points = associate_points_to_lines({}, lines, kParams);
  EXPECT_EQ(no_points.line_count(), 1u);
  EXPECT_TRUE(no_points.points_of_line[0].empty());
  const PointLineAssociation no_lines = associate_points_to_lines({{1, 1}}, {}, kParams);
  EXPECT_EQ(no_lines.point_count(), 1u);
  EXPECT_TRUE(no_lines.lines_of_point[0].empty());
}

// Random 752x480 layouts with many points placed on or near lines: grid and brute force must agree exactly.
TEST(PointLineAssociation, GridEqualsBruteForceOnRandomLayouts) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<float> ux(0, 752), uy(0, 480), ut(-0.1f, 1.1f), off(-4, 4), len(5, 400), ang(0, 6.3f);
  for (int trial = 0; trial < 8; ++trial) {
    std::vector<LineSegment> lines;
    for (int l = 0; l < 300; ++l) {
      const Eigen::Vector2f p0(ux(rng), uy(rng));
      const float a = (l % 10 == 0) ? 0.0f : (l % 10 == 1 ? 1.5707964f : ang(rng));  // some axis-aligned
      lines.push_back({p0, p0 + len(rng) * Eigen::Vector2f(std::cos(a), std::sin(a))});
    }
    std::vector<Eigen::Vector2f> points;
    for (int i = 0; i < 400; ++i) {
      if (i % 2) {
        points.emplace_back(ux(rng), uy(rng));
      } else {
        const LineSegment& l = lines[i % lines.size()];
        const Eigen::Vector2f d = l.direction();
        points.push_back(l.p0 + ut(rng) * (l.p1 - l.p0) + off(rng) * Eigen::Vector2f(-d.y(), d.x()));
      }
    }
    for (bool both : {true, false}) {
      AssociationParams params = kParams;
      params.require_both_extents = both;
      for (float cell : {4.0f, 16.0f, 64.0f}) {
        params.grid_cell_size = cell;
        const PointLineAssociation grid = associate_points_to_lines(points, lines, params);
        const PointLineAssociation brute = associate_points_to_lines_brute_force(points, lines, params);
        ASSERT_EQ(grid.points_of_line, brute.points_of_line) << "trial " << trial << " cell " << cell;
        ASSERT_EQ(grid.lines_of_point, brute.lines_of_point);
      }
    }
  }
}

}  // namespace
}  // namespace vkvo::features
