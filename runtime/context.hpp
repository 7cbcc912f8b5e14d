#pragma once
// Vulkan instance + device + compute queue, chosen once per process and shared by all kernels and buffers.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <vulkan/vulkan_raii.hpp>

#include "runtime/cooperative_matrix.hpp"
#include "runtime/device_profile.hpp"
#include "runtime/precision.hpp"

namespace vkvo::rt {

// Any failure of the Vulkan runtime: no driver, no device, unsupported feature, allocation failure.
class VulkanError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct MemoryHeap {
  std::uint64_t bytes = 0;
  bool device_local = false;
};

// What a physical device can do, as far as vkvo cares.
struct DeviceCaps {
  std::uint32_t index = 0;  // position in vkEnumeratePhysicalDevices
  std::string name;
  std::string type;  // discrete | integrated | virtual | cpu | other
  std::uint32_t vendor_id = 0, device_id = 0;
  std::uint32_t api_version = 0;
  std::string driver;  // driver name + info where the device reports them
  bool float16_arithmetic = false;
  bool int8_arithmetic = false;
  bool storage_16bit = false;
  bool storage_8bit = false;
  bool int64 = false;  // shaderInt64: 64-bit integer types in shaders
  std::uint32_t subgroup_size = 0;
  bool subgroup_arithmetic = false;
  bool subgroup_ballot = false;   // subgroupBroadcast & co.
  bool subgroup_compute = false;  // subgroup operations are available in compute shaders
  bool timestamps = false;
  double timestamp_period_ns = 0;
  bool unified_memory = false;  // every device-local heap is host visible (lavapipe, Jetson, phones)
  std::uint32_t max_workgroup_invocations = 0;
  std::uint32_t max_shared_memory_bytes = 0;
  std::uint64_t max_storage_buffer_range = 0;
  std::uint32_t max_texel_buffer_elements = 0;
  std::uint64_t min_texel_buffer_offset_alignment = 1;
  std::vector<MemoryHeap> heaps;
  // Which extension runs cooperative matrices here (none unless the device has both its feature and
  // vulkanMemoryModel, which the SPIR-V of every cooperative-matrix shader declares), and the shapes it reports.
  CooperativeMatrixApi cooperative_matrix = CooperativeMatrixApi::none;
  bool vulkan_memory_model = false;
  std::vector<CooperativeMatrixShape> cooperative_matrix_shapes;

  bool supports(Precision p) const;
  bool has_cooperative_matrix_shape(const CooperativeMatrixShape& shape) const;
  // Throws std::runtime_error unless the device supports `p`, naming `user` (e.g. "SuperPoint"), the device, the
  // feature it lacks and the precisions it has.
  void require(Precision p, std::string_view user) const;
};

struct ContextOptions {
  // Device selector: index or case-insensitive name substring. Empty: $VKVO_DEVICE, else the best device
  // (discrete > integrated > virtual > cpu).
  std::string device;
  // Khronos validation layer + messenger. nullopt: on when $VKVO_VALIDATION=1.
  std::optional<bool> validation;
  // Where the on-disk pipeline cache lives. Empty: $VKVO_CACHE_DIR, $XDG_CACHE_HOME/vkvo or ~/.cache/vkvo.
  std::filesystem::path cache_dir;
  bool pipeline_cache = true;
  // false: the device is created without its 16-bit storage and arithmetic features, as on a device that lacks
  // them: only fp32 runs, `auto` precision picks it and an explicit fp16 / fp16s is an error naming the device.
  // For a driver whose 16-bit paths misbehave, and to test what vkvo does on such a device.
  bool use_16bit = true;
  // false: the device is created without shaderInt64, as on a device that lacks it (some mobile GPUs): the kernels
  // that use 64-bit types for wider stores (WinogradConv3x3's wide input transforms) are not created and their
  // 32-bit forms run instead. To test those forms on any device.
  bool use_int64 = true;
  // false: buffers are used as on a discrete GPU even where the device's memory is unified (lavapipe): shaders'
  // buffers are not mapped and every host transfer goes through a staging buffer. To test that path on any device.
  bool use_unified_memory = true;
  // false: the device is created without its cooperative-matrix extension, so the profile keeps every GEMM and
  // convolution on the SIMT kernels. nullopt: on unless $VKVO_COOPERATIVE_MATRIX=0. To compare both paths.
  std::optional<bool> cooperative_matrix;
};

// The caps a Context made with `options` works with: `device`'s, less what the options switch off (16-bit types,
// int64, unified memory, cooperative matrices; cooperative_matrix as resolved from the environment).
DeviceCaps effective_caps(DeviceCaps device, const ContextOptions& options);

// Lists every Vulkan device (throws VulkanError naming the cause when there is no loader, driver or device).
std::vector<DeviceCaps> list_devices();

// Number of validation-layer warnings and errors reported so far in this process (tests assert it stays 0).
std::uint64_t validation_message_count();

class Context {
 public:
  explicit Context(const ContextOptions& options = {});
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  const DeviceCaps& caps() const { return caps_; }
  // Every per-device choice, made once from caps().
  const DeviceProfile& profile() const { return profile_; }
  bool validation_enabled() const { return validation_enabled_; }

  const vk::raii::Device& device() const { return device_; }
  const vk::raii::PhysicalDevice& physical_device() const { return physical_device_; }
  // Whether shaders can read `format` through a uniform texel buffer (textureBuffer).
  bool supports_uniform_texel_format(vk::Format format) const;
  const vk::raii::Queue& queue() const { return queue_; }
  std::uint32_t queue_family() const { return queue_family_; }
  const vk::raii::PipelineCache& pipeline_cache() const { return pipeline_cache_; }

  // A memory type index among `type_bits` having all `required` properties; nullopt if none.
  std::optional<std::uint32_t> find_memory_type(std::uint32_t type_bits, vk::MemoryPropertyFlags required) const;

  // Runs `record` in a one-time command buffer and waits for it (uploads/downloads through staging).
  void run_once(const std::function<void(const vk::raii::CommandBuffer&)>& record) const;

  // Submits one command buffer and waits for `fence`. Thread-safe: Vulkan queues need external
  // synchronisation, and the VO's feature and optimisation stages both run networks.
  void submit_and_wait(vk::CommandBuffer commands, const vk::raii::Fence& fence) const;

  // Writes the pipeline cache to disk now (also done by the destructor).
  void save_pipeline_cache() const;

  // Queue submissions made so far through this context (sequences, uploads, downloads): tests assert how many a
  // network call costs.
  std::uint64_t submission_count() const { return submissions_.load(); }

 private:
  vk::raii::Context loader_;
  vk::raii::Instance instance_{nullptr};
  vk::raii::DebugUtilsMessengerEXT messenger_{nullptr};
  vk::raii::PhysicalDevice physical_device_{nullptr};
  vk::raii::Device device_{nullptr};
  vk::raii::Queue queue_{nullptr};
  vk::raii::CommandPool transfer_pool_{nullptr};
  vk::raii::PipelineCache pipeline_cache_{nullptr};
  std::uint32_t queue_family_ = 0;
  DeviceCaps caps_;
  DeviceProfile profile_;
  bool validation_enabled_ = false;
  std::filesystem::path cache_file_;
  mutable std::mutex queue_mutex_;  // guards queue_ and transfer_pool_
  mutable std::atomic<std::uint64_t> submissions_{0};
};

}  // namespace vkvo::rt
