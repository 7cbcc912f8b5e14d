#include "features/lines/stereo_line_matching.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vkvo::features {
namespace {

constexpr int kMaxRows = 64;  // rows sampled per strip: enough for the statistic, bounded cost for long lines

// x of the segment's supporting line at row y (the segment is not horizontal).
float x_at_row(const LineSegment& s, float y) {
  return s.p0.x() + (y - s.p0.y()) * (s.p1.x() - s.p0.x()) / (s.p1.y() - s.p0.y());
}

float row_extent(const LineSegment& s) { return std::abs(s.p1.y() - s.p0.y()); }

struct RowSpan {
  float first = 0.0f, last = 0.0f;
  float length() const { return last - first; }
};

// The rows both segments span.
RowSpan common_rows(const LineSegment& a, const LineSegment& b) {
  return {std::max(std::min(a.p0.y(), a.p1.y()), std::min(b.p0.y(), b.p1.y())),
          std::min(std::max(a.p0.y(), a.p1.y()), std::max(b.p0.y(), b.p1.y()))};
}

// The row and disparity gates of a left-right pair.
bool passes_gates(const LineSegment& left, const LineSegment& right, const DisparityRange& disparity,
                  const StereoLineMatchParams& params) {
  if (row_extent(left) < params.min_rows || row_extent(right) < params.min_rows) return false;
  const RowSpan rows = common_rows(left, right);
  if (rows.length() < params.min_row_overlap * std::max(row_extent(left), row_extent(right))) return false;
  for (const float y : {rows.first, rows.last}) {
    const double d = x_at_row(left, y) - x_at_row(right, y);
    if (d < disparity.min || d > disparity.max) return false;
  }
  return true;
}

}  // namespace

float strip_correlation(const ImageLines& left, int left_line, const ImageLines& right, int right_line,
                        int half_width) {
  const LineSegment& a = left.segments[static_cast<std::size_t>(left_line)];
  const LineSegment& b = right.segments[static_cast<std::size_t>(right_line)];
  const RowSpan rows = common_rows(a, b);
  if (rows.length() < 2.0f || a.p0.y() == a.p1.y() || b.p0.y() == b.p1.y()) return kNoCorrelation;
  const int row_count = std::min(kMaxRows, static_cast<int>(rows.length()) + 1);
  const float row_step = rows.length() / static_cast<float>(row_count - 1);
  StripSamples strip;  // across the line along the rows, as the disparity shifts it
  for (int i = 0; i < row_count; ++i) {
    const float y = rows.first + row_step * static_cast<float>(i);
    strip.along_a.emplace_back(x_at_row(a, y), y);
    strip.along_b.emplace_back(x_at_row(b, y), y);
  }
  return strip_zncc(left.image, right.image, strip, half_width);
}

void add_stereo_partners_by_appearance(const ImageLines& left, const ImageLines& right, const DisparityRange& disparity,
                                       const StereoLineMatchParams& params, std::vector<int>& partner) {
  if (left.image.type() != CV_8UC1 || right.image.type() != CV_8UC1)
    throw std::invalid_argument("add_stereo_partners_by_appearance: 8-bit grey images expected");
  if (partner.size() != left.segments.size())
    throw std::invalid_argument("add_stereo_partners_by_appearance: partner must be sized like the left lines");
  const std::size_t left_count = left.segments.size(), right_count = right.segments.size();
  std::vector<bool> right_taken(right_count, false);
  for (const int r : partner)
    if (r >= 0 && static_cast<std::size_t>(r) < right_count) right_taken[static_cast<std::size_t>(r)] = true;

  // Correlations of the gated pairs between unpaired lines; kNoCorrelation elsewhere.
  std::vector<float> score(left_count * right_count, kNoCorrelation);
  for (std::size_t l = 0; l < left_count; ++l) {
    if (partner[l] >= 0) continue;
    for (std::size_t r = 0; r < right_count; ++r)
      if (!right_taken[r] && passes_gates(left.segments[l], right.segments[r], disparity, params))
        score[l * right_count + r] =
            strip_correlation(left, static_cast<int>(l), right, static_cast<int>(r), params.half_width);
  }
  assign_clear_winners(score, left_count, right_count, params.min_zncc, params.min_margin, partner);
}

}  // namespace vkvo::features
