#include "runtime/context.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <iterator>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

namespace vkvo::rt {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
std::atomic<std::uint64_t> g_validation_messages{0};

VKAPI_ATTR VkBool32 VKAPI_CALL on_validation_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                     VkDebugUtilsMessageTypeFlagsEXT /*types*/,
                                                     const VkDebugUtilsMessengerCallbackDataEXT* data, void* /*user*/) {
  if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
    ++g_validation_messages;
    spdlog::error("Vulkan validation: {}", data->pMessage ? data->pMessage : "(no message)");
  }
  return VK_FALSE;
}

std::string env_or_empty(const char* name) {
  const char* value = std::getenv(name);
  return value ? value : "";
}

std::string lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

std::string device_type_name(vk::PhysicalDeviceType type) {
  switch (type) {
    case vk::PhysicalDeviceType::eDiscreteGpu: return "discrete";
    case vk::PhysicalDeviceType::eIntegratedGpu: return "integrated";
    case vk::PhysicalDeviceType::eVirtualGpu: return "virtual";
    case vk::PhysicalDeviceType::eCpu: return "cpu";
    default: return "other";
  }
}

int device_type_rank(const std::string& type) {
  if (type == "discrete") return 4;
  if (type == "integrated") return 3;
  if (type == "virtual") return 2;
  if (type == "cpu") return 1;
  return 0;
}

bool has_extension(const vk::raii::PhysicalDevice& device, const char* name) {
  for (const auto& ext : device.enumerateDeviceExtensionProperties())
    if (std::string_view(ext.extensionName.data()) == name) return true;
  return false;
}

MatrixComponent matrix_component(vk::ComponentTypeNV type) {
  switch (type) {
    case vk::ComponentTypeNV::eFloat16: return MatrixComponent::f16;
    case vk::ComponentTypeNV::eFloat32: return MatrixComponent::f32;
    case vk::ComponentTypeNV::eFloat64: return MatrixComponent::f64;
    case vk::ComponentTypeNV::eSint8: return MatrixComponent::s8;
    case vk::ComponentTypeNV::eSint16: return MatrixComponent::s16;
    case vk::ComponentTypeNV::eSint32: return MatrixComponent::s32;
    case vk::ComponentTypeNV::eSint64: return MatrixComponent::s64;
    case vk::ComponentTypeNV::eUint8: return MatrixComponent::u8;
    case vk::ComponentTypeNV::eUint16: return MatrixComponent::u16;
    case vk::ComponentTypeNV::eUint32: return MatrixComponent::u32;
    case vk::ComponentTypeNV::eUint64: return MatrixComponent::u64;
    default: return MatrixComponent::other;
  }
}

MatrixScope matrix_scope(vk::ScopeNV scope) {
  switch (scope) {
    case vk::ScopeNV::eDevice: return MatrixScope::device;
    case vk::ScopeNV::eWorkgroup: return MatrixScope::workgroup;
    case vk::ScopeNV::eSubgroup: return MatrixScope::subgroup;
    case vk::ScopeNV::eQueueFamily: return MatrixScope::queue_family;
    default: return MatrixScope::other;
  }
}

// VK_NV_cooperative_matrix: its feature, the memory model its shaders declare, and the shapes it reports.
void query_cooperative_matrix(const vk::raii::PhysicalDevice& device, bool api12, DeviceCaps& caps) {
  if (api12 || has_extension(device, VK_KHR_VULKAN_MEMORY_MODEL_EXTENSION_NAME)) {
    auto f = device.getFeatures2<vk::PhysicalDeviceFeatures2, vk::PhysicalDeviceVulkanMemoryModelFeatures>();
    caps.vulkan_memory_model = f.get<vk::PhysicalDeviceVulkanMemoryModelFeatures>().vulkanMemoryModel;
  }
  if (!has_extension(device, VK_NV_COOPERATIVE_MATRIX_EXTENSION_NAME)) return;
  auto f = device.getFeatures2<vk::PhysicalDeviceFeatures2, vk::PhysicalDeviceCooperativeMatrixFeaturesNV>();
  if (!f.get<vk::PhysicalDeviceCooperativeMatrixFeaturesNV>().cooperativeMatrix || !caps.vulkan_memory_model) return;
  caps.cooperative_matrix = CooperativeMatrixApi::nv;
  for (const auto& p : device.getCooperativeMatrixPropertiesNV())
    caps.cooperative_matrix_shapes.push_back({.m = p.MSize,
                                              .n = p.NSize,
                                              .k = p.KSize,
                                              .a = matrix_component(p.AType),
                                              .b = matrix_component(p.BType),
                                              .c = matrix_component(p.CType),
                                              .result = matrix_component(p.DType),
                                              .scope = matrix_scope(p.scope)});
}

