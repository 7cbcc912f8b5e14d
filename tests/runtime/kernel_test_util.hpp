#pragma once
// Random tensors, precision-aware upload/download and tolerances for the kernel tests.
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "runtime/buffer.hpp"
#include "runtime/half.hpp"

namespace vkvo::test {

inline std::vector<float> random_values(std::size_t n, std::uint32_t seed, float lo = -1.0f, float hi = 1.0f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(lo, hi);
  std::vector<float> v(n);
  for (auto& x : v) x = dist(rng);
  return v;
}

// The values as the device will see them at `precision` (fp16 storage rounds them).
inline std::vector<float> as_stored(const std::vector<float>& v, rt::Precision precision) {
  return rt::decode_storage(rt::encode_storage(v, precision), precision);
}

inline rt::Buffer upload_tensor(const rt::Context& ctx, const std::vector<float>& v, rt::Precision precision) {
  const auto bytes = rt::encode_storage(v, precision);
  rt::Buffer buffer(ctx, bytes.size());
  buffer.upload(bytes.data(), bytes.size());
  return buffer;
}

inline std::vector<float> download_tensor(const rt::Buffer& b, std::size_t count, rt::Precision precision) {
  std::vector<std::byte> bytes(count * rt::storage_bytes(precision));
  b.download(bytes.data(), bytes.size());
  return rt::decode_storage(bytes, precision);
}

// Error bound relative to the largest reference magnitude: fp32 accumulates in fp32 (1e-5 of the scale covers
// summation-order differences over ~1000-term dot products); fp16 storage rounds each output to 11 bits (2^-11);
// fp16 math also rounds products and per-channel partial sums.
inline float tolerance(rt::Precision precision, const std::vector<float>& reference) {
  float scale = 0;
  for (float r : reference) scale = std::max(scale, std::abs(r));
  switch (precision) {
    case rt::Precision::fp32: return 1e-5f * scale + 1e-6f;
    case rt::Precision::fp16s: return 1.5e-3f * scale + 1e-4f;
    case rt::Precision::fp16: return 8e-3f * scale + 1e-3f;
  }
  return 0;
}

// NaN where any difference is NaN (std::max would skip it), so that EXPECT_LE against a tolerance fails.
inline float max_abs_diff(const std::vector<float>& a, const std::vector<float>& b) {
  float m = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const float d = std::abs(a[i] - b[i]);
    if (std::isnan(d)) return d;
    m = std::max(m, d);
  }
  return m;
}

}  // namespace vkvo::test
