// Line matching through point matches (paper eq. 2) on constructed associations: correct pairs, ambiguous pairs
// resolved one-to-one by score, too few shared points, and input validation.
#include "features/lines/line_matching.hpp"
#include "common/test_support.hpp"

namespace vkvo::features {
namespace {

// Builds an association from per-line point lists (lines_of_point derived).
PointLineAssociation make_association(size_t point_count, const std::vector<std::vector<int>>& points_of_line) {
  PointLineAssociation a;
  a.points_of_line = points_of_line;
  a.lines_of_point.resize(point_count);
  for (size_t l = 0; l < points_of_line.size(); ++l)
    for (int p : points_of_line[l]) a.lines_of_point[p].push_back(static_cast<int>(l));
  return a;
}

const LineMatchParams kParams{0.5f, 1};  // S > 0.5 and at least 2 shared point matches

TEST(LineMatching, CorrectPairsWithPermutedIndices) {
  // A: line 0 = points {0,1,2,3}, line 1 = {4,5,6}. B: line 0 = {10,11,12}, line 1 = {0,1,2,3,9}.
  const PointLineAssociation a = make_association(7, {{0, 1, 2, 3}, {4, 5, 6}});
  const PointLineAssociation b = make_association(13, {{10, 11, 12}, {0, 1, 2, 3, 9}});
  const std::vector<int> point_matches = {0, 1, 2, 3, 10, 11, 12};
  EXPECT_EQ(match_lines(a, b, point_matches, kParams), (std::vector<int>{1, 0}));

  const auto candidates = line_match_candidates(a, b, point_matches);
  ASSERT_EQ(candidates.size(), 2u);
  EXPECT_EQ(candidates[0].line_a, 0);
  EXPECT_EQ(candidates[0].line_b, 1);
  EXPECT_EQ(candidates[0].shared, 4);
  EXPECT_FLOAT_EQ(candidates[0].score, 4.0f / 4.0f);  // min(N_m = 4, N_n = 5)
  EXPECT_FLOAT_EQ(candidates[1].score, 3.0f / 3.0f);
}

TEST(LineMatching, ScoreUsesTheSmallerPointCount) {
  // 3 shared matches; N_m = 10, N_n = 4 -> S = 0.75 passes 0.5; with N_n = 8 -> S = 0.375 fails.
  const PointLineAssociation a = make_association(10, {{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}});
  const std::vector<int> point_matches = {0, 1, 2, -1, -1, -1, -1, -1, -1, -1};
  EXPECT_EQ(match_lines(a, make_association(8, {{0, 1, 2, 3}}), point_matches, kParams), (std::vector<int>{0}));
  EXPECT_EQ(match_lines(a, make_association(8, {{0, 1, 2, 3, 4, 5, 6, 7}}), point_matches, kParams),
            (std::vector<int>{-1}));
  // Thresholds are strict: S = 0.75 is rejected by score_threshold 0.75.
  EXPECT_EQ(match_lines(a, make_association(8, {{0, 1, 2, 3}}), point_matches, LineMatchParams{0.75f, 1}),
            (std::vector<int>{-1}));
}

TEST(LineMatching, AirvoScoreSquaresTheSharedCountAndIncludesTheThreshold) {
  // 3 shared matches, N_m = 10, N_n = 8: the paper's S = 3/8 = 0.375 fails 0.5; AirVO's 3^2/8 = 1.125 passes 0.8.
  const PointLineAssociation a = make_association(10, {{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}});
  const PointLineAssociation b = make_association(8, {{0, 1, 2, 3, 4, 5, 6, 7}});
  const std::vector<int> point_matches = {0, 1, 2, -1, -1, -1, -1, -1, -1, -1};
  EXPECT_EQ(match_lines(a, b, point_matches, kParams), (std::vector<int>{-1}));
  const LineMatchParams airvo{0.8f, 1, LineMatchScore::kAirvo};
  EXPECT_EQ(match_lines(a, b, point_matches, airvo), (std::vector<int>{0}));
  // 2 shared matches with N_n = 5: 2^2/5 = 0.8 sits on the threshold, which AirVO's ">=" accepts; N_n = 6 fails.
  const std::vector<int> two_matches = {0, 1, -1, -1, -1, -1, -1, -1, -1, -1};
  EXPECT_EQ(match_lines(a, make_association(8, {{0, 1, 2, 3, 4}}), two_matches, airvo), (std::vector<int>{0}));
  EXPECT_EQ(match_lines(a, make_association(8, {{0, 1, 2, 3, 4, 5}}), two_matches, airvo), (std::vector<int>{-1}));
}

TEST(LineMatching, TooFewSharedPointsAreRejected) {
  // One shared point gives S = 1 but N_pm = 1 is not > delta_N = 1.
  const PointLineAssociation a = make_association(2, {{0}, {1}});
  const PointLineAssociation b = make_association(2, {{0}, {1}});
  EXPECT_EQ(match_lines(a, b, {0, 1}, kParams), (std::vector<int>{-1, -1}));
  EXPECT_EQ(match_lines(a, b, {0, 1}, LineMatchParams{0.5f, 0}), (std::vector<int>{0, 1}));
}

TEST(LineMatching, AmbiguousPairsResolvedOneToOneByScore) {
  // Two parallel lines in A share points with one line of B (e.g. both lie on the same edge in B).
  // A0 = {0,1,2} (all 3 matched into B0), A1 = {3,4,5,6,7,8} (2 matched into B0, 4 into B1).
  // B0 = {0,1,2,3,4} -> S(A0,B0) = 3/3 = 1, S(A1,B0) = 2/5 = 0.4; B1 = {5,6,7,8} -> S(A1,B1) = 4/4 = 1.
  const PointLineAssociation a = make_association(9, {{0, 1, 2}, {3, 4, 5, 6, 7, 8}});
  const PointLineAssociation b = make_association(9, {{0, 1, 2, 3, 4}, {5, 6, 7, 8}});
  const std::vector<int> identity = {0, 1, 2, 3, 4, 5, 6, 7, 8};
  EXPECT_EQ(match_lines(a, b, identity, kParams), (std::vector<int>{0, 1}));

  // Contested B line: A0 and A1 both score on B0 only; the higher score (A1: 4/4) wins, A0 (3/5) stays unmatched
  // even though it passes the thresholds on its own.
  const PointLineAssociation a2 = make_association(9, {{0, 1, 2, 7, 8}, {3, 4, 5, 6}});
  const PointLineAssociation b2 = make_association(9, {{0, 1, 2, 3, 4, 5, 6}, {}});
  EXPECT_EQ(match_lines(a2, b2, identity, kParams), (std::vector<int>{-1, 0}));

  // Equal scores: more shared points wins (A1: 4/4 beats A0: 2/2 for B0).
  const PointLineAssociation a3 = make_association(6, {{0, 1}, {2, 3, 4, 5}});
  const PointLineAssociation b3 = make_association(6, {{0, 1, 2, 3, 4, 5}});
  const auto m3 = match_lines(a3, b3, {0, 1, 2, 3, 4, 5}, kParams);
  EXPECT_EQ(m3, (std::vector<int>{-1, 0}));
}

TEST(LineMatching, PointsOnSeveralLinesCountForEach) {
  // Point 0 lies on both lines of A (a corner) and on both lines of B.
  const PointLineAssociation a = make_association(5, {{0, 1, 2}, {0, 3, 4}});
  const PointLineAssociation b = make_association(5, {{0, 1, 2}, {0, 3, 4}});
  const auto candidates = line_match_candidates(a, b, {0, 1, 2, 3, 4});
  ASSERT_EQ(candidates.size(), 4u);
  EXPECT_EQ(candidates[1].line_a, 0);
  EXPECT_EQ(candidates[1].line_b, 1);
  EXPECT_EQ(candidates[1].shared, 1);
  EXPECT_EQ(match_lines(a, b, {0, 1, 2, 3, 4}, kParams), (std::vector<int>{0, 1}));
}

TEST(LineMatching, RejectsInconsistentInput) {
  const PointLineAssociation a = make_association(2, {{0, 1}});
  const PointLineAssociation b = make_association(2, {{0, 1}});
  EXPECT_THROW(match_lines(a, b, {0}, kParams), std::invalid_argument);
  EXPECT_THROW(match_lines(a, b, {0, 2}, kParams), std::invalid_argument);
  EXPECT_THROW(match_lines(a, b, {0, -2}, kParams), std::invalid_argument);
  EXPECT_EQ(match_lines(a, b, {-1, -1}, kParams), (std::vector<int>{-1}));
}

}  // namespace
}  // namespace vkvo::features