std::optional<std::uint32_t> compute_queue_family(const vk::raii::PhysicalDevice& device) {
  const auto families = device.getQueueFamilyProperties();
  // Prefer a compute queue without graphics (dedicated compute engines run beside rendering), else any.
  for (std::uint32_t i = 0; i < families.size(); ++i)
    if ((families[i].queueFlags & vk::QueueFlagBits::eCompute) &&
        !(families[i].queueFlags & vk::QueueFlagBits::eGraphics))
      return i;
  for (std::uint32_t i = 0; i < families.size(); ++i)
    if (families[i].queueFlags & vk::QueueFlagBits::eCompute) return i;
  return std::nullopt;
}

DeviceCaps query_caps(const vk::raii::PhysicalDevice& device, std::uint32_t index) {
  DeviceCaps caps;
  caps.index = index;
  const auto props = device.getProperties();
  caps.name = props.deviceName.data();
  caps.type = device_type_name(props.deviceType);
  caps.vendor_id = props.vendorID;
  caps.device_id = props.deviceID;
  caps.api_version = props.apiVersion;
  caps.max_workgroup_invocations = props.limits.maxComputeWorkGroupInvocations;
  caps.max_shared_memory_bytes = props.limits.maxComputeSharedMemorySize;
  caps.max_storage_buffer_range = props.limits.maxStorageBufferRange;
  caps.max_texel_buffer_elements = props.limits.maxTexelBufferElements;
  caps.min_texel_buffer_offset_alignment = props.limits.minTexelBufferOffsetAlignment;
  caps.timestamp_period_ns = props.limits.timestampPeriod;

  const bool api12 = props.apiVersion >= VK_API_VERSION_1_2;
  const bool has_f16i8 = api12 || has_extension(device, VK_KHR_SHADER_FLOAT16_INT8_EXTENSION_NAME);
  const bool has_8bit = api12 || has_extension(device, VK_KHR_8BIT_STORAGE_EXTENSION_NAME);

  auto features = device.getFeatures2<vk::PhysicalDeviceFeatures2, vk::PhysicalDevice16BitStorageFeatures>();
  caps.storage_16bit = features.get<vk::PhysicalDevice16BitStorageFeatures>().storageBuffer16BitAccess;
  caps.int64 = features.get<vk::PhysicalDeviceFeatures2>().features.shaderInt64;
  if (has_f16i8) {
    auto f = device.getFeatures2<vk::PhysicalDeviceFeatures2, vk::PhysicalDeviceShaderFloat16Int8Features>();
    caps.float16_arithmetic = f.get<vk::PhysicalDeviceShaderFloat16Int8Features>().shaderFloat16;
    caps.int8_arithmetic = f.get<vk::PhysicalDeviceShaderFloat16Int8Features>().shaderInt8;
  }
  if (has_8bit) {
    auto f = device.getFeatures2<vk::PhysicalDeviceFeatures2, vk::PhysicalDevice8BitStorageFeatures>();
    caps.storage_8bit = f.get<vk::PhysicalDevice8BitStorageFeatures>().storageBuffer8BitAccess;
  }

  auto props2 = device.getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceSubgroupProperties>();
  const auto& subgroup = props2.get<vk::PhysicalDeviceSubgroupProperties>();
  caps.subgroup_size = subgroup.subgroupSize;
  caps.subgroup_arithmetic = static_cast<bool>(subgroup.supportedOperations & vk::SubgroupFeatureFlagBits::eArithmetic);
  caps.subgroup_ballot = static_cast<bool>(subgroup.supportedOperations & vk::SubgroupFeatureFlagBits::eBallot);
  caps.subgroup_compute = static_cast<bool>(subgroup.supportedStages & vk::ShaderStageFlagBits::eCompute);
  if (api12) {
    auto driver = device.getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceDriverProperties>();
    const auto& d = driver.get<vk::PhysicalDeviceDriverProperties>();
    caps.driver = fmt::format("{} {}", d.driverName.data(), d.driverInfo.data());
  }

  query_cooperative_matrix(device, api12, caps);

  if (const auto family = compute_queue_family(device)) {
    caps.timestamps =
        props.limits.timestampComputeAndGraphics || device.getQueueFamilyProperties()[*family].timestampValidBits > 0;
  }

  const auto memory = device.getMemoryProperties();
  bool all_device_local_visible = true, any_device_local = false;
  for (std::uint32_t h = 0; h < memory.memoryHeapCount; ++h)
    caps.heaps.push_back({memory.memoryHeaps[h].size,
                          static_cast<bool>(memory.memoryHeaps[h].flags & vk::MemoryHeapFlagBits::eDeviceLocal)});
  for (std::uint32_t t = 0; t < memory.memoryTypeCount; ++t) {
    const auto flags = memory.memoryTypes[t].propertyFlags;
    if (!(flags & vk::MemoryPropertyFlagBits::eDeviceLocal)) continue;
    any_device_local = true;
    if (!(flags & vk::MemoryPropertyFlagBits::eHostVisible)) all_device_local_visible = false;
  }
  caps.unified_memory = any_device_local && all_device_local_visible;
  return caps;
}

