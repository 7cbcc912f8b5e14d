// The `vkvo` Python module: SuperPoint, SuperGlue and the VO on any Vulkan device, numpy arrays in and out.
// Errors are Python exceptions carrying the C++ message: ValueError for unusable arguments (std::invalid_argument
// and friends, through pybind11), FileNotFoundError for missing files, vkvo.VulkanError (a RuntimeError) for the
// device, RuntimeError for the rest.
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <pybind11/stl.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "python/bindings.hpp"
#include "python/common.hpp"
#include "runtime/context.hpp"
#include "runtime/device_profile.hpp"

namespace vkvo::python {
namespace {

// One device as a dict (one place to add what DeviceCaps gains).
py::dict device_dict(const rt::DeviceCaps& caps) {
  using namespace py::literals;
  std::vector<std::string> precisions;
  for (const auto p : rt::kAllPrecisions)
    if (caps.supports(p)) precisions.emplace_back(rt::to_string(p));
  std::uint64_t device_local_bytes = 0;
  for (const auto& heap : caps.heaps) device_local_bytes += heap.device_local ? heap.bytes : 0;
  const std::string api = fmt::format("{}.{}.{}", VK_VERSION_MAJOR(caps.api_version),
                                      VK_VERSION_MINOR(caps.api_version), VK_VERSION_PATCH(caps.api_version));
  return py::dict("index"_a = caps.index, "name"_a = caps.name, "type"_a = caps.type, "vendor_id"_a = caps.vendor_id,
                  "device_id"_a = caps.device_id, "api_version"_a = api, "driver"_a = caps.driver,
                  "precisions"_a = precisions,
                  "preferred_precision"_a = std::string(rt::to_string(rt::make_device_profile(caps).precision)),
                  "unified_memory"_a = caps.unified_memory, "memory_bytes"_a = device_local_bytes);
}

py::list devices() {
  std::vector<rt::DeviceCaps> all;
  {
    const py::gil_scoped_release release;
    all = rt::list_devices();
  }
  py::list list;
  for (const auto& caps : all) list.append(device_dict(caps));
  return list;
}

void set_log_level(const std::string& level) {
  const auto parsed = spdlog::level::from_str(level);
  if (parsed == spdlog::level::off && level != "off")
    raise(PyExc_ValueError,
          fmt::format("log level '{}': expected trace, debug, info, warning, error, critical or off", level));
  spdlog::set_level(parsed);
}

}  // namespace
}  // namespace vkvo::python

PYBIND11_MODULE(vkvo, m) {
  using namespace vkvo::python;
  namespace rt = vkvo::rt;
  m.doc() = "vkvo: SuperPoint, SuperGlue and stereo visual odometry (AirVO) on any Vulkan device";
  m.attr("__version__") = VKVO_VERSION;
  // The library logs through spdlog: to stderr here (stdout is the program's), warnings and errors only unless
  // vkvo.set_log_level says otherwise.
  spdlog::set_default_logger(spdlog::stderr_color_mt("vkvo"));
  spdlog::set_level(spdlog::level::warn);

  py::register_exception<rt::VulkanError>(m, "VulkanError", PyExc_RuntimeError);
  m.def("devices", &devices,
        "Every Vulkan device as a dict (index, name, type, precisions, preferred_precision, ...); select one with "
        "a device= argument or $VKVO_DEVICE.");
  m.def("set_log_level", &set_log_level, py::arg("level"),
        "The library's log level: trace, debug, info, warning (the default), error, critical or off (to stderr).");
  m.def("_validation_message_count", &rt::validation_message_count,
        "Vulkan validation messages so far in this process (tests, with VKVO_VALIDATION=1).");
  bind_features(m);
  bind_odometry(m);
  bind_eval(m);
}
