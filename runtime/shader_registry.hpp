#pragma once
// The SPIR-V of every shader variant, embedded in the binary at build time.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "runtime/precision.hpp"

namespace vkvo::rt {

namespace detail {
struct EmbeddedShader {
  const char* op;
  const char* variant;
  const std::uint32_t* words;
  std::size_t word_count;
};
std::span<const EmbeddedShader> embedded_shaders();  // generated table
}  // namespace detail

// The SPIR-V words of shader `op` (file name without .comp) compiled for `precision`; throws if unknown.
std::span<const std::uint32_t> find_shader(std::string_view op, Precision precision);
// Names of all embedded ops, sorted.
std::vector<std::string> shader_ops();

}  // namespace vkvo::rt