vk::raii::Instance create_instance(const vk::raii::Context& loader, bool& validation) {
  std::vector<const char*> layers, extensions;
  if (validation) {
    const auto available = loader.enumerateInstanceLayerProperties();
    const bool found = std::any_of(available.begin(), available.end(), [](const vk::LayerProperties& l) {
      return std::string_view(l.layerName.data()) == kValidationLayer;
    });
    if (found) {
      layers.push_back(kValidationLayer);
      extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    } else {
      spdlog::warn("validation requested but {} is not installed (apt-get install vulkan-validationlayers)",
                   kValidationLayer);
      validation = false;
    }
  }
  vk::InstanceCreateFlags flags;
  for (const auto& ext : loader.enumerateInstanceExtensionProperties())
    if (std::string_view(ext.extensionName.data()) == VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME) {
      extensions.push_back(VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME);  // MoltenVK and other layered drivers
      flags |= vk::InstanceCreateFlagBits::eEnumeratePortabilityKHR;
    }
  const vk::ApplicationInfo app{.pApplicationName = "vkvo",
                                .applicationVersion = 1,
                                .pEngineName = "vkvo",
                                .engineVersion = 1,
                                .apiVersion = VK_API_VERSION_1_1};
  const vk::InstanceCreateInfo info{.flags = flags,
                                    .pApplicationInfo = &app,
                                    .enabledLayerCount = static_cast<std::uint32_t>(layers.size()),
                                    .ppEnabledLayerNames = layers.data(),
                                    .enabledExtensionCount = static_cast<std::uint32_t>(extensions.size()),
                                    .ppEnabledExtensionNames = extensions.data()};
  return vk::raii::Instance(loader, info);
}

std::vector<DeviceCaps> list_devices_of(const vk::raii::Instance& instance) {
  vk::raii::PhysicalDevices devices(instance);
  std::vector<DeviceCaps> result;
  for (std::uint32_t i = 0; i < devices.size(); ++i) result.push_back(query_caps(devices[i], i));
  return result;
}

std::uint32_t choose_device(const std::vector<DeviceCaps>& devices, const std::string& selector) {
  if (devices.empty())
    throw VulkanError(
        "no Vulkan device found: install a Vulkan driver (on a CPU-only machine "
        "`apt-get install mesa-vulkan-drivers` provides lavapipe)");
  if (!selector.empty()) {
    if (std::all_of(selector.begin(), selector.end(), [](unsigned char c) { return std::isdigit(c); })) {
      const auto index = static_cast<std::uint32_t>(std::stoul(selector));
      if (index >= devices.size())
        throw VulkanError(fmt::format("VKVO_DEVICE={} but only {} Vulkan device(s) exist", selector, devices.size()));
      return index;
    }
    for (const auto& d : devices)
      if (lowercase(d.name).find(lowercase(selector)) != std::string::npos) return d.index;
    std::string names;
    for (const auto& d : devices) names += fmt::format(" [{}] {}", d.index, d.name);
    throw VulkanError(fmt::format("no Vulkan device matches '{}'; devices:{}", selector, names));
  }
  return std::max_element(devices.begin(), devices.end(),
                          [](const DeviceCaps& a, const DeviceCaps& b) {
                            return device_type_rank(a.type) < device_type_rank(b.type);
                          })
      ->index;
}

