#pragma once
// What every part of the Python module shares: errors raised as Python's own exception types, path and
// precision arguments, and the Vulkan contexts (one per device, shared by every object that runs on it).
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <pybind11/pybind11.h>

#include "runtime/context.hpp"
#include "runtime/precision.hpp"

namespace vkvo::python {

namespace py = pybind11;
namespace fs = std::filesystem;

// Raises `type` (e.g. PyExc_ValueError) with `message` once control returns to Python.
[[noreturn]] void raise(PyObject* type, const std::string& message);

// `path` when it exists, else FileNotFoundError naming `what` and the path.
const fs::path& existing_path(const fs::path& path, const std::string& what);

// A `precision` argument: "auto" (nullopt: the device's preferred precision), "fp32", "fp16s" or "fp16";
// ValueError otherwise.
std::optional<rt::Precision> precision_argument(const std::string& text);

// The context of a `device` argument as VKVO_DEVICE takes it: None (VKVO_DEVICE, else the best device), an index,
// or a case-insensitive name substring. Objects keep the pointer; the context lives while one of them does.
// Call with the GIL released (creating a device takes a while).
std::shared_ptr<const rt::Context> shared_context(const std::string& device);
// The `device` argument as that string (TypeError for anything but None, int or str).
std::string device_argument(const py::object& device);

}  // namespace vkvo::python
