// `vkvo bench --superglue --model PACK [--keypoints N ...]`: SuperGlue end to end on the chosen device at N = M =
// 200, 400, 1000 (or the given counts) random keypoints, per precision: median wall-clock ms of match() (upload,
// one submit, download) and GFLOP/s, then one profiled call's per-dispatch GPU timestamps summed per stage.
#include <algorithm>
#include <chrono>
#include <map>
#include <random>

#include <fmt/format.h>

#include "app/bench_registry.hpp"
#include "app/kernel_bench.hpp"
#include "features/superglue.hpp"

namespace {

using namespace vkvo;

// "self attn q.k" -> "attn q.k": stages summed over layers.
std::string stage_of(const std::string& label) {
  for (const char* prefix : {"self ", "cross "})
    if (label.rfind(prefix, 0) == 0) return label.substr(std::string(prefix).size());
  return label;
}

int run(const rt::Context& context, const app::BenchOptions& options) {
  if (options.model.empty()) {
    fmt::print("--superglue needs --model PACK (a SuperGlue model pack from `vkvo convert`)\n");
    return 1;
  }
  const auto pack = io::ModelPack::load(options.model, io::NetworkKind::superglue);
  for (rt::Precision precision : options.precisions) {
    features::SuperGlueParams params{.precision = precision};
    if (options.attention != "auto") params.shared_attention = options.attention == "shared";
    if (options.sinkhorn != "auto") {
      params.fused_sinkhorn = options.sinkhorn == "fused";
      params.sinkhorn_workgroup_per_line = options.sinkhorn == "workgroup-per-line";
    }
    features::SuperGlue net(context, pack, params);
    const int dim = net.config().descriptor_dim;
    fmt::print("\nSuperGlue ({} layers, {} Sinkhorn iterations), precision {}, attention {}\n",
               net.config().cross_layers.size(), net.config().sinkhorn_iterations, rt::to_string(precision),
               net.attention_form());
    fmt::print("{:>6} {:>10} {:>9} {:>10} {:>9}\n", "N=M", "wall ms", "GFLOP", "GFLOP/s", "matches");
    std::mt19937 rng(1);
    for (std::size_t n : options.keypoints) {
      const auto a = features::random_point_features(n, dim, rng, 752, 480);
      auto b = a;  // the same points, slightly perturbed: a realistic share of matches
      std::normal_distribution<float> noise(0.0f, 0.05f);
      for (Eigen::Index i = 0; i < b.descriptors.rows(); ++i) {
        for (int c = 0; c < dim; ++c) b.descriptors(i, c) += noise(rng);
        b.descriptors.row(i).normalize();
      }
      // Timed as the VO runs it, without per-dispatch timestamps; then one profiled call for the stage table.
      net.set_profiling(false);
      std::size_t matched = net.match(a, b).count();  // warm-up: allocation and recording
      std::vector<double> wall;
      for (int r = 0; r < options.repeat; ++r) {
        const auto start = std::chrono::steady_clock::now();
        matched = net.match(a, b).count();
        wall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
      }
      const double ms = app::median_ms(wall), flops = net.flops(n, n);
      fmt::print("{:>6} {:>10.1f} {:>9.2f} {:>10.1f} {:>9}\n", n, ms, flops * 1e-9, flops * 1e-6 / ms, matched);
      net.set_profiling(true);
      net.match(a, b);
      const auto timings = net.last_timings();
      if (timings.empty()) continue;  // no timestamps on this device
      double profiled_ms = 0;
      for (const auto& t : timings) profiled_ms += t.ms;
      fmt::print("         one profiled call: {:.1f} ms of GPU time (timestamps add ~35 us per dispatch on lavapipe)\n",
                 profiled_ms);
      std::map<std::string, std::pair<double, int>> stages;
      for (const auto& t : timings) {
        auto& s = stages[stage_of(t.label)];
        s.first += t.ms;
        s.second += 1;
      }
      std::vector<std::pair<std::string, std::pair<double, int>>> sorted(stages.begin(), stages.end());
      std::sort(sorted.begin(), sorted.end(),
                [](const auto& x, const auto& y) { return x.second.first > y.second.first; });
      for (const auto& [stage, s] : sorted)
        fmt::print("         {:<22} {:>8.2f} ms  {:>4} dispatches\n", stage, s.first, s.second);
    }
  }
  return 0;
}

app::NetworkBenchRegistration registration{
    {"superglue", "SuperGlue end to end at N = M = 200, 400, 1000 or --keypoints (needs --model PACK)", run}};

}  // namespace