std::filesystem::path default_cache_dir() {
  if (auto dir = env_or_empty("VKVO_CACHE_DIR"); !dir.empty()) return dir;
  if (auto dir = env_or_empty("XDG_CACHE_HOME"); !dir.empty()) return std::filesystem::path(dir) / "vkvo";
  if (auto home = env_or_empty("HOME"); !home.empty()) return std::filesystem::path(home) / ".cache" / "vkvo";
  return std::filesystem::temp_directory_path() / "vkvo-cache";
}

std::vector<char> read_file_or_empty(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Turns loader/driver failures into one error type with a hint of what to install.
template <class F>
auto guarded(const char* what, F&& f) {
  try {
    return f();
  } catch (const vk::SystemError& e) {
    throw VulkanError(
        fmt::format("{} failed: {} (is a Vulkan driver installed? `vulkaninfo --summary` "
                    "lists what the loader sees)",
                    what, e.what()));
  } catch (const VulkanError&) {
    throw;
  } catch (const std::exception& e) {
    throw VulkanError(
        fmt::format("{} failed: {} (install libvulkan1 and a driver, e.g. mesa-vulkan-drivers)", what, e.what()));
  }
}

}  // namespace

bool DeviceCaps::has_cooperative_matrix_shape(const CooperativeMatrixShape& shape) const {
  return cooperative_matrix != CooperativeMatrixApi::none &&
         std::find(cooperative_matrix_shapes.begin(), cooperative_matrix_shapes.end(), shape) !=
             cooperative_matrix_shapes.end();
}

DeviceCaps effective_caps(DeviceCaps caps, const ContextOptions& options) {
  if (!options.use_16bit) caps.storage_16bit = caps.float16_arithmetic = false;
  if (!options.use_int64) caps.int64 = false;
  if (!options.use_unified_memory) caps.unified_memory = false;
  if (!options.cooperative_matrix.value_or(env_or_empty("VKVO_COOPERATIVE_MATRIX") != "0")) {
    caps.cooperative_matrix = CooperativeMatrixApi::none;
    caps.cooperative_matrix_shapes.clear();
  }
  return caps;
}

bool DeviceCaps::supports(Precision p) const {
  switch (p) {
    case Precision::fp32: return true;
    case Precision::fp16s: return storage_16bit;
    case Precision::fp16: return storage_16bit && float16_arithmetic;
  }
  return false;
}

void DeviceCaps::require(Precision p, std::string_view user) const {
  if (supports(p)) return;
  const char* lacks =
      !storage_16bit ? "16-bit storage (storageBuffer16BitAccess)" : "float16 arithmetic (shaderFloat16)";
  std::string usable;
  for (const Precision q : kAllPrecisions)
    if (supports(q)) usable += (usable.empty() ? "" : ", ") + std::string(to_string(q));
  throw std::runtime_error(fmt::format("{}: device '{}' does not support precision {}: it lacks {}; use {} or auto",
                                       user, name, to_string(p), lacks, usable));
}

std::uint64_t validation_message_count() { return g_validation_messages.load(); }

std::vector<DeviceCaps> list_devices() {
  return guarded("listing Vulkan devices", [] {
    vk::raii::Context loader;
    bool validation = false;
    const auto instance = create_instance(loader, validation);
    return list_devices_of(instance);
  });
}

