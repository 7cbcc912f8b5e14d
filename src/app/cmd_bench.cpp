// `vkvo bench`: GPU-timestamped timings of the kernels (median ms and GFLOP/s per kernel and precision) on the
// chosen device.
#include <algorithm>
#include <memory>
#include <vector>

#include <fmt/format.h>

#include "app/bench_registry.hpp"
#include "app/command.hpp"
#include "app/device_options.hpp"
#include "app/kernel_bench.hpp"
#include "runtime/context.hpp"
#include "runtime/host.hpp"

namespace {

struct Options {
  int repeat = 10;
  std::vector<std::string> precisions;
  vkvo::app::DeviceSelection device;
  std::string model;
  bool kernels = false;
  std::string filter;
  std::string winograd = "auto";
  int winograd_tile = 0;
  std::vector<std::size_t> keypoints{200, 400, 1000};
  std::string attention = "auto", sinkhorn = "auto";
  std::vector<std::string> networks;  // names of the --<network> flags given
};

int run(const Options& options) {
  const vkvo::rt::Context context(options.device.context_options());
  const auto& caps = context.caps();
  fmt::print("device: {} ({}), {}\n", caps.name, caps.type, caps.driver);
  // A CPU device's figures are the host's (runtime/host.hpp); a GPU's still include its uploads and submissions.
  fmt::print("host: {}\n", vkvo::rt::host_cpu().describe());
  std::vector<vkvo::rt::Precision> precisions;
  for (const auto& name : options.precisions) {
    precisions.push_back(*vkvo::rt::parse_precision(name));  // CLI11 has checked the name
  }
  if (precisions.empty())
    for (auto p : vkvo::rt::kAllPrecisions)
      if (caps.supports(p)) precisions.push_back(p);
  std::erase_if(precisions, [&](vkvo::rt::Precision p) {
    if (caps.supports(p)) return false;
    fmt::print("precision {} is not supported on this device: skipped\n", vkvo::rt::to_string(p));
    return true;
  });
  if (precisions.empty()) return 1;
  int status = 0;
  if (options.kernels || options.networks.empty()) {
    vkvo::app::print_bench_header();
    for (auto p : precisions)
      for (const auto& result : vkvo::app::bench_kernels(context, p, options.repeat, options.filter))
        vkvo::app::print_bench_row(result);
  }
  const vkvo::app::BenchOptions bench_options{
      options.repeat,        precisions,        options.model,     options.winograd,
      options.winograd_tile, options.keypoints, options.attention, options.sinkhorn};
  for (const auto& bench : vkvo::app::network_bench_registry())
    if (std::find(options.networks.begin(), options.networks.end(), bench.name) != options.networks.end())
      status |= bench.run(context, bench_options);
  return status;
}

vkvo::app::CommandRegistration registration{
    {"bench", "time the compute kernels on the chosen device (median ms, GFLOP/s)", [](CLI::App& sub) {
       auto options = std::make_shared<Options>();
       sub.add_option("--repeat", options->repeat, "timed submissions per kernel")->check(CLI::PositiveNumber);
       vkvo::app::add_precision_list_option(sub, options->precisions);
       vkvo::app::add_device_option(sub, options->device);
       sub.add_option("--model", options->model, "model pack for the network benchmarks");
       sub.add_flag("--kernels", options->kernels, "the single-kernel table (default when no network is named)");
       sub.add_option("--winograd", options->winograd, "SuperPoint's 3x3 convolutions by Winograd F(m x m, 3x3)")
           ->check(CLI::IsMember({"auto", "on", "off"}));
       sub.add_option("--winograd-tile", options->winograd_tile,
                      "SuperPoint's Winograd output tile: 4 (F(4x4,3x3)) or 6 (F(6x6,3x3); default)")
           ->check(CLI::IsMember({4, 6}));
       sub.add_option("--keypoints", options->keypoints,
                      "SuperGlue: keypoints per image, N = M (default: 200 400 1000)")
           ->check(CLI::Range(std::size_t{1}, std::size_t{2048}));
       sub.add_option("--attention", options->attention,
                      "SuperGlue's fused attention: shared-memory tiles (GPUs' choice) or rows in registers (CPUs')")
           ->check(CLI::IsMember({"auto", "shared", "registers"}));
       sub.add_option("--sinkhorn", options->sinkhorn,
                      "SuperGlue's Sinkhorn: one fused workgroup (up to 1023 keypoints), or two dispatches per "
                      "iteration with a workgroup (GPUs' choice) or an invocation (CPUs') per line")
           ->check(CLI::IsMember({"auto", "fused", "workgroup-per-line", "invocation-per-line"}));
       sub.add_option("--filter", options->filter, "kernel table: only kernels whose name contains this (e.g. gemm)");
       for (const auto& bench : vkvo::app::network_bench_registry())
         sub.add_flag_callback(
             "--" + bench.name, [options, name = bench.name] { options->networks.push_back(name); }, bench.description);
       return std::function<int()>([options] { return run(*options); });
     }}};

}  // namespace
