// `vkvo devices`: every Vulkan device with the capabilities vkvo cares about, and which one it would use.
#include <string>

#include <fmt/format.h>

#include "app/command.hpp"
#include "runtime/context.hpp"
#include "runtime/host.hpp"

namespace {

std::string yes_no(bool v) { return v ? "yes" : "no"; }

int list_all() {
  const auto devices = vkvo::rt::list_devices();
  vkvo::rt::ContextOptions options;
  options.validation = false;
  options.pipeline_cache = false;
  const vkvo::rt::Context chosen(options);
  const std::string host = vkvo::rt::host_cpu().describe();
  for (const auto& d : devices) {
    fmt::print("[{}] {}{}\n", d.index, d.name, d.index == chosen.caps().index ? "   <- selected" : "");
    fmt::print("    type {}, Vulkan {}.{}.{}, vendor 0x{:04x} device 0x{:04x}\n", d.type,
               VK_VERSION_MAJOR(d.api_version), VK_VERSION_MINOR(d.api_version), VK_VERSION_PATCH(d.api_version),
               d.vendor_id, d.device_id);
    if (!d.driver.empty()) fmt::print("    driver {}\n", d.driver);
    if (d.type == "cpu") fmt::print("    runs on the host: {}\n", host);
    fmt::print("    fp16 arithmetic {}, 16-bit storage {}, 8-bit storage {}, int8 arithmetic {}, int64 {}\n",
               yes_no(d.float16_arithmetic), yes_no(d.storage_16bit), yes_no(d.storage_8bit), yes_no(d.int8_arithmetic),
               yes_no(d.int64));
    fmt::print(
        "    subgroup size {} (arithmetic {}, broadcast {}), max workgroup {} invocations, shared memory {} KiB\n",
        d.subgroup_size, yes_no(d.subgroup_arithmetic), yes_no(d.subgroup_ballot && d.subgroup_compute),
        d.max_workgroup_invocations, d.max_shared_memory_bytes / 1024);
    fmt::print("    timestamps {} ({:.3f} ns/tick), unified memory {}, max storage buffer {} MiB\n",
               yes_no(d.timestamps), d.timestamp_period_ns, yes_no(d.unified_memory), d.max_storage_buffer_range >> 20);
    for (std::size_t h = 0; h < d.heaps.size(); ++h)
      fmt::print("    heap {}: {:.1f} GiB{}\n", h, double(d.heaps[h].bytes) / (1 << 30),
                 d.heaps[h].device_local ? " device-local" : "");
    if (d.cooperative_matrix_shapes.empty()) {
      fmt::print("    cooperative matrix shapes: none\n");
    } else {
      fmt::print("    cooperative matrix shapes (VK_NV_cooperative_matrix), A*B+C->D:\n");
      for (const auto& shape : d.cooperative_matrix_shapes) fmt::print("      {}\n", vkvo::rt::to_string(shape));
    }
    const bool tensor_cores = vkvo::rt::make_device_profile(vkvo::rt::effective_caps(d, {})).cooperative_matrix;
    fmt::print("    tensor-core kernels: {}\n", tensor_cores ? "yes (VKVO_COOPERATIVE_MATRIX=0 turns them off)"
                                                : vkvo::rt::supports_coopmat_kernels(d)
                                                    ? "no (VKVO_COOPERATIVE_MATRIX=0)"
                                                    : fmt::format("no (they need the shape {} and 16-bit types)",
                                                                  vkvo::rt::to_string(vkvo::rt::kCoopmatKernelShape)));
    std::string precisions;
    for (auto p : vkvo::rt::kAllPrecisions)
      if (d.supports(p)) precisions += fmt::format(" {}", vkvo::rt::to_string(p));
    fmt::print("    precisions:{} (default {})\n", precisions,
               vkvo::rt::to_string(vkvo::rt::make_device_profile(d).precision));
  }
  fmt::print("select with VKVO_DEVICE=<index|name substring>\n");
  return 0;
}

vkvo::app::CommandRegistration registration{{"devices", "list Vulkan devices and their capabilities",
                                             [](CLI::App&) { return std::function<int()>(list_all); }}};

}  // namespace
