#include <sstream>

#include <gtest/gtest.h>

#include "runtime/host.hpp"

namespace vkvo::rt {
namespace {

std::string model_of(const std::string& cpuinfo) {
  std::istringstream in(cpuinfo);
  return cpu_model_from_cpuinfo(in);
}

TEST(HostCpu, ReadsTheFirstModelNameOfX86Cpuinfo) {
  const std::string cpuinfo =
      "processor\t: 0\nvendor_id\t: GenuineIntel\nmodel\t\t: 207\n"
      "model name\t: Intel(R) Xeon(R) Processor  \nflags\t\t: fpu avx2\n\n"
      "processor\t: 1\nmodel name\t: Some Other CPU\n";
  EXPECT_EQ(model_of(cpuinfo), "Intel(R) Xeon(R) Processor");
}

TEST(HostCpu, FallsBackToArmHardwareOrProcessorLines) {
  // "processor" (each CPU's index) is not the model; "Processor" and "Hardware" name it on older ARM kernels.
  EXPECT_EQ(model_of("processor\t: 0\nBogoMIPS\t: 38.40\nHardware\t: BCM2835\n"), "BCM2835");
  EXPECT_EQ(model_of("Processor\t: AArch64 Processor rev 4 (aarch64)\nprocessor\t: 0\n"),
            "AArch64 Processor rev 4 (aarch64)");
  // A model name wins over them wherever it stands.
  EXPECT_EQ(model_of("Hardware\t: Board\nmodel name\t: ARMv7 Processor rev 3 (v7l)\n"), "ARMv7 Processor rev 3 (v7l)");
}

TEST(HostCpu, EmptyWhereNoLineNamesAModel) {
  EXPECT_EQ(model_of(""), "");
  EXPECT_EQ(model_of("processor\t: 0\nCPU implementer\t: 0x41\nmodel name\t:\n"), "");
}

TEST(HostCpu, DescribesThisMachine) {
  const HostCpu host = host_cpu();
  EXPECT_FALSE(host.model.empty());
  EXPECT_GE(host.logical_cpus, 1u);
  const std::string text = host.describe();
  EXPECT_NE(text.find(host.model), std::string::npos);
  EXPECT_NE(text.find(std::to_string(host.logical_cpus) + " logical CPU"), std::string::npos);
  EXPECT_EQ((HostCpu{.model = "X", .logical_cpus = 1}.describe()), "X, 1 logical CPU");
  EXPECT_EQ((HostCpu{.model = "X", .logical_cpus = 0}.describe()), "X, logical CPUs unknown");
}

}  // namespace
}  // namespace vkvo::rt
