#pragma once
// A recorded list of dispatches and copies, submitted as one command buffer. Barriers are inserted only where
// a later command touches a buffer an earlier one wrote (or writes one it read), so independent dispatches may
// overlap. Every command gets a GPU timestamp when the device supports them.
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include <vulkan/vulkan_raii.hpp>

namespace vkvo::rt {

class Context;
class Buffer;
class Kernel;

// A buffer (or a byte range of one) bound to the next binding slot of a kernel.
struct Binding {
  Binding(const Buffer& b, std::size_t offset_bytes = 0, std::size_t range_bytes = VK_WHOLE_SIZE)
      : buffer(&b), offset(offset_bytes), range(range_bytes) {}
  const Buffer* buffer;
  std::size_t offset;
  std::size_t range;
};

struct Groups {
  std::uint32_t x = 1, y = 1, z = 1;
};

// Workgroups needed to cover `items` with `per_group` items each.
inline constexpr std::uint32_t groups_for(std::size_t items, std::size_t per_group) {
  return static_cast<std::uint32_t>((items + per_group - 1) / per_group);
}

struct CommandTiming {
  std::string label;
  double ms = 0;
};

class Sequence {
 public:
  // A GPU timestamp after each of the first `max_timed_commands` commands, where the device has timestamps; 0
  // records none. They are not free: lavapipe flushes its context at each one (docs/performance-history.md,
  // "Device defaults"), so sequences of many short dispatches take them only to profile.
  explicit Sequence(const Context& context, std::uint32_t max_timed_commands = 512);
  ~Sequence();
  Sequence(const Sequence&) = delete;
  Sequence& operator=(const Sequence&) = delete;

  // Starts recording, discarding what was recorded before.
  void begin();
  void dispatch(const Kernel& kernel, std::span<const Binding> bindings, const void* push, std::size_t push_bytes,
                Groups groups, std::string label = {});
  template <class Push>
  void dispatch(const Kernel& kernel, std::initializer_list<Binding> bindings, const Push& push, Groups groups,
                std::string label = {}) {
    dispatch(kernel, std::span<const Binding>(bindings.begin(), bindings.size()), &push, sizeof(Push), groups,
             std::move(label));
  }
  void copy(const Buffer& src, const Buffer& dst, std::size_t bytes, std::size_t src_offset = 0,
            std::size_t dst_offset = 0, std::string label = "copy");
  void fill_zero(const Buffer& buffer, std::string label = "fill");
  // Ends recording; results become visible to the host after submit().
  void end();
  // Submits what was recorded and waits. May be called any number of times after end().
  void submit();

  // Per-command GPU time of the last submit (empty when the device has no timestamps).
  std::vector<CommandTiming> timings() const;
  double gpu_ms() const;  // sum of timings()
  std::size_t command_count() const { return labels_.size(); }

 private:
  enum class Access { read, write };
  void track(vk::Buffer buffer, Access access);
  void flush_hazards();
  void timestamp_after(std::string label);

  const Context* context_;
  vk::raii::CommandPool pool_{nullptr};
  vk::raii::CommandBuffer cmd_{nullptr};
  vk::raii::Fence fence_{nullptr};
  vk::raii::QueryPool queries_{nullptr};
  std::uint32_t max_queries_ = 0;
  std::vector<vk::raii::DescriptorPool> descriptor_pools_;
  std::vector<vk::raii::DescriptorSet> descriptor_sets_;
  std::vector<vk::raii::BufferView> buffer_views_;  // texel views of the recorded dispatches
  std::uint32_t sets_in_current_pool_ = 0;

  // Buffers accessed since the last barrier, and whether they were written.
  std::unordered_map<VkBuffer, Access> pending_;
  std::vector<Access> next_accesses_;
  std::vector<vk::Buffer> next_buffers_;
  std::vector<std::string> labels_;
  std::vector<std::uint64_t> last_timestamps_;
  bool recording_ = false;
  bool recorded_ = false;
};

}  // namespace vkvo::rt
