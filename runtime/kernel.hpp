#pragma once
// One compute pipeline: an embedded shader variant + its descriptor layout (N buffers at set 0, bindings
// 0..N-1: storage buffers, or uniform texel buffers where the spec names a texel format), push-constant block
// and specialization constants.
#include <cstdint>
#include <string>
#include <vector>

#include <vulkan/vulkan_raii.hpp>

#include "runtime/precision.hpp"

namespace vkvo::rt {

class Context;

struct KernelSpec {
  std::string op;                       // shader file name without .comp
  Precision precision = Precision::fp32;
  std::uint32_t bindings = 0;           // storage buffers at set 0, bindings 0..bindings-1
  std::uint32_t written_bindings = 0;   // bit i set: binding i is written (drives barrier placement)
  std::uint32_t push_constant_bytes = 0;
  std::vector<std::uint32_t> specialization;  // value of constant_id i (ints, or floats bit-cast)
  // Per binding (may be shorter than `bindings`): eUndefined = storage buffer, else a read-only uniform texel
  // buffer (GLSL textureBuffer) viewed with this format. CPU drivers fetch texels with vector gathers where
  // they load storage buffers one lane at a time, so hot read-only operands are read through texel views.
  std::vector<vk::Format> texel_formats;

  vk::Format texel_format(std::uint32_t binding) const {
    return binding < texel_formats.size() ? texel_formats[binding] : vk::Format::eUndefined;
  }
  vk::DescriptorType descriptor_type(std::uint32_t binding) const {
    return texel_format(binding) == vk::Format::eUndefined ? vk::DescriptorType::eStorageBuffer
                                                           : vk::DescriptorType::eUniformTexelBuffer;
  }
};

class Kernel {
 public:
  Kernel(const Context& context, KernelSpec spec);

  const KernelSpec& spec() const { return spec_; }
  bool writes(std::uint32_t binding) const { return (spec_.written_bindings >> binding) & 1u; }
  vk::Pipeline pipeline() const { return *pipeline_; }
  vk::PipelineLayout layout() const { return *layout_; }
  vk::DescriptorSetLayout set_layout() const { return *set_layout_; }

 private:
  KernelSpec spec_;
  vk::raii::DescriptorSetLayout set_layout_{nullptr};
  vk::raii::PipelineLayout layout_{nullptr};
  vk::raii::ShaderModule module_{nullptr};
  vk::raii::Pipeline pipeline_{nullptr};
};

}  // namespace vkvo::rt
