#include "runtime/shader_registry.hpp"

#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace vkvo::rt {

const OpInfo& op_info(Op op) { return detail::op_table()[static_cast<std::size_t>(op)]; }

std::string_view to_string(Op op) { return op_info(op).name; }

const EmbeddedShader& find_shader(Op op, std::optional<Precision> precision) {
  const OpInfo& info = op_info(op);
  if (info.per_precision() && !precision)
    throw std::invalid_argument(fmt::format("shader {} is compiled per precision: name one", info.name));
  if (!info.per_precision() && precision)
    throw std::invalid_argument(fmt::format("shader {} is compiled once for every precision: name none (got {})",
                                            info.name, to_string(*precision)));
  for (const auto& shader : detail::embedded_shaders())
    if (shader.op == op && shader.precision == precision) return shader;
  std::string compiled;
  for (const Precision p : kAllPrecisions)
    if (info.compiled_for(p)) compiled += (compiled.empty() ? "" : ", ") + std::string(to_string(p));
  throw std::invalid_argument(fmt::format("shader {} has no {} variant: the shader table compiles it for {} only",
                                          info.name, to_string(*precision), compiled));
}

}  // namespace vkvo::rt
