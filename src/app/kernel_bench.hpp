#pragma once
// Kernel timings for `vkvo bench`: each kernel is recorded once and submitted `repeat` times; the median of the
// GPU timestamps is reported (wall-clock time when the device has no timestamps).
#include <string>
#include <string_view>
#include <vector>

#include "runtime/context.hpp"

namespace vkvo::app {

struct BenchResult {
  std::string name;
  std::string precision;
  double median_ms = 0;
  double gflops = 0;  // GFLOP/s, 0 where FLOPs are not meaningful (pooling)
  double gbytes = 0;  // GB/s of tensor traffic
};

// `filter`: only the kernels whose name contains it (all when empty), e.g. "gemm" or "conv3x3 64->64".
std::vector<BenchResult> bench_kernels(const rt::Context& context, rt::Precision precision, int repeat,
                                       std::string_view filter = {});
void print_bench_header();
void print_bench_row(const BenchResult& result);
// Median of GPU (or wall) milliseconds of `submit` over `repeat` runs after one warm-up.
double median_ms(const std::vector<double>& samples);

}  // namespace vkvo::app
