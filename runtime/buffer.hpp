#pragma once
// A storage buffer. Device-local with staging copies on discrete GPUs; host-visible and persistently mapped on
// unified-memory devices (lavapipe, Jetson, phones), where uploads and downloads are plain memcpy.
// A device buffer that the host transfers to or from a second time keeps its staging buffer: per-call inputs and
// outputs then cost a copy and a submission, not an allocation each (on a GPU the allocations took more than the
// network: docs/performance-history.md, "Device defaults"); a weight upload, done once, frees its staging at once.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan_raii.hpp>

namespace vkvo::rt {

class Context;

enum class BufferKind {
  device,   // read and written by shaders; host access through staging unless the device is UMA
  staging,  // host-visible, mapped: inputs written by the host each frame and copied in by a Sequence
};

class Buffer {
 public:
  Buffer(const Context& context, std::size_t bytes, BufferKind kind = BufferKind::device, std::string name = {});
  ~Buffer();
  Buffer(Buffer&&) noexcept;
  Buffer& operator=(Buffer&&) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  void upload(const void* data, std::size_t bytes, std::size_t offset = 0);
  void download(void* data, std::size_t bytes, std::size_t offset = 0) const;
  void fill_zero();

  template <class T>
  void upload(std::span<const T> values, std::size_t offset = 0) {
    upload(values.data(), values.size_bytes(), offset);
  }
  template <class T>
  std::vector<T> download(std::size_t count, std::size_t offset = 0) const {
    std::vector<T> values(count);
    download(values.data(), count * sizeof(T), offset);
    return values;
  }

  vk::Buffer handle() const { return *buffer_; }
  std::size_t size() const { return bytes_; }
  const std::string& name() const { return name_; }
  bool host_visible() const { return mapped_ != nullptr; }
  void* mapped() const { return mapped_; }
  // Whether host transfers reuse a staging buffer of this buffer's size (after the second of them).
  bool keeps_staging() const { return staging_ != nullptr; }

 private:
  // The staging buffer for a transfer of `bytes`: the kept one, or a new one kept from the second transfer on, or
  // else a temporary held by `temporary`.
  Buffer& staging_for(std::size_t bytes, std::unique_ptr<Buffer>& temporary) const;

  const Context* context_;
  std::size_t bytes_;
  std::string name_;
  vk::raii::Buffer buffer_{nullptr};
  vk::raii::DeviceMemory memory_{nullptr};
  void* mapped_ = nullptr;
  mutable std::unique_ptr<Buffer> staging_;
  mutable unsigned transfers_ = 0;
};

}  // namespace vkvo::rt
