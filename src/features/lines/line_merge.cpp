#include "features/lines/line_merge.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

namespace vkvo::features {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// Undirected orientation in [0, pi).
float orientation(const LineSegment& s) {
  const Eigen::Vector2f d = s.p1 - s.p0;
  float angle = std::atan2(d.y(), d.x());
  if (angle < 0.0f) angle += kPi;
  if (angle >= kPi) angle -= kPi;
  return angle;
}

// Angle between two undirected directions given as unit vectors, in [0, pi/2].
float undirected_angle(const Eigen::Vector2f& da, const Eigen::Vector2f& db) {
  const float cosine = std::min(1.0f, std::abs(da.dot(db)));
  return std::acos(cosine);
}

}  // namespace

bool segments_mergeable(const LineSegment& a, const LineSegment& b, const MergeParams& params) {
  const Eigen::Vector2f da = a.direction();
  const Eigen::Vector2f db = b.direction();
  if (undirected_angle(da, db) >= params.max_angle) return false;

  const float midpoint_distance = std::min(b.distance_to_line(a.midpoint()), a.distance_to_line(b.midpoint()));
  if (midpoint_distance > params.max_midpoint_distance) return false;

  // Overlap of the two intervals along a's direction (positions relative to a.p0).
  const float a_end = a.length();
  const float b0 = (b.p0 - a.p0).dot(da);
  const float b1 = (b.p1 - a.p0).dot(da);
  const float b_min = std::min(b0, b1);
  const float b_max = std::max(b0, b1);
  if (b_min <= a_end && b_max >= 0.0f) return true;

  const float gap = std::min({(a.p0 - b.p0).norm(), (a.p0 - b.p1).norm(), (a.p1 - b.p0).norm(), (a.p1 - b.p1).norm()});
  return gap < params.max_endpoint_gap;
}

LineSegment merge_two_segments(const LineSegment& a, const LineSegment& b) {
  const float la = a.length();
  const float lb = b.length();
  const Eigen::Vector2f da = a.direction();
  Eigen::Vector2f db = b.direction();
  if (da.dot(db) < 0.0f) db = -db;  // same sense before averaging
  Eigen::Vector2f direction = la * da + lb * db;
  direction.normalize();
  const Eigen::Vector2f centre = (la * a.midpoint() + lb * b.midpoint()) / (la + lb);

  float t_min = 0.0f, t_max = 0.0f;
  bool first = true;
  for (const Eigen::Vector2f& p : {a.p0, a.p1, b.p0, b.p1}) {
    const float t = (p - centre).dot(direction);
    t_min = first ? t : std::min(t_min, t);
    t_max = first ? t : std::max(t_max, t);
    first = false;
  }
  return {centre + t_min * direction, centre + t_max * direction};
}

std::vector<LineSegment> merge_segments(std::vector<LineSegment> segments, const MergeParams& params) {
  segments.erase(
      std::remove_if(segments.begin(), segments.end(), [](const LineSegment& s) { return !(s.length() > 1e-6f); }),
      segments.end());
  bool merged_any = true;
  while (merged_any && segments.size() > 1) {
    merged_any = false;
    const size_t n = segments.size();
    std::vector<float> angle(n);
    for (size_t i = 0; i < n; ++i) angle[i] = orientation(segments[i]);
    std::vector<size_t> order(n);
    std::iota(order.begin(), order.end(), size_t{0});
    std::sort(order.begin(), order.end(), [&](size_t i, size_t j) { return angle[i] < angle[j]; });

    // Each segment absorbs the later segments of its angle window (circular over [0, pi)); a pair whose angle
    // window is crossed only after an earlier merge is picked up by the next round.
    std::vector<char> alive(n, 1);
    for (size_t k = 0; k < n; ++k) {
      const size_t i = order[k];
      if (!alive[i]) continue;
      for (size_t step = 1; step < n; ++step) {
        const size_t j = order[(k + step) % n];
        float delta = angle[j] - angle[i];
        if (delta < 0.0f) delta += kPi;
        if (delta >= params.max_angle) break;
        if (!alive[j] || !segments_mergeable(segments[i], segments[j], params)) continue;
        segments[i] = merge_two_segments(segments[i], segments[j]);
        alive[j] = 0;
        merged_any = true;
      }
    }
    std::vector<LineSegment> survivors;
    survivors.reserve(n);
    for (size_t i = 0; i < n; ++i)
      if (alive[i]) survivors.push_back(segments[i]);
    segments = std::move(survivors);
  }
  return segments;
}

void filter_short_segments(std::vector<LineSegment>& segments, float min_length) {
  segments.erase(std::remove_if(segments.begin(), segments.end(),
                                [min_length](const LineSegment& s) { return s.length() < min_length; }),
                 segments.end());
}

}  // namespace vkvo::features
