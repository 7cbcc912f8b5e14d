#include "features/lines/line_appearance.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>

namespace vkvo::features {
namespace {

// Bilinear sample of an 8-bit grey image; nullopt outside it.
std::optional<float> sample(const cv::Mat& image, const Eigen::Vector2f& at) {
  const float x = at.x(), y = at.y();
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

}  // namespace

float strip_zncc(const cv::Mat& image_a, const cv::Mat& image_b, const StripSamples& strip, int half_width) {
  double sum_a = 0, sum_b = 0, sum_aa = 0, sum_bb = 0, sum_ab = 0;
  int n = 0;
  const std::size_t points = std::min(strip.along_a.size(), strip.along_b.size());
  for (std::size_t i = 0; i < points; ++i) {
    for (int o = -half_width; o <= half_width; ++o) {
      const auto va = sample(image_a, strip.along_a[i] + static_cast<float>(o) * strip.across_a);
      const auto vb = sample(image_b, strip.along_b[i] + static_cast<float>(o) * strip.across_b);
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

void assign_clear_winners(const std::vector<float>& score, std::size_t rows, std::size_t cols, float min_score,
                          float min_margin, std::vector<int>& partner) {
  if (cols == 0) return;
  const auto at = [&](std::size_t r, std::size_t c) { return score[r * cols + c]; };
  const auto best_of_row = [&](std::size_t r, std::size_t except) {
    float best = kNoCorrelation;
    for (std::size_t c = 0; c < cols; ++c)
      if (c != except) best = std::max(best, at(r, c));
    return best;
  };
  const auto best_of_column = [&](std::size_t c, std::size_t except) {
    float best = kNoCorrelation;
    for (std::size_t r = 0; r < rows; ++r)
      if (r != except) best = std::max(best, at(r, c));
    return best;
  };
  for (std::size_t r = 0; r < rows && r < partner.size(); ++r) {
    if (partner[r] >= 0) continue;
    std::size_t c = 0;
    for (std::size_t k = 1; k < cols; ++k)
      if (at(r, k) > at(r, c)) c = k;
    const float s = at(r, c);
    if (s < min_score) continue;
    if (s - best_of_row(r, c) >= min_margin && s - best_of_column(c, r) >= min_margin) partner[r] = static_cast<int>(c);
  }
}

}  // namespace vkvo::features
