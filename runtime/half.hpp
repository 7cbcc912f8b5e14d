#pragma once
// IEEE binary16 conversions for uploading tensors at fp16 storage precision.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "runtime/precision.hpp"

namespace vkvo::rt {

std::uint16_t float_to_half(float value);  // round to nearest even; overflow -> inf; NaN kept
float half_to_float(std::uint16_t bits);

// Values encoded at the storage precision of `precision` (fp32: 4 bytes each, fp16/fp16s: 2 bytes each).
std::vector<std::byte> encode_storage(std::span<const float> values, Precision precision);
std::vector<float> decode_storage(std::span<const std::byte> bytes, Precision precision);

}  // namespace vkvo::rt
