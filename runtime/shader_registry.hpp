#pragma once
// The shader table (shaders/CMakeLists.txt) as the binary holds it: every op, the precisions it is compiled for, the
// device feature it needs, and the SPIR-V and reflected interface of each of its variants.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "runtime/precision.hpp"
#include "runtime/shader_interface.hpp"
#include "runtime/shader_op.hpp"  // generated: enum class Op

namespace vkvo::rt {

// Device features a shader variant may need beyond what every Vulkan 1.1 device has (the table's REQUIRES).
enum class ShaderFeature : std::uint8_t {
  none,
  int64,               // shaderInt64 (DeviceCaps::int64)
  cooperative_matrix,  // the tensor-core kernels' shape (supports_coopmat_kernels, DeviceProfile::cooperative_matrix)
};

struct OpInfo {
  const char* name;         // the table's op name
  std::uint8_t precisions;  // bit (1 << Precision) per precision it is compiled for; 0: precision-independent
  ShaderFeature feature;    // what the device must have to run it
  bool per_precision() const { return precisions != 0; }
  bool compiled_for(Precision p) const { return (precisions >> unsigned(p)) & 1u; }
};

struct EmbeddedShader {
  Op op;
  std::optional<Precision> precision;  // nullopt: the one variant of a precision-independent op
  const std::uint32_t* words;
  std::size_t word_count;
  const ShaderInterface* interface;
  std::span<const std::uint32_t> spirv() const { return {words, word_count}; }
};

namespace detail {
std::span<const OpInfo> op_table();                  // generated, indexed by Op
std::span<const EmbeddedShader> embedded_shaders();  // generated
}  // namespace detail

const OpInfo& op_info(Op op);
std::string_view to_string(Op op);
// The variant of `op` at `precision`: a precision for ops compiled per precision, none for the others. Throws
// std::invalid_argument naming the op and what it is compiled for otherwise.
const EmbeddedShader& find_shader(Op op, std::optional<Precision> precision);

}  // namespace vkvo::rt