Context::Context(const ContextOptions& options)
    : loader_(guarded("loading the Vulkan library", [] { return vk::raii::Context(); })) {
  validation_enabled_ = options.validation.value_or(env_or_empty("VKVO_VALIDATION") == "1");
  instance_ = guarded("creating the Vulkan instance", [&] { return create_instance(loader_, validation_enabled_); });
  if (validation_enabled_) {
    using S = vk::DebugUtilsMessageSeverityFlagBitsEXT;
    using T = vk::DebugUtilsMessageTypeFlagBitsEXT;
    messenger_ = instance_.createDebugUtilsMessengerEXT({.messageSeverity = S::eWarning | S::eError,
                                                         .messageType = T::eGeneral | T::eValidation | T::ePerformance,
                                                         .pfnUserCallback = &on_validation_message});
  }

  const auto devices = guarded("enumerating Vulkan devices", [&] { return list_devices_of(instance_); });
  const std::string selector = options.device.empty() ? env_or_empty("VKVO_DEVICE") : options.device;
  const std::uint32_t chosen = choose_device(devices, selector);
  caps_ = effective_caps(devices[chosen], options);
  profile_ = make_device_profile(caps_);
  physical_device_ = std::move(vk::raii::PhysicalDevices(instance_)[chosen]);
  if (caps_.api_version < VK_API_VERSION_1_1)
    throw VulkanError(fmt::format("device '{}' supports only Vulkan {}.{}; vkvo needs 1.1", caps_.name,
                                  VK_VERSION_MAJOR(caps_.api_version), VK_VERSION_MINOR(caps_.api_version)));
  const auto family = compute_queue_family(physical_device_);
  if (!family) throw VulkanError(fmt::format("device '{}' has no compute queue", caps_.name));
  queue_family_ = *family;

  // Enable exactly the 16/8-bit and 64-bit features the device has; shaders for unsupported precisions are never
  // created, nor those with 64-bit types (WinogradConv3x3's wide transforms) without shaderInt64.
  std::vector<const char*> extensions;
  const bool api12 = caps_.api_version >= VK_API_VERSION_1_2;
  if (!api12 && caps_.float16_arithmetic) extensions.push_back(VK_KHR_SHADER_FLOAT16_INT8_EXTENSION_NAME);
  if (!api12 && caps_.storage_8bit) extensions.push_back(VK_KHR_8BIT_STORAGE_EXTENSION_NAME);
  vk::PhysicalDevice8BitStorageFeatures storage8{.storageBuffer8BitAccess = caps_.storage_8bit};
  vk::PhysicalDeviceShaderFloat16Int8Features f16i8{.pNext = caps_.storage_8bit ? &storage8 : nullptr,
                                                    .shaderFloat16 = caps_.float16_arithmetic,
                                                    .shaderInt8 = caps_.int8_arithmetic};
  vk::PhysicalDevice16BitStorageFeatures storage16{.pNext = (caps_.float16_arithmetic || caps_.int8_arithmetic)
                                                                ? static_cast<void*>(&f16i8)
                                                                : (caps_.storage_8bit ? &storage8 : nullptr),
                                                   .storageBuffer16BitAccess = caps_.storage_16bit};
  // Cooperative matrices where the caps keep them (effective_caps): the extension, its feature and the Vulkan
  // memory model their shaders declare.
  const bool cooperative = caps_.cooperative_matrix == CooperativeMatrixApi::nv;
  vk::PhysicalDeviceVulkanMemoryModelFeatures memory_model{.pNext = &storage16, .vulkanMemoryModel = VK_TRUE};
  vk::PhysicalDeviceCooperativeMatrixFeaturesNV cooperative_matrix{.pNext = &memory_model,
                                                                   .cooperativeMatrix = VK_TRUE};
  if (cooperative) {
    extensions.push_back(VK_NV_COOPERATIVE_MATRIX_EXTENSION_NAME);
    if (has_extension(physical_device_, VK_KHR_VULKAN_MEMORY_MODEL_EXTENSION_NAME))
      extensions.push_back(VK_KHR_VULKAN_MEMORY_MODEL_EXTENSION_NAME);
  }
  vk::PhysicalDeviceFeatures2 features2{.pNext = cooperative ? static_cast<void*>(&cooperative_matrix) : &storage16,
                                        .features = {.shaderInt64 = caps_.int64}};
  const float priority = 1.0f;
  const vk::DeviceQueueCreateInfo queue_info{
      .queueFamilyIndex = queue_family_, .queueCount = 1, .pQueuePriorities = &priority};
  device_ = guarded("creating the Vulkan device", [&] {
    return vk::raii::Device(physical_device_,
                            vk::DeviceCreateInfo{.pNext = &features2,
                                                 .queueCreateInfoCount = 1,
                                                 .pQueueCreateInfos = &queue_info,
                                                 .enabledExtensionCount = static_cast<std::uint32_t>(extensions.size()),
                                                 .ppEnabledExtensionNames = extensions.data()});
  });
  queue_ = device_.getQueue(queue_family_, 0);
  transfer_pool_ = device_.createCommandPool(
      {.flags = vk::CommandPoolCreateFlagBits::eTransient, .queueFamilyIndex = queue_family_});

  std::vector<char> cache_data;
  if (options.pipeline_cache) {
    const auto dir = options.cache_dir.empty() ? default_cache_dir() : options.cache_dir;
    cache_file_ = dir / fmt::format("pipelines-{:04x}-{:04x}.bin", caps_.vendor_id, caps_.device_id);
    cache_data = read_file_or_empty(cache_file_);  // the driver checks the header and ignores a stale cache
  }
  pipeline_cache_ = device_.createPipelineCache(
      {.initialDataSize = cache_data.size(), .pInitialData = cache_data.empty() ? nullptr : cache_data.data()});
  spdlog::debug("Vulkan device: {} ({}), validation {}", caps_.name, caps_.type, validation_enabled_ ? "on" : "off");
}

