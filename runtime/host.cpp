#include "runtime/host.hpp"

#include <sys/utsname.h>

#include <fstream>
#include <string_view>
#include <thread>

#include <fmt/format.h>

namespace vkvo::rt {
namespace {

std::string_view trimmed(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

}  // namespace

std::string cpu_model_from_cpuinfo(std::istream& cpuinfo) {
  std::string fallback;
  for (std::string line; std::getline(cpuinfo, line);) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    const std::string_view key = trimmed(std::string_view(line).substr(0, colon));
    const std::string_view value = trimmed(std::string_view(line).substr(colon + 1));
    if (value.empty()) continue;
    if (key == "model name") return std::string(value);
    // On ARM "Processor" names the core in older kernels, and "processor" (lower case) is every CPU's index.
    if (fallback.empty() && (key == "Hardware" || key == "Processor")) fallback = value;
  }
  return fallback;
}

HostCpu host_cpu() {
  HostCpu host;
  host.logical_cpus = std::thread::hardware_concurrency();
  if (std::ifstream cpuinfo("/proc/cpuinfo"); cpuinfo) host.model = cpu_model_from_cpuinfo(cpuinfo);
  if (host.model.empty()) {
    utsname name{};
    host.model = uname(&name) == 0 ? name.machine : "unknown CPU";
  }
  return host;
}

std::string HostCpu::describe() const {
  if (logical_cpus == 0) return fmt::format("{}, logical CPUs unknown", model);
  return fmt::format("{}, {} logical CPU{}", model, logical_cpus, logical_cpus == 1 ? "" : "s");
}

}  // namespace vkvo::rt
