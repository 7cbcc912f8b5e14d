#include "app/device_options.hpp"

namespace vkvo::app {
namespace {

const std::vector<std::string> kPrecisions{"fp32", "fp16s", "fp16"};

std::vector<std::string> with_auto() {
  std::vector<std::string> names{"auto"};
  names.insert(names.end(), kPrecisions.begin(), kPrecisions.end());
  return names;
}

}  // namespace

rt::ContextOptions DeviceSelection::context_options() const {
  rt::ContextOptions options;
  options.device = device;
  return options;
}

std::optional<rt::Precision> DeviceSelection::chosen_precision() const {
  if (precision.empty() || precision == "auto") return std::nullopt;
  return rt::parse_precision(precision);  // CLI11 has checked the name
}

void add_device_option(CLI::App& command, DeviceSelection& selection) {
  command.add_option("--device", selection.device,
                     "device index or name substring, as `vkvo devices` lists them (default: $VKVO_DEVICE, else "
                     "the best device)");
}

void add_precision_option(CLI::App& command, DeviceSelection& selection) {
  command
      .add_option("--precision", selection.precision,
                  "network precision: auto (the device's preferred), fp32, fp16s (16-bit storage) or fp16")
      ->check(CLI::IsMember(with_auto()));
}

void add_precision_list_option(CLI::App& command, std::vector<std::string>& precisions) {
  command
      .add_option("--precision", precisions, "fp32, fp16s and/or fp16 (default: every precision the device supports)")
      ->check(CLI::IsMember(kPrecisions));
}

}  // namespace vkvo::app
