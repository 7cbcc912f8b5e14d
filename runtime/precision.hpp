#pragma once
// Numeric precision variants every shader is compiled to (see cmake/VkvoShaders.cmake and
// shaders/include/precision.glsl).
#include <cstddef>
#include <optional>
#include <string_view>

namespace vkvo::rt {

enum class Precision {
  fp32,   // fp32 storage, fp32 math: devices without 16-bit storage
  fp16s,  // fp16 storage, fp32 math: devices whose fp16 math is emulated (lavapipe)
  fp16,   // fp16 storage, fp16 math, fp32 accumulation where the op needs it: GPUs with fast fp16
};

inline constexpr Precision kAllPrecisions[] = {Precision::fp32, Precision::fp16s, Precision::fp16};

std::string_view to_string(Precision p);
// Accepts "fp32", "fp16s" (alias "fp16-storage") and "fp16"; nullopt otherwise.
std::optional<Precision> parse_precision(std::string_view text);
// Bytes of one stored tensor element.
inline constexpr std::size_t storage_bytes(Precision p) { return p == Precision::fp32 ? 4 : 2; }

}  // namespace vkvo::rt
