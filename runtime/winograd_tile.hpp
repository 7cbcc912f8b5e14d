#pragma once
// The output tile of Winograd's F(m x m, 3x3) (runtime/winograd.hpp), on its own so that configuration code can
// name it without the Vulkan headers.
#include <cstdint>

namespace vkvo::rt {

// Output pixels per tile side: F(4x4, 3x3) or F(6x6, 3x3).
enum class WinogradTile : std::uint32_t { f43 = 4, f63 = 6 };

}  // namespace vkvo::rt
