#include "runtime/kernel.hpp"

#include <fmt/format.h>

#include "runtime/context.hpp"
#include "runtime/shader_registry.hpp"

namespace vkvo::rt {

Kernel::Kernel(const Context& context, KernelSpec spec) : spec_(std::move(spec)) {
  context.caps().require(spec_.precision, "shader " + spec_.op);
  const auto words = find_shader(spec_.op, spec_.precision);
  const auto& device = context.device();

  std::vector<vk::DescriptorSetLayoutBinding> bindings;
  for (std::uint32_t b = 0; b < spec_.bindings; ++b) {
    const vk::Format format = spec_.texel_format(b);
    if (format != vk::Format::eUndefined && writes(b))
      throw VulkanError(fmt::format("kernel '{}': binding {} is a read-only texel buffer but marked written", spec_.op, b));
    if (format != vk::Format::eUndefined && !context.supports_uniform_texel_format(format))
      throw VulkanError(fmt::format("device '{}' cannot read {} through uniform texel buffers ({}, binding {})",
                                    context.caps().name, vk::to_string(format), spec_.op, b));
    bindings.push_back({.binding = b, .descriptorType = spec_.descriptor_type(b), .descriptorCount = 1,
                        .stageFlags = vk::ShaderStageFlagBits::eCompute});
  }
  set_layout_ = device.createDescriptorSetLayout(
      {.bindingCount = static_cast<std::uint32_t>(bindings.size()), .pBindings = bindings.data()});

  const vk::PushConstantRange push{.stageFlags = vk::ShaderStageFlagBits::eCompute, .offset = 0,
                                   .size = spec_.push_constant_bytes};
  const vk::DescriptorSetLayout set_layout = *set_layout_;
  layout_ = device.createPipelineLayout({.setLayoutCount = 1, .pSetLayouts = &set_layout,
                                         .pushConstantRangeCount = spec_.push_constant_bytes ? 1u : 0u,
                                         .pPushConstantRanges = spec_.push_constant_bytes ? &push : nullptr});

  module_ = device.createShaderModule({.codeSize = words.size_bytes(), .pCode = words.data()});

  std::vector<vk::SpecializationMapEntry> entries;
  for (std::uint32_t i = 0; i < spec_.specialization.size(); ++i)
    entries.push_back({.constantID = i, .offset = i * 4u, .size = 4});
  const vk::SpecializationInfo specialization{.mapEntryCount = static_cast<std::uint32_t>(entries.size()),
                                              .pMapEntries = entries.data(),
                                              .dataSize = spec_.specialization.size() * 4,
                                              .pData = spec_.specialization.data()};
  const vk::ComputePipelineCreateInfo info{
      .stage = {.stage = vk::ShaderStageFlagBits::eCompute, .module = *module_, .pName = "main",
                .pSpecializationInfo = entries.empty() ? nullptr : &specialization},
      .layout = *layout_};
  pipeline_ = vk::raii::Pipeline(device, context.pipeline_cache(), info);
}

}  // namespace vkvo::rt
