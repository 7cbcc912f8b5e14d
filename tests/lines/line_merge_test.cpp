// Segment merging: the three merge conditions at their thresholds, the fused geometry against a closed form,
// and the repeat-until-stable loop.
#include <cmath>
#include <random>

#include "common/test_support.hpp"
#include "features/lines/line_merge.hpp"

namespace vkvo::features {
namespace {

LineSegment seg(float x0, float y0, float x1, float y1) { return {{x0, y0}, {x1, y1}}; }

// A segment along direction `angle` through `origin`, from parameter t0 to t1.
LineSegment along(const Eigen::Vector2f& origin, float angle, float t0, float t1, float offset = 0.0f) {
  const Eigen::Vector2f d(std::cos(angle), std::sin(angle));
  const Eigen::Vector2f n(-d.y(), d.x());
  return {origin + t0 * d + offset * n, origin + t1 * d + offset * n};
}

const MergeParams kParams{0.03f, 3.0f, 50.0f};

TEST(LineSegment, CoefficientsAreNormalisedAndGiveDistances) {
  const LineSegment s = seg(10, 10, 40, 50);  // direction (0.6, 0.8)
  const Eigen::Vector3f abc = s.coefficients();
  EXPECT_NEAR(abc.head<2>().norm(), 1.0f, 1e-6f);
  EXPECT_NEAR(abc.dot(Eigen::Vector3f(10, 10, 1)), 0.0f, 1e-5f);
  EXPECT_NEAR(abc.dot(Eigen::Vector3f(40, 50, 1)), 0.0f, 1e-4f);
  // (10,10) + 5 * normal(-0.8, 0.6) is 5 px away.
  EXPECT_NEAR(s.distance_to_line({10 - 4.0f, 10 + 3.0f}), 5.0f, 1e-5f);
  EXPECT_NEAR(s.length(), 50.0f, 1e-5f);
}

TEST(LineMerge, AngleConditionIsStrictAtDeltaTheta) {
  const Eigen::Vector2f o(100, 100);
  const LineSegment base = along(o, 0.3f, 0, 100);
  // Second segment overlaps the first and shares its midpoint, so only the angle decides.
  EXPECT_TRUE(segments_mergeable(
      base, along(o + 50 * Eigen::Vector2f(std::cos(0.3f), std::sin(0.3f)), 0.3f + 0.029f, -40, 40), kParams));
  EXPECT_FALSE(segments_mergeable(
      base, along(o + 50 * Eigen::Vector2f(std::cos(0.3f), std::sin(0.3f)), 0.3f + 0.031f, -40, 40), kParams));
  // Undirected: reversed endpoints are the same line.
  const LineSegment reversed{base.p1, base.p0};
  EXPECT_TRUE(segments_mergeable(base, reversed, kParams));
}

TEST(LineMerge, MidpointDistanceConditionAtDeltaD) {
  const Eigen::Vector2f o(50, 200);
  const LineSegment base = along(o, 1.2f, 0, 120);
  EXPECT_TRUE(segments_mergeable(base, along(o, 1.2f, 60, 150, 2.9f), kParams));
  EXPECT_FALSE(segments_mergeable(base, along(o, 1.2f, 60, 150, 3.1f), kParams));
}

TEST(LineMerge, EndpointGapOnlyMattersWithoutOverlap) {
  const Eigen::Vector2f o(20, 300);
  const LineSegment base = along(o, -0.4f, 0, 100);
  EXPECT_TRUE(segments_mergeable(base, along(o, -0.4f, 149, 200), kParams));   // gap 49 px
  EXPECT_FALSE(segments_mergeable(base, along(o, -0.4f, 151, 200), kParams));  // gap 51 px
  EXPECT_TRUE(segments_mergeable(base, along(o, -0.4f, 90, 300), kParams));    // overlapping, any length
  // Axis-aligned pair: x-projections overlap, so no gap test; far apart in x: gap test rejects.
  EXPECT_TRUE(segments_mergeable(seg(0, 10, 100, 10), seg(50, 11, 400, 11), kParams));
  EXPECT_FALSE(segments_mergeable(seg(0, 10, 100, 10), seg(200, 10, 300, 10), kParams));
}

TEST(LineMerge, FusedSegmentMatchesClosedForm) {
  // Two collinear pieces of y = 0.5 x + 3: the fused segment spans the outermost endpoints.
  const LineSegment a = seg(0, 3, 40, 23);
  const LineSegment b = seg(60, 33, 100, 53);
  const LineSegment m = merge_two_segments(a, b);
  EXPECT_NEAR((m.p0 - Eigen::Vector2f(0, 3)).norm(), 0.0f, 1e-4f);
  EXPECT_NEAR((m.p1 - Eigen::Vector2f(100, 53)).norm(), 0.0f, 1e-4f);

  // Parallel pieces offset by +-1 px, lengths 30 and 90: the fused line passes through the length-weighted centre
  // (offset (30*1 + 90*(-1))/120 = -0.5 px) along the common direction.
  const LineSegment c = seg(0, 1, 30, 1);
  const LineSegment d = seg(40, -1, 130, -1);
  const LineSegment f = merge_two_segments(c, d);
  EXPECT_NEAR(f.p0.y(), -0.5f, 1e-5f);
  EXPECT_NEAR(f.p1.y(), -0.5f, 1e-5f);
  EXPECT_NEAR(f.p0.x(), 0.0f, 1e-4f);
  EXPECT_NEAR(f.p1.x(), 130.0f, 1e-4f);

  // Length-weighted direction: angles 0 and 0.02 rad with lengths 100 and 300 -> 0.015 rad (small-angle mean).
  const LineSegment g = merge_two_segments(along({0, 0}, 0.0f, 0, 100), along({0, 0}, 0.02f, 0, 300));
  const Eigen::Vector2f dir = g.direction();
  EXPECT_NEAR(std::atan2(dir.y(), dir.x()), 0.015f, 2e-5f);
}

TEST(LineMerge, ChainOfPiecesBecomesOneSegment) {
  // A line cut into 8 pieces with 20 px gaps, shuffled and with alternating endpoint order, plus noise.
  std::mt19937 rng(7);
  std::normal_distribution<float> noise(0.0f, 0.2f);
  const Eigen::Vector2f o(30, 40);
  const float angle = 0.7f;
  std::vector<LineSegment> pieces;
  for (int k = 0; k < 8; ++k) {
    LineSegment s = along(o, angle, k * 60.0f, k * 60.0f + 40.0f);
    s.p0 += Eigen::Vector2f(noise(rng), noise(rng));
    s.p1 += Eigen::Vector2f(noise(rng), noise(rng));
    if (k % 2) std::swap(s.p0, s.p1);
    pieces.push_back(s);
  }
  // A parallel line 10 px away and a perpendicular one must stay separate.
  pieces.push_back(along(o, angle, 0, 460, 10.0f));
  pieces.push_back(along(o + Eigen::Vector2f(200, 0), angle + 1.5708f, 0, 100));
  std::shuffle(pieces.begin(), pieces.end(), rng);

  const std::vector<LineSegment> merged = merge_segments(pieces, kParams);
  ASSERT_EQ(merged.size(), 3u);
  int long_ones = 0;
  for (const LineSegment& s : merged) {
    if (s.length() < 400.0f) continue;
    ++long_ones;
    const float offset = along(o, angle, 0, 1).distance_to_line(s.midpoint());
    if (offset < 2.0f) {
      EXPECT_NEAR(s.length(), 460.0f, 1.5f);  // 7 * 60 + 40, within the noise
    }
  }
  EXPECT_EQ(long_ones, 2);
}

TEST(LineMerge, AngleWindowWrapsAroundPi) {
  // Nearly horizontal pieces whose orientations straddle 0/pi (0.005 rad and pi - 0.002 rad) must still merge.
  const std::vector<LineSegment> flat = {seg(0, 100, 100, 100.5f), seg(110, 100.6f, 200, 100.4f)};
  EXPECT_EQ(merge_segments(flat, kParams).size(), 1u);
}

TEST(LineMerge, FilterDropsShortAndDegenerate) {
  std::vector<LineSegment> s = {seg(0, 0, 10, 0), seg(0, 0, 0, 59.9f), seg(0, 0, 60, 0)};
  filter_short_segments(s, 60.0f);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_FLOAT_EQ(s[0].length(), 60.0f);
  EXPECT_TRUE(merge_segments({seg(5, 5, 5, 5)}, kParams).empty());
}

}  // namespace
}  // namespace vkvo::features
