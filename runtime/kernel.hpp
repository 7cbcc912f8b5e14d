#pragma once
// One compute pipeline: an embedded shader variant (runtime/shader_registry.hpp) + its descriptor set layout, push
// constant range and specialization constants. The bindings (set 0, 0..N-1, storage buffers or uniform texel
// buffers), which of them the shader writes and the push-constant size come from the variant's reflected
// interface, not from the caller.
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include <vulkan/vulkan_raii.hpp>

#include "runtime/precision.hpp"
#include "runtime/shader_registry.hpp"

namespace vkvo::rt {

class Context;

struct KernelSpec {
  Op op;
  // The storage precision of an op compiled per precision (the shader table's PRECISIONS); none for the others.
  std::optional<Precision> precision;
  std::vector<std::uint32_t> specialization;  // value of constant_id i (ints, or floats bit-cast)
  // Per binding (may stop after the last texel binding): the format each uniform texel buffer binding is viewed
  // with, eUndefined for storage buffers. CPU drivers fetch texels with vector gathers where they load storage
  // buffers one lane at a time, so hot read-only operands are read through texel views.
  std::vector<vk::Format> texel_formats;

  vk::Format texel_format(std::uint32_t binding) const {
    return binding < texel_formats.size() ? texel_formats[binding] : vk::Format::eUndefined;
  }
};

class Kernel {
 public:
  // Throws if the device lacks the precision or the feature the variant needs, or if the texel formats do not
  // match the shader's texel bindings.
  Kernel(const Context& context, KernelSpec spec);

  const KernelSpec& spec() const { return spec_; }
  std::string_view name() const { return to_string(spec_.op); }
  const ShaderInterface& interface() const { return *interface_; }
  std::uint32_t bindings() const { return interface_->binding_count; }
  bool writes(std::uint32_t binding) const { return interface_->bindings[binding].write; }
  vk::DescriptorType descriptor_type(std::uint32_t binding) const;
  vk::Pipeline pipeline() const { return *pipeline_; }
  vk::PipelineLayout layout() const { return *layout_; }
  vk::DescriptorSetLayout set_layout() const { return *set_layout_; }

 private:
  KernelSpec spec_;
  const ShaderInterface* interface_;
  vk::raii::DescriptorSetLayout set_layout_{nullptr};
  vk::raii::PipelineLayout layout_{nullptr};
  vk::raii::ShaderModule module_{nullptr};
  vk::raii::Pipeline pipeline_{nullptr};
};

}  // namespace vkvo::rt
