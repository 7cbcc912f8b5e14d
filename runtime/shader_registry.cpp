#include "runtime/shader_registry.hpp"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

namespace vkvo::rt {

std::span<const std::uint32_t> find_shader(std::string_view op, Precision precision) {
  const auto variant = to_string(precision);
  for (const auto& shader : detail::embedded_shaders())
    if (op == shader.op && variant == shader.variant) return {shader.words, shader.word_count};
  throw std::invalid_argument(fmt::format("no embedded shader '{}' ({}); is shaders/{}.comp in the build?", op,
                                          variant, op));
}

std::vector<std::string> shader_ops() {
  std::vector<std::string> ops;
  for (const auto& shader : detail::embedded_shaders())
    if (std::find(ops.begin(), ops.end(), shader.op) == ops.end()) ops.emplace_back(shader.op);
  std::sort(ops.begin(), ops.end());
  return ops;
}

}  // namespace vkvo::rt
