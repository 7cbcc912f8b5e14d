#include "runtime/kernel.hpp"

#include <string>

#include <fmt/format.h>

#include "runtime/context.hpp"

namespace vkvo::rt {
namespace {

const EmbeddedShader& checked_shader(const Context& context, const KernelSpec& spec) {
  const std::string name(to_string(spec.op));
  if (spec.precision) context.caps().require(*spec.precision, "shader " + name);
  const EmbeddedShader& shader = find_shader(spec.op, spec.precision);
  if (op_info(spec.op).feature == ShaderFeature::int64 && !context.caps().int64)
    throw VulkanError(fmt::format("shader {} needs shaderInt64, which device '{}' lacks (or was created without)", name,
                                  context.caps().name));
  if (op_info(spec.op).feature == ShaderFeature::cooperative_matrix && !supports_coopmat_kernels(context.caps()))
    throw VulkanError(
        fmt::format("shader {} needs cooperative matrices of shape {} and 16-bit types, which device "
                    "'{}' lacks (or was created without: VKVO_COOPERATIVE_MATRIX=0)",
                    name, to_string(kCoopmatKernelShape), context.caps().name));
  const ShaderInterface& interface = *shader.interface;
  if (spec.specialization.size() > interface.specialization_constants)
    throw VulkanError(fmt::format("shader {} declares {} specialization constants, {} given", name,
                                  interface.specialization_constants, spec.specialization.size()));
  if (spec.texel_formats.size() > interface.binding_count)
    throw VulkanError(fmt::format("shader {}: texel formats for {} bindings, the shader has {}", name,
                                  spec.texel_formats.size(), interface.binding_count));
  for (std::uint32_t b = 0; b < interface.binding_count; ++b) {
    const bool texel = interface.bindings[b].kind == BindingKind::uniform_texel_buffer;
    const vk::Format format = spec.texel_format(b);
    if (texel != (format != vk::Format::eUndefined))
      throw VulkanError(fmt::format("shader {}: binding {} is a {} but {}", name, b,
                                    texel ? "uniform texel buffer" : "storage buffer",
                                    texel ? "no texel format is given for it" : "a texel format is given for it"));
    if (texel && !context.supports_uniform_texel_format(format))
      throw VulkanError(fmt::format("device '{}' cannot read {} through uniform texel buffers ({}, binding {})",
                                    context.caps().name, vk::to_string(format), name, b));
  }
  return shader;
}

}  // namespace

Kernel::Kernel(const Context& context, KernelSpec spec) : spec_(std::move(spec)) {
  const EmbeddedShader& shader = checked_shader(context, spec_);
  interface_ = shader.interface;
  const auto& device = context.device();

  std::vector<vk::DescriptorSetLayoutBinding> bindings;
  for (std::uint32_t b = 0; b < interface_->binding_count; ++b)
    bindings.push_back({.binding = b,
                        .descriptorType = descriptor_type(b),
                        .descriptorCount = 1,
                        .stageFlags = vk::ShaderStageFlagBits::eCompute});
  set_layout_ = device.createDescriptorSetLayout(
      {.bindingCount = static_cast<std::uint32_t>(bindings.size()), .pBindings = bindings.data()});

  const std::uint32_t push_bytes = interface_->push_constant_bytes;
  const vk::PushConstantRange push{.stageFlags = vk::ShaderStageFlagBits::eCompute, .offset = 0, .size = push_bytes};
  const vk::DescriptorSetLayout set_layout = *set_layout_;
  layout_ = device.createPipelineLayout({.setLayoutCount = 1,
                                         .pSetLayouts = &set_layout,
                                         .pushConstantRangeCount = push_bytes ? 1u : 0u,
                                         .pPushConstantRanges = push_bytes ? &push : nullptr});

  const auto words = shader.spirv();
  module_ = device.createShaderModule({.codeSize = words.size_bytes(), .pCode = words.data()});

  std::vector<vk::SpecializationMapEntry> entries;
  for (std::uint32_t i = 0; i < spec_.specialization.size(); ++i)
    entries.push_back({.constantID = i, .offset = i * 4u, .size = 4});
  const vk::SpecializationInfo specialization{.mapEntryCount = static_cast<std::uint32_t>(entries.size()),
                                              .pMapEntries = entries.data(),
                                              .dataSize = spec_.specialization.size() * 4,
                                              .pData = spec_.specialization.data()};
  const vk::ComputePipelineCreateInfo info{
      .stage = {.stage = vk::ShaderStageFlagBits::eCompute,
                .module = *module_,
                .pName = "main",
                .pSpecializationInfo = entries.empty() ? nullptr : &specialization},
      .layout = *layout_};
  pipeline_ = vk::raii::Pipeline(device, context.pipeline_cache(), info);
}

vk::DescriptorType Kernel::descriptor_type(std::uint32_t binding) const {
  return interface_->bindings[binding].kind == BindingKind::uniform_texel_buffer
             ? vk::DescriptorType::eUniformTexelBuffer
             : vk::DescriptorType::eStorageBuffer;
}

}  // namespace vkvo::rt
