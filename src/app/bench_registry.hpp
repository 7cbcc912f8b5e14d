#pragma once
// Benchmarks of whole networks for `vkvo bench --<name>`: each src/app/bench_<name>.cpp registers one.
#include <functional>
#include <string>
#include <vector>

#include "runtime/context.hpp"

namespace vkvo::app {

struct BenchOptions {
  int repeat = 10;
  std::vector<rt::Precision> precisions;               // supported by the device; never empty
  std::string model;                                   // --model PACK where the bench needs weights
  std::string winograd = "auto";                       // --winograd: SuperPoint's 3x3 convolutions (auto | on | off)
  int winograd_tile = 0;                               // --winograd-tile: 4 or 6 (0: SuperPointParams' default)
  std::vector<std::size_t> keypoints{200, 400, 1000};  // --keypoints: SuperGlue's N = M
  std::string attention = "auto";  // --attention: SuperGlue's fused attention (auto | shared | registers)
  std::string sinkhorn = "auto";   // --sinkhorn: auto | fused | workgroup-per-line | invocation-per-line
};

struct NetworkBench {
  std::string name;  // flag: --<name>
  std::string description;
  std::function<int(const rt::Context&, const BenchOptions&)> run;
};

std::vector<NetworkBench>& network_bench_registry();

struct NetworkBenchRegistration {
  explicit NetworkBenchRegistration(NetworkBench bench) { network_bench_registry().push_back(std::move(bench)); }
};

}  // namespace vkvo::app
