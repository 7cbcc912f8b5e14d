// `vkvo bench`: GPU-timestamped timings of the kernels (median ms and GFLOP/s per kernel and precision) on the
// chosen device.
#include <algorithm>
#include <memory>
#include <vector>

#include <fmt/format.h>

#include "app/command.hpp"
#include "app/kernel_bench.hpp"
#include "runtime/context.hpp"

namespace {

struct Options {
  int repeat = 10;
  std::vector<std::string> precisions;
  std::string device;
};

int run(const Options& options) {
  vkvo::rt::ContextOptions context_options;
  context_options.device = options.device;
  const vkvo::rt::Context context(context_options);
  const auto& caps = context.caps();
  fmt::print("device: {} ({}), {}\n", caps.name, caps.type, caps.driver);
  std::vector<vkvo::rt::Precision> precisions;
  for (const auto& name : options.precisions) {
    const auto p = vkvo::rt::parse_precision(name);
    if (!p) throw std::runtime_error(fmt::format("unknown precision '{}' (fp32, fp16s, fp16)", name));
    precisions.push_back(*p);
  }
  if (precisions.empty())
    for (auto p : vkvo::rt::kAllPrecisions)
      if (caps.supports(p)) precisions.push_back(p);
  vkvo::app::print_bench_header();
  for (auto p : precisions) {
    if (!caps.supports(p)) {
      fmt::print("{:<34} {:<6} unsupported on this device\n", "(all)", vkvo::rt::to_string(p));
      continue;
    }
    for (const auto& result : vkvo::app::bench_kernels(context, p, options.repeat)) vkvo::app::print_bench_row(result);
  }
  return 0;
}

vkvo::app::CommandRegistration registration{
    {"bench", "time the compute kernels on the chosen device (median ms, GFLOP/s)", [](CLI::App& sub) {
       auto options = std::make_shared<Options>();
       sub.add_option("--repeat", options->repeat, "timed submissions per kernel")->check(CLI::PositiveNumber);
       sub.add_option("--precision", options->precisions, "fp32, fp16s and/or fp16 (default: all supported)");
       sub.add_option("--device", options->device, "device index or name substring (default: $VKVO_DEVICE or best)");
       return std::function<int()>([options] { return run(*options); });
     }}};

}  // namespace
