#include "runtime/sequence.hpp"

#include <array>

#include <fmt/format.h>

#include "runtime/buffer.hpp"
#include "runtime/context.hpp"
#include "runtime/kernel.hpp"

namespace vkvo::rt {
namespace {

constexpr std::uint32_t kSetsPerPool = 128;
constexpr std::uint32_t kMaxBindingsPerSet = kMaxBindings;  // runtime/shader_interface.hpp
constexpr auto kComputeAndTransfer = vk::PipelineStageFlagBits::eComputeShader | vk::PipelineStageFlagBits::eTransfer;

}  // namespace

Sequence::Sequence(const Context& context, std::uint32_t max_timed_commands) : context_(&context) {
  const auto& device = context.device();
  pool_ = device.createCommandPool(
      {.flags = vk::CommandPoolCreateFlagBits::eResetCommandBuffer, .queueFamilyIndex = context.queue_family()});
  cmd_ = std::move(vk::raii::CommandBuffers(
      device, {.commandPool = *pool_, .level = vk::CommandBufferLevel::ePrimary, .commandBufferCount = 1})[0]);
  fence_ = device.createFence({});
  if (context.caps().timestamps && max_timed_commands > 0) {
    max_queries_ = max_timed_commands + 1;
    queries_ = device.createQueryPool({.queryType = vk::QueryType::eTimestamp, .queryCount = max_queries_});
  }
}

Sequence::~Sequence() = default;

void Sequence::begin() {
  descriptor_sets_.clear();  // freed back to their pools before recording anew
  descriptor_pools_.clear();
  buffer_views_.clear();
  sets_in_current_pool_ = kSetsPerPool;
  pending_.clear();
  labels_.clear();
  last_timestamps_.clear();
  cmd_.reset();
  cmd_.begin({});
  if (max_queries_) {
    cmd_.resetQueryPool(*queries_, 0, max_queries_);
    cmd_.writeTimestamp(vk::PipelineStageFlagBits::eBottomOfPipe, *queries_, 0);
  }
  recording_ = true;
  recorded_ = false;
}

void Sequence::track(vk::Buffer buffer, Access access) {
  next_buffers_.push_back(buffer);
  next_accesses_.push_back(access);
}

// Inserts one global memory barrier if the command about to be recorded reads or writes a buffer written since
// the last barrier, or writes one read since then; then records the command's accesses.
void Sequence::flush_hazards() {
  bool hazard = false;
  for (std::size_t i = 0; i < next_buffers_.size() && !hazard; ++i) {
    const auto it = pending_.find(static_cast<VkBuffer>(next_buffers_[i]));
    if (it == pending_.end()) continue;
    hazard = it->second == Access::write || next_accesses_[i] == Access::write;
  }
  if (hazard) {
    const vk::MemoryBarrier barrier{
        .srcAccessMask = vk::AccessFlagBits::eShaderWrite | vk::AccessFlagBits::eTransferWrite,
        .dstAccessMask = vk::AccessFlagBits::eShaderRead | vk::AccessFlagBits::eShaderWrite |
                         vk::AccessFlagBits::eTransferRead | vk::AccessFlagBits::eTransferWrite};
    cmd_.pipelineBarrier(kComputeAndTransfer, kComputeAndTransfer, {}, barrier, {}, {});
    pending_.clear();
  }
  for (std::size_t i = 0; i < next_buffers_.size(); ++i) {
    auto& state = pending_[static_cast<VkBuffer>(next_buffers_[i])];
    if (next_accesses_[i] == Access::write)
      state = Access::write;
    else if (state != Access::write)
      state = Access::read;
  }
  next_buffers_.clear();
  next_accesses_.clear();
}

void Sequence::timestamp_after(std::string label) {
  labels_.push_back(std::move(label));
  if (max_queries_ && labels_.size() < max_queries_)
    cmd_.writeTimestamp(vk::PipelineStageFlagBits::eBottomOfPipe, *queries_,
                        static_cast<std::uint32_t>(labels_.size()));
}

void Sequence::dispatch(const Kernel& kernel, std::span<const Binding> bindings, const void* push,
                        std::size_t push_bytes, Groups groups, std::string label) {
  if (!recording_) throw VulkanError("Sequence::dispatch outside begin()/end()");
  const auto& spec = kernel.spec();
  if (bindings.size() != kernel.bindings())
    throw VulkanError(
        fmt::format("kernel '{}' takes {} buffers, {} given", kernel.name(), kernel.bindings(), bindings.size()));
  if (push_bytes != kernel.interface().push_constant_bytes)
    throw VulkanError(fmt::format("kernel '{}' takes {} push-constant bytes, {} given", kernel.name(),
                                  kernel.interface().push_constant_bytes, push_bytes));
  if (groups.x == 0 || groups.y == 0 || groups.z == 0) return;  // nothing to do (e.g. zero keypoints)

  if (sets_in_current_pool_ == kSetsPerPool) {
    const std::array<vk::DescriptorPoolSize, 2> sizes{
        vk::DescriptorPoolSize{.type = vk::DescriptorType::eStorageBuffer,
                               .descriptorCount = kSetsPerPool * kMaxBindingsPerSet},
        vk::DescriptorPoolSize{.type = vk::DescriptorType::eUniformTexelBuffer,
                               .descriptorCount = kSetsPerPool * kMaxBindingsPerSet}};
    descriptor_pools_.push_back(
        context_->device().createDescriptorPool({.flags = vk::DescriptorPoolCreateFlagBits::eFreeDescriptorSet,
                                                 .maxSets = kSetsPerPool,
                                                 .poolSizeCount = static_cast<std::uint32_t>(sizes.size()),
                                                 .pPoolSizes = sizes.data()}));
    sets_in_current_pool_ = 0;
  }
  const vk::DescriptorSetLayout set_layout = kernel.set_layout();
  descriptor_sets_.push_back(std::move(vk::raii::DescriptorSets(
      context_->device(),
      {.descriptorPool = *descriptor_pools_.back(), .descriptorSetCount = 1, .pSetLayouts = &set_layout})[0]));
  ++sets_in_current_pool_;
  const vk::DescriptorSet set = *descriptor_sets_.back();

  std::vector<vk::DescriptorBufferInfo> infos;
  std::vector<vk::BufferView> views(bindings.size());
  infos.reserve(bindings.size());
  for (std::uint32_t i = 0; i < bindings.size(); ++i) {
    const auto& b = bindings[i];
    infos.push_back({.buffer = b.buffer->handle(), .offset = b.offset, .range = b.range});
    track(b.buffer->handle(), Access::read);
    if (const vk::Format format = spec.texel_format(i); format != vk::Format::eUndefined) {
      if (b.offset % context_->caps().min_texel_buffer_offset_alignment != 0)
        throw VulkanError(fmt::format(
            "kernel '{}': binding {} of '{}' starts at byte {}, not a multiple of the "
            "device's texel-buffer offset alignment {}",
            kernel.name(), i, b.buffer->name(), b.offset, context_->caps().min_texel_buffer_offset_alignment));
      buffer_views_.push_back(context_->device().createBufferView(
          {.buffer = b.buffer->handle(), .format = format, .offset = b.offset, .range = b.range}));
      views[i] = *buffer_views_.back();
    }
  }
  std::vector<vk::WriteDescriptorSet> writes;
  for (std::uint32_t i = 0; i < infos.size(); ++i) {
    const bool texel = views[i] != vk::BufferView{};
    writes.push_back({.dstSet = set,
                      .dstBinding = i,
                      .descriptorCount = 1,
                      .descriptorType = kernel.descriptor_type(i),
                      .pBufferInfo = texel ? nullptr : &infos[i],
                      .pTexelBufferView = texel ? &views[i] : nullptr});
    if (kernel.writes(i)) next_accesses_[next_accesses_.size() - infos.size() + i] = Access::write;
  }
  context_->device().updateDescriptorSets(writes, {});
  flush_hazards();

  cmd_.bindPipeline(vk::PipelineBindPoint::eCompute, kernel.pipeline());
  cmd_.bindDescriptorSets(vk::PipelineBindPoint::eCompute, kernel.layout(), 0, set, {});
  if (push_bytes)  // the raw entry point: push constants are an untyped byte block here
    cmd_.getDispatcher()->vkCmdPushConstants(*cmd_, kernel.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0,
                                             static_cast<std::uint32_t>(push_bytes), push);
  cmd_.dispatch(groups.x, groups.y, groups.z);
  timestamp_after(label.empty() ? std::string(kernel.name()) : std::move(label));
}

void Sequence::copy(const Buffer& src, const Buffer& dst, std::size_t bytes, std::size_t src_offset,
                    std::size_t dst_offset, std::string label) {
  if (!recording_) throw VulkanError("Sequence::copy outside begin()/end()");
  if (src_offset + bytes > src.size() || dst_offset + bytes > dst.size())
    throw VulkanError(
        fmt::format("copy of {} bytes from '{}' to '{}' overruns a buffer", bytes, src.name(), dst.name()));
  if (bytes == 0) return;
  track(src.handle(), Access::read);
  track(dst.handle(), Access::write);
  flush_hazards();
  cmd_.copyBuffer(src.handle(), dst.handle(),
                  vk::BufferCopy{.srcOffset = src_offset, .dstOffset = dst_offset, .size = bytes});
  timestamp_after(std::move(label));
}

void Sequence::fill_zero(const Buffer& buffer, std::string label) {
  if (!recording_) throw VulkanError("Sequence::fill_zero outside begin()/end()");
  track(buffer.handle(), Access::write);
  flush_hazards();
  cmd_.fillBuffer(buffer.handle(), 0, VK_WHOLE_SIZE, 0);
  timestamp_after(std::move(label));
}

void Sequence::end() {
  if (!recording_) throw VulkanError("Sequence::end without begin()");
  // Make every shader/transfer write visible to host reads (mapped buffers) and to later submissions.
  const vk::MemoryBarrier barrier{
      .srcAccessMask = vk::AccessFlagBits::eShaderWrite | vk::AccessFlagBits::eTransferWrite,
      .dstAccessMask =
          vk::AccessFlagBits::eHostRead | vk::AccessFlagBits::eShaderRead | vk::AccessFlagBits::eTransferRead};
  cmd_.pipelineBarrier(kComputeAndTransfer, vk::PipelineStageFlagBits::eHost | kComputeAndTransfer, {}, barrier, {},
                       {});
  cmd_.end();
  recording_ = false;
  recorded_ = true;
}

void Sequence::submit() {
  if (!recorded_) throw VulkanError("Sequence::submit before end()");
  context_->submit_and_wait(*cmd_, fence_);
  if (max_queries_) {
    const auto count = static_cast<std::uint32_t>(std::min<std::size_t>(labels_.size() + 1, max_queries_));
    auto [result, values] = queries_.getResults<std::uint64_t>(0, count, count * sizeof(std::uint64_t),
                                                               sizeof(std::uint64_t), vk::QueryResultFlagBits::e64);
    if (result == vk::Result::eSuccess) last_timestamps_ = std::move(values);
  }
}

std::vector<CommandTiming> Sequence::timings() const {
  std::vector<CommandTiming> result;
  const double ns_per_tick = context_->caps().timestamp_period_ns;
  for (std::size_t i = 1; i < last_timestamps_.size(); ++i)
    result.push_back(
        {labels_[i - 1], static_cast<double>(last_timestamps_[i] - last_timestamps_[i - 1]) * ns_per_tick * 1e-6});
  return result;
}

double Sequence::gpu_ms() const {
  double total = 0;
  for (const auto& t : timings()) total += t.ms;
  return total;
}

}  // namespace vkvo::rt
