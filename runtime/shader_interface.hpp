#pragma once
// What a shader variant declares to the host, reflected from its SPIR-V at build time (shaders/gen/spirv_embed.cpp):
// its descriptor bindings at set 0 (0..binding_count-1), each a storage buffer or a uniform texel buffer, and
// whether the shader reads and writes it (GLSL readonly / writeonly); its push-constant block's size; and how many
// specialization constants it declares.
#include <array>
#include <cstdint>

namespace vkvo::rt {

enum class BindingKind : std::uint8_t {
  storage_buffer,        // `buffer` blocks
  uniform_texel_buffer,  // textureBuffer / utextureBuffer, read with texelFetch (shaders/include/texel_buffer.glsl)
};

struct BindingInfo {
  BindingKind kind = BindingKind::storage_buffer;
  bool read = false;
  bool write = false;  // drives barrier placement in a Sequence
};

inline constexpr std::uint32_t kMaxBindings = 16;

struct ShaderInterface {
  std::uint32_t binding_count = 0;
  std::array<BindingInfo, kMaxBindings> bindings{};
  std::uint32_t push_constant_bytes = 0;
  std::uint32_t specialization_constants = 0;  // constant_id 0..n-1
};

}  // namespace vkvo::rt
