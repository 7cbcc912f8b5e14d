#include "python/common.hpp"

#include <map>
#include <mutex>

#include <fmt/format.h>

namespace vkvo::python {

void raise(PyObject* type, const std::string& message) {
  PyErr_SetString(type, message.c_str());
  throw py::error_already_set();
}

const fs::path& existing_path(const fs::path& path, const std::string& what) {
  if (!fs::exists(path)) raise(PyExc_FileNotFoundError, fmt::format("{} {} does not exist", what, path.string()));
  return path;
}

std::optional<rt::Precision> precision_argument(const std::string& text) {
  if (text == "auto") return std::nullopt;
  if (const auto precision = rt::parse_precision(text)) return precision;
  raise(PyExc_ValueError, fmt::format("precision '{}': expected auto, fp32, fp16s or fp16", text));
}

std::shared_ptr<const rt::Context> shared_context(const std::string& device) {
  static std::mutex mutex;
  static std::map<std::string, std::weak_ptr<const rt::Context>> contexts;
  const std::lock_guard lock(mutex);
  auto& slot = contexts[device];
  if (auto context = slot.lock()) return context;
  rt::ContextOptions options;
  options.device = device;
  auto context = std::make_shared<const rt::Context>(options);
  slot = context;
  return context;
}

std::string device_argument(const py::object& device) {
  if (device.is_none()) return "";
  if (py::isinstance<py::bool_>(device)) raise(PyExc_TypeError, "device: expected None, an index or a name");
  if (py::isinstance<py::int_>(device)) return std::to_string(device.cast<long long>());
  if (py::isinstance<py::str>(device)) return device.cast<std::string>();
  raise(PyExc_TypeError, fmt::format("device: expected None, an index or a name, got {}",
                                     py::str(py::type::of(device).attr("__name__")).cast<std::string>()));
}

}  // namespace vkvo::python
