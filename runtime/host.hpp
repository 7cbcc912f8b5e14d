#pragma once
// The machine the process runs on. On a CPU device (lavapipe) it is the device: the driver names only its LLVM
// and vector width, yet the same build runs at very different speeds on different 2-core cloud VMs
// (docs/performance-history.md), so benchmark figures name the host next to the device.
#include <istream>
#include <string>

namespace vkvo::rt {

struct HostCpu {
  std::string model;  // e.g. "Intel(R) Xeon(R) Processor"; the architecture ("aarch64") where none is named
  unsigned logical_cpus = 0;

  std::string describe() const;  // "<model>, <n> logical CPU(s)"
};

HostCpu host_cpu();

// The processor's name in Linux's /proc/cpuinfo text: the first "model name" (x86), else the first "Hardware" or
// "Processor" line that names one (older ARM kernels); empty when none does.
std::string cpu_model_from_cpuinfo(std::istream& cpuinfo);

}  // namespace vkvo::rt
