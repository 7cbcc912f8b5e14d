#include "system/keyframe_line_matching.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "features/lines/line_appearance.hpp"

namespace vkvo::system {
namespace {

constexpr int kMaxSamples = 64;  // points along a segment: enough for the statistic, bounded cost for long lines

Eigen::Vector2f across(const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
  const Eigen::Vector2d d = (to - from).normalized();
  return Eigen::Vector2f(static_cast<float>(-d.y()), static_cast<float>(d.x()));
}

// The strips along `a` and its transfer onto `b` through the 3D line both see, or nullopt when the transferred
// points cover less than min_overlap of either segment.
std::optional<features::StripSamples> transferred_strip(const geometry::PinholeCamera& camera,
                                                        const geometry::PlueckerLine& L,
                                                        const geometry::LineObservation& a,
                                                        const geometry::LineObservation& b, float min_overlap) {
  const Eigen::Vector2d a0 = a.segment.head<2>(), a1 = a.segment.tail<2>();
  const Eigen::Vector2d b0 = b.segment.head<2>(), b1 = b.segment.tail<2>();
  const double b_length_sq = (b1 - b0).squaredNorm();
  if (!(b_length_sq > 1.0)) return std::nullopt;
  const int count = std::clamp(static_cast<int>((a1 - a0).norm()) + 1, 2, kMaxSamples);
  const Eigen::Isometry3d T_b_world = b.T_world_camera.inverse();
  features::StripSamples strip;
  double along_b_min = 1.0, along_b_max = 0.0;  // where on b the transferred points fall, as a fraction of b
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector2d p = a0 + (a1 - a0) * (static_cast<double>(i) / (count - 1));
    const auto X = geometry::point_on_line_seen_at(L, camera, a.T_world_camera, p);
    if (!X) continue;
    const Eigen::Vector3d X_b = T_b_world * *X;
    if (X_b.z() <= 0.0) continue;
    const Eigen::Vector2d q = camera.project(X_b);
    const double t = (q - b0).dot(b1 - b0) / b_length_sq;
    if (t < 0.0 || t > 1.0) continue;
    along_b_min = std::min(along_b_min, t);
    along_b_max = std::max(along_b_max, t);
    strip.along_a.push_back(p.cast<float>());
    strip.along_b.push_back(q.cast<float>());
  }
  const double covered_a = static_cast<double>(strip.along_a.size()) / count;
  if (covered_a < min_overlap || along_b_max - along_b_min < min_overlap) return std::nullopt;
  // The transfer keeps the order along the line, so both steps across point to the same side of the 3D line.
  strip.across_a = across(strip.along_a.front().cast<double>(), strip.along_a.back().cast<double>());
  strip.across_b = across(strip.along_b.front().cast<double>(), strip.along_b.back().cast<double>());
  return strip;
}

}  // namespace

void add_keyframe_partners_by_appearance(const geometry::PinholeCamera& camera, const KeyframeLineView& here,
                                         const KeyframeLineView& reference,
                                         const geometry::TriangulationParams& triangulation,
                                         const features::KeyframeLineMatchParams& params, std::vector<int>& partner) {
  if (here.image.type() != CV_8UC1 || reference.image.type() != CV_8UC1)
    throw std::invalid_argument("add_keyframe_partners_by_appearance: 8-bit grey images expected");
  const std::size_t rows = here.segments.size(), cols = reference.segments.size();
  if (partner.size() != rows || here.open.size() != rows || reference.open.size() != cols)
    throw std::invalid_argument("add_keyframe_partners_by_appearance: partner and open must be sized like the lines");
  std::vector<bool> taken(cols, false);
  for (const int r : partner)
    if (r >= 0 && static_cast<std::size_t>(r) < cols) taken[static_cast<std::size_t>(r)] = true;

  std::vector<float> score(rows * cols, features::kNoCorrelation);
  for (std::size_t l = 0; l < rows; ++l) {
    if (!here.open[l] || partner[l] >= 0) continue;
    const geometry::LineObservation a{here.T_world_camera, here.segments[l]};
    for (std::size_t r = 0; r < cols; ++r) {
      if (!reference.open[r] || taken[r]) continue;
      const geometry::LineObservation b{reference.T_world_camera, reference.segments[r]};
      const auto L = geometry::triangulate_two_view_line(camera, a, b, triangulation);
      if (!L) continue;
      if (const auto strip = transferred_strip(camera, *L, a, b, params.min_overlap))
        score[l * cols + r] = features::strip_zncc(here.image, reference.image, *strip, params.half_width);
    }
  }
  features::assign_clear_winners(score, rows, cols, params.min_zncc, params.min_margin, partner);
}

}  // namespace vkvo::system
