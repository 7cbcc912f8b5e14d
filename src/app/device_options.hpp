#pragma once
// --device and --precision, declared once for every command that runs on the Vulkan device: one set of accepted
// values, one help text, one conversion.
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "runtime/context.hpp"
#include "runtime/precision.hpp"

namespace vkvo::app {

struct DeviceSelection {
  std::string device;              // index or name substring; empty: $VKVO_DEVICE, else the best device
  std::string precision = "auto";  // auto (the device's preferred) or a precision's name

  rt::ContextOptions context_options() const;
  // nullopt: the device's preferred precision.
  std::optional<rt::Precision> chosen_precision() const;
};

void add_device_option(CLI::App& command, DeviceSelection& selection);
void add_precision_option(CLI::App& command, DeviceSelection& selection);
// `vkvo bench`: any number of precisions (none: every precision the device supports).
void add_precision_list_option(CLI::App& command, std::vector<std::string>& precisions);

}  // namespace vkvo::app
