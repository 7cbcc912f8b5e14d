#pragma once
// Line matching through point matches, paper eq. 2: S_mn = N_pm / min(N_m, N_n), where N_pm counts the point
// matches between the points of line m (image A) and of line n (image B), and N_m, N_n are the numbers of points
// associated with each line. Works for frame-to-keyframe and for left-to-right stereo alike.
#include <vector>

#include "features/lines/line_params.hpp"
#include "features/lines/point_line_association.hpp"

namespace vkvo::features {

struct LineMatchCandidate {
  int line_a = -1;
  int line_b = -1;
  int shared = 0;      // N_pm
  float score = 0.0f;  // S_mn
};

// All pairs with N_pm > 0, with their counts and scores (for diagnostics and tests); ordered by line_a, line_b.
std::vector<LineMatchCandidate> line_match_candidates(const PointLineAssociation& a, const PointLineAssociation& b,
                                                      const std::vector<int>& point_matches_a_to_b);

// Per line of A: the index of its line in B, or -1. Accepted pairs pass params.score's test (S > score_threshold,
// or N_pm * S >= score_threshold) and N_pm > shared_threshold; one-to-one, assigned greedily by descending score (ties:
// more shared points, then lower indices). `point_matches_a_to_b[i]` is the index in B of point i of A, -1 when
// unmatched; its size must equal a.point_count(). Throws std::invalid_argument on inconsistent sizes or out-of-range
// indices.
std::vector<int> match_lines(const PointLineAssociation& a, const PointLineAssociation& b,
                             const std::vector<int>& point_matches_a_to_b, const LineMatchParams& params);

}  // namespace vkvo::features
