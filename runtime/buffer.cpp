#include "runtime/buffer.hpp"

#include <cstring>

#include <fmt/format.h>

#include "runtime/context.hpp"

namespace vkvo::rt {
namespace {

constexpr vk::BufferUsageFlags kUsage = vk::BufferUsageFlagBits::eStorageBuffer |
                                        vk::BufferUsageFlagBits::eUniformTexelBuffer |
                                        vk::BufferUsageFlagBits::eTransferSrc | vk::BufferUsageFlagBits::eTransferDst;

void check_range(const Buffer& buffer, std::size_t bytes, std::size_t offset, const char* what) {
  if (offset + bytes > buffer.size())
    throw VulkanError(fmt::format("{} of {} bytes at offset {} overruns buffer '{}' of {} bytes", what, bytes, offset,
                                  buffer.name(), buffer.size()));
}

}  // namespace

Buffer::Buffer(const Context& context, std::size_t bytes, BufferKind kind, std::string name)
    : context_(&context), bytes_(bytes), name_(std::move(name)) {
  // Vulkan forbids zero-sized buffers; empty tensors (0 keypoints) still get a valid binding.
  const std::size_t alloc_bytes = std::max<std::size_t>(bytes, 16);
  buffer_ =
      context.device().createBuffer({.size = alloc_bytes, .usage = kUsage, .sharingMode = vk::SharingMode::eExclusive});
  const auto requirements = buffer_.getMemoryRequirements();

  using M = vk::MemoryPropertyFlagBits;
  std::optional<std::uint32_t> type;
  if (kind == BufferKind::staging) {
    type = context.find_memory_type(requirements.memoryTypeBits, M::eHostVisible | M::eHostCoherent | M::eHostCached);
    if (!type) type = context.find_memory_type(requirements.memoryTypeBits, M::eHostVisible | M::eHostCoherent);
  } else if (context.caps().unified_memory) {
    type = context.find_memory_type(requirements.memoryTypeBits, M::eDeviceLocal | M::eHostVisible | M::eHostCoherent);
  }
  if (!type) type = context.find_memory_type(requirements.memoryTypeBits, M::eDeviceLocal);
  if (!type) throw VulkanError(fmt::format("no memory type for buffer '{}'", name_));

  try {
    memory_ = context.device().allocateMemory({.allocationSize = requirements.size, .memoryTypeIndex = *type});
  } catch (const vk::SystemError& e) {
    throw VulkanError(fmt::format("allocating {} bytes for buffer '{}' failed: {}", alloc_bytes, name_, e.what()));
  }
  buffer_.bindMemory(*memory_, 0);
  const auto properties = context.physical_device().getMemoryProperties().memoryTypes[*type].propertyFlags;
  // Device buffers are mapped only on unified memory: ContextOptions::use_unified_memory = false keeps lavapipe's
  // host-visible memory unmapped, so that the staging path runs there too.
  const bool map = kind == BufferKind::staging || context.caps().unified_memory;
  if (map && (properties & M::eHostVisible)) mapped_ = memory_.mapMemory(0, VK_WHOLE_SIZE);
}

Buffer::~Buffer() = default;
Buffer::Buffer(Buffer&&) noexcept = default;
Buffer& Buffer::operator=(Buffer&&) noexcept = default;

void Buffer::upload(const void* data, std::size_t bytes, std::size_t offset) {
  check_range(*this, bytes, offset, "upload");
  if (bytes == 0) return;
  if (mapped_) {
    std::memcpy(static_cast<std::byte*>(mapped_) + offset, data, bytes);
    return;
  }
  std::unique_ptr<Buffer> temporary;
  Buffer& staging = staging_for(bytes, temporary);
  staging.upload(data, bytes);
  context_->run_once([&](const vk::raii::CommandBuffer& cmd) {
    cmd.copyBuffer(staging.handle(), handle(), vk::BufferCopy{.srcOffset = 0, .dstOffset = offset, .size = bytes});
  });
}

void Buffer::download(void* data, std::size_t bytes, std::size_t offset) const {
  check_range(*this, bytes, offset, "download");
  if (bytes == 0) return;
  if (mapped_) {
    std::memcpy(data, static_cast<const std::byte*>(mapped_) + offset, bytes);
    return;
  }
  std::unique_ptr<Buffer> temporary;
  const Buffer& staging = staging_for(bytes, temporary);
  context_->run_once([&](const vk::raii::CommandBuffer& cmd) {
    cmd.copyBuffer(handle(), staging.handle(), vk::BufferCopy{.srcOffset = offset, .dstOffset = 0, .size = bytes});
  });
  staging.download(data, bytes);
}

Buffer& Buffer::staging_for(std::size_t bytes, std::unique_ptr<Buffer>& temporary) const {
  ++transfers_;
  if (!staging_ && transfers_ >= 2)
    staging_ = std::make_unique<Buffer>(*context_, bytes_, BufferKind::staging, name_ + ".staging");
  if (staging_) return *staging_;
  temporary = std::make_unique<Buffer>(*context_, bytes, BufferKind::staging, name_ + ".staging");
  return *temporary;
}

void Buffer::fill_zero() {
  if (mapped_) {
    std::memset(mapped_, 0, bytes_);
    return;
  }
  context_->run_once([&](const vk::raii::CommandBuffer& cmd) { cmd.fillBuffer(handle(), 0, VK_WHOLE_SIZE, 0); });
}

}  // namespace vkvo::rt
