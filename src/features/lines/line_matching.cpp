#include "features/lines/line_matching.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace vkvo::features {

std::vector<LineMatchCandidate> line_match_candidates(const PointLineAssociation& a, const PointLineAssociation& b,
                                                      const std::vector<int>& point_matches_a_to_b) {
  if (point_matches_a_to_b.size() != a.point_count())
    throw std::invalid_argument("match_lines: " + std::to_string(point_matches_a_to_b.size()) + " point matches for " +
                                std::to_string(a.point_count()) + " points of image A");
  const int points_b = static_cast<int>(b.point_count());
  for (int j : point_matches_a_to_b)
    if (j < -1 || j >= points_b)
      throw std::invalid_argument("match_lines: point match index " + std::to_string(j) + " outside [-1, " +
                                  std::to_string(points_b) + ")");

  // Per line of A, count shared point matches with every line of B through a scratch counter (sparse reset).
  std::vector<LineMatchCandidate> candidates;
  std::vector<int> shared(b.line_count(), 0);
  std::vector<int> touched;
  for (size_t m = 0; m < a.line_count(); ++m) {
    for (int i : a.points_of_line[m]) {
      const int j = point_matches_a_to_b[i];
      if (j < 0) continue;
      for (int n : b.lines_of_point[j])
        if (shared[n]++ == 0) touched.push_back(n);
    }
    std::sort(touched.begin(), touched.end());
    for (int n : touched) {
      const size_t smaller = std::min(a.points_of_line[m].size(), b.points_of_line[n].size());
      candidates.push_back({static_cast<int>(m), n, shared[n], static_cast<float>(shared[n]) / smaller});
      shared[n] = 0;
    }
    touched.clear();
  }
  return candidates;
}

std::vector<int> match_lines(const PointLineAssociation& a, const PointLineAssociation& b,
                             const std::vector<int>& point_matches_a_to_b, const LineMatchParams& params) {
  std::vector<LineMatchCandidate> candidates = line_match_candidates(a, b, point_matches_a_to_b);
  if (params.score == LineMatchScore::kAirvo)
    for (LineMatchCandidate& c : candidates) c.score *= static_cast<float>(c.shared);  // N_pm^2 / min(N_m, N_n)
  const auto passes = [&](const LineMatchCandidate& c) {
    if (c.shared <= params.shared_threshold) return false;
    return params.score == LineMatchScore::kAirvo ? c.score >= params.score_threshold
                                                  : c.score > params.score_threshold;
  };
  candidates.erase(std::remove_if(candidates.begin(), candidates.end(), [&](const auto& c) { return !passes(c); }),
                   candidates.end());
  std::sort(candidates.begin(), candidates.end(), [](const LineMatchCandidate& x, const LineMatchCandidate& y) {
    if (x.score != y.score) return x.score > y.score;
    if (x.shared != y.shared) return x.shared > y.shared;
    if (x.line_a != y.line_a) return x.line_a < y.line_a;
    return x.line_b < y.line_b;
  });
  std::vector<int> match_of_a(a.line_count(), -1);
  std::vector<char> b_taken(b.line_count(), 0);
  for (const LineMatchCandidate& c : candidates) {
    if (match_of_a[c.line_a] >= 0 || b_taken[c.line_b]) continue;
    match_of_a[c.line_a] = c.line_b;
    b_taken[c.line_b] = 1;
  }
  return match_of_a;
}

}  // namespace vkvo::features
