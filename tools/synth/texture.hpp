#pragma once
// Albedo textures of planar surface patches: 8-bit, with a box-filtered mip pyramid so that a pixel samples the
// texture over its own footprint (mip-mapped bilinear filtering) and distant surfaces do not alias.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace vkvo::synth {

class Texture {
 public:
  // `albedo` is CV_8UC1 covering the patch; texel (0, 0) is at surface coordinates (0, 0) metres, texel i spans
  // [i, i + 1) / texels_per_meter.
  Texture(const cv::Mat& albedo, double texels_per_meter);
  static Texture constant(double albedo);  // a uniform surface (albedo in [0, 1])

  // Albedo in [0, 1] at surface coordinates (u, v) metres, filtered over a square footprint of `footprint` metres.
  float sample(float u, float v, float footprint) const {
    float level = 0.f;
    const float texels = footprint * tpm_;
    if (texels > 1.f) level = std::min(fast_log2(texels), static_cast<float>(levels_.size() - 1));
    const int l0 = static_cast<int>(level);
    // "Brilinear": one bilinear lookup when the level is within 1/4 of an integer, a blend of the two levels only
    // in between. Continuous in the level (no seams), and half the texel reads of full trilinear on average.
    const float w = std::clamp((level - static_cast<float>(l0) - 0.25f) * 2.f, 0.f, 1.f);
    if (w <= 0.f || l0 + 1 >= static_cast<int>(levels_.size())) return bilinear(levels_[l0], u, v);
    if (w >= 1.f) return bilinear(levels_[l0 + 1], u, v);
    const float a = bilinear(levels_[l0], u, v);
    return a + w * (bilinear(levels_[l0 + 1], u, v) - a);
  }

  // 1 / sqrt(x) to ~0.2% (bit trick + one Newton step): footprints need no more.
  static float inv_sqrt(float x) {
    const float y = std::bit_cast<float>(0x5f3759dfu - (std::bit_cast<uint32_t>(x) >> 1));
    return y * (1.5f - 0.5f * x * y * y);
  }

  double texels_per_meter() const { return tpm_; }
  const cv::Mat& level(int i) const { return mats_[i]; }
  int level_count() const { return static_cast<int>(levels_.size()); }

 private:
  struct Level {
    const uint8_t* data;
    int width, height;
    size_t stride;
    float scale;  // texels of this level per metre
  };

  static float fast_log2(float x) {                // log2 to ~5e-3 for normal x > 0: plenty for choosing a mip level
    const auto bits = std::bit_cast<uint32_t>(x);  // x = (1 + m) * 2^e
    const auto e = static_cast<float>(static_cast<int>(bits >> 23) - 127);
    const float m = static_cast<float>(bits & 0x7fffffu) * (1.f / 8388608.f);
    return e + m * (4.f / 3.f - m / 3.f);
  }

  static float bilinear(const Level& l, float u, float v) {
    const float x = std::clamp(u * l.scale - 0.5f, 0.f, static_cast<float>(l.width - 1));
    const float y = std::clamp(v * l.scale - 0.5f, 0.f, static_cast<float>(l.height - 1));
    const int x0 = std::min(static_cast<int>(x), l.width - 2 < 0 ? 0 : l.width - 2);
    const int y0 = std::min(static_cast<int>(y), l.height - 2 < 0 ? 0 : l.height - 2);
    const int dx = l.width > 1 ? 1 : 0;
    const size_t dy = l.height > 1 ? l.stride : 0;
    const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
    const uint8_t* p = l.data + static_cast<size_t>(y0) * l.stride + x0;
    const float top = p[0] + fx * (static_cast<float>(p[dx]) - p[0]);
    const float bottom = p[dy] + fx * (static_cast<float>(p[dy + dx]) - p[dy]);
    return (top + fy * (bottom - top)) * (1.f / 255.f);
  }

  void index_levels();

  std::vector<cv::Mat> mats_;
  std::vector<Level> levels_;
  float tpm_ = 1.f;
};

}  // namespace vkvo::synth