bool Context::supports_uniform_texel_format(vk::Format format) const {
  return static_cast<bool>(physical_device_.getFormatProperties(format).bufferFeatures &
                           vk::FormatFeatureFlagBits::eUniformTexelBuffer);
}

Context::~Context() {
  try {
    save_pipeline_cache();
  } catch (const std::exception& e) {
    spdlog::warn("could not save the pipeline cache: {}", e.what());
  }
}

void Context::save_pipeline_cache() const {
  if (cache_file_.empty()) return;
  const auto data = pipeline_cache_.getData();
  std::error_code ec;
  std::filesystem::create_directories(cache_file_.parent_path(), ec);
  // A name of this process's own: several processes (ctest -j, two CLIs) may save the same cache at once.
  const auto tmp = cache_file_.string() + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) return;  // a read-only home is no reason to fail
    out.write(reinterpret_cast<const char*>(data.data()), static_cast<std::streamsize>(data.size()));
  }
  std::filesystem::rename(tmp, cache_file_, ec);
}

std::optional<std::uint32_t> Context::find_memory_type(std::uint32_t type_bits,
                                                       vk::MemoryPropertyFlags required) const {
  const auto memory = physical_device_.getMemoryProperties();
  for (std::uint32_t t = 0; t < memory.memoryTypeCount; ++t)
    if ((type_bits & (1u << t)) && (memory.memoryTypes[t].propertyFlags & required) == required) return t;
  return std::nullopt;
}

void Context::run_once(const std::function<void(const vk::raii::CommandBuffer&)>& record) const {
  const vk::raii::Fence fence(device_, vk::FenceCreateInfo{});
  std::lock_guard lock(queue_mutex_);  // the transient pool is shared too
  vk::raii::CommandBuffers buffers(
      device_, {.commandPool = *transfer_pool_, .level = vk::CommandBufferLevel::ePrimary, .commandBufferCount = 1});
  const auto& cmd = buffers[0];
  cmd.begin({.flags = vk::CommandBufferUsageFlagBits::eOneTimeSubmit});
  record(cmd);
  cmd.end();
  const vk::CommandBuffer handle = *cmd;
  ++submissions_;
  queue_.submit(vk::SubmitInfo{.commandBufferCount = 1, .pCommandBuffers = &handle}, *fence);
  if (device_.waitForFences(*fence, VK_TRUE, UINT64_MAX) != vk::Result::eSuccess)
    throw VulkanError("waiting for a transfer failed");
}

void Context::submit_and_wait(vk::CommandBuffer commands, const vk::raii::Fence& fence) const {
  device_.resetFences(*fence);
  {
    std::lock_guard lock(queue_mutex_);
    ++submissions_;
    queue_.submit(vk::SubmitInfo{.commandBufferCount = 1, .pCommandBuffers = &commands}, *fence);
  }
  if (device_.waitForFences(*fence, VK_TRUE, UINT64_MAX) != vk::Result::eSuccess)
    throw VulkanError("waiting for a command sequence failed");
}

}  // namespace vkvo::rt
