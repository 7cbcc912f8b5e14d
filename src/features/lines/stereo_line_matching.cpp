#include "features/lines/stereo_line_matching.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace vkvo::features {
namespace {

constexpr float kNoCorrelation = -2.0f;
constexpr int kMaxRows = 64;  // rows sampled per strip: enough for the statistic, bounded cost for long lines

// x of the segment's supporting line at row y (the segment is not horizontal).
float x_at_row(const LineSegment& s, float y) {
  return s.p0.x() + (y - s.p0.y()) * (s.p1.x() - s.p0.x()) / (s.p1.y() - s.p0.y());
}

float row_extent(const LineSegment& s) { return std::abs(s.p1.y() - s.p0.y()); }

// Bilinear sample of an 8-bit grey image; nullopt outside it.
std::optional<float> sample(const cv::Mat& image, float x, float y) {
  if (!(x >= 0.0f && y >= 0.0f && x < static_cast<float>(image.cols - 1) && y < static_cast<float>(image.rows - 1)))
    return std::nullopt;
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
  const auto* row0 = image.ptr<std::uint8_t>(y0);
  const auto* row1 = image.ptr<std::uint8_t>(y0 + 1);
  const float top = (1.0f - fx) * row0[x0] + fx * row0[x0 + 1];
  const float bottom = (1.0f - fx) * row1[x0] + fx * row1[x0 + 1];
  return (1.0f - fy) * top + fy * bottom;
}

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
  double sum_a = 0, sum_b = 0, sum_aa = 0, sum_bb = 0, sum_ab = 0;
  int n = 0;
  for (int i = 0; i < row_count; ++i) {
    const float y = rows.first + row_step * static_cast<float>(i);
    const float xa = x_at_row(a, y), xb = x_at_row(b, y);
    for (int o = -half_width; o <= half_width; ++o) {
      const auto va = sample(left.image, xa + static_cast<float>(o), y);
      const auto vb = sample(right.image, xb + static_cast<float>(o), y);
      if (!va || !vb) continue;
      sum_a += *va;
      sum_b += *vb;
      sum_aa += *va * *va;
      sum_bb += *vb * *vb;
      sum_ab += *va * *vb;
      ++n;
    }
  }
  if (n < 3 * (2 * half_width + 1)) return kNoCorrelation;
  const double var_a = sum_aa - sum_a * sum_a / n, var_b = sum_bb - sum_b * sum_b / n;
  constexpr double kFlat = 1e-6;  // per sample, in squared grey levels: a strip without an edge
  if (var_a <= kFlat * n || var_b <= kFlat * n) return kNoCorrelation;
  return static_cast<float>((sum_ab - sum_a * sum_b / n) / std::sqrt(var_a * var_b));
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
  const auto at = [&](std::size_t l, std::size_t r) { return score[l * right_count + r]; };
  // The best score of left line l over the right lines other than `except`, and of right line r likewise.
  const auto best_of_left = [&](std::size_t l, std::size_t except) {
    float best = kNoCorrelation;
    for (std::size_t r = 0; r < right_count; ++r)
      if (r != except) best = std::max(best, at(l, r));
    return best;
  };
  const auto best_of_right = [&](std::size_t r, std::size_t except) {
    float best = kNoCorrelation;
    for (std::size_t l = 0; l < left_count; ++l)
      if (l != except) best = std::max(best, at(l, r));
    return best;
  };
  // Scores stay as computed, so a pair taken here does not change the next line's decision.
  for (std::size_t l = 0; l < left_count; ++l) {
    if (partner[l] >= 0 || right_count == 0) continue;
    std::size_t r = 0;
    for (std::size_t k = 1; k < right_count; ++k)
      if (at(l, k) > at(l, r)) r = k;
    const float s = at(l, r);
    if (s < params.min_zncc) continue;
    if (s - best_of_left(l, r) >= params.min_margin && s - best_of_right(r, l) >= params.min_margin)
      partner[l] = static_cast<int>(r);
  }
}

}  // namespace vkvo::features
