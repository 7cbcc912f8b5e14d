#pragma once
// Counter-based noise: the value for a pixel is a hash of (stream, index), so images are reproducible for a seed
// whatever the order or threading in which pixels are computed.
#include <cstdint>

namespace vkvo::synth {

inline uint64_t hash64(uint64_t x) {  // splitmix64 finaliser
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// A stream per (seed, frame, camera); pixel (x, y) then draws hash64(hash64(stream + y) + x).
inline uint64_t noise_stream(uint64_t seed, int frame, int camera) {
  return hash64(hash64(seed) ^ (static_cast<uint64_t>(frame) << 1 | static_cast<uint64_t>(camera & 1)));
}

// Approximately standard normal from one hash: the sum of four 16-bit uniforms (Irwin-Hall, variance 4/12),
// rescaled to unit variance. Tails end at +-3.46 sigma, which is all a sensor-noise model needs.
inline float standard_normal(uint64_t h) {
  float sum = 0.f;
  for (int i = 0; i < 4; ++i, h >>= 16) sum += static_cast<float>(h & 0xffff) * (1.f / 65536.f);
  return (sum - 2.f) * 1.7320508f;  // sqrt(12 / 4)
}

}  // namespace vkvo::synth
