// `vkvo bench --superpoint --model PACK`: whole SuperPoint::detect (image upload to keypoints back) at 640x480 and
// 752x480 per precision: median wall ms, GFLOP/s of the network's convolutions, and the per-command GPU
// timestamp breakdown (median over as many profiled runs).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>

#include <fmt/format.h>
#include <opencv2/core.hpp>

#include "app/bench_registry.hpp"
#include "app/kernel_bench.hpp"
#include "features/superpoint.hpp"
#include "io/model_pack.hpp"

namespace {

using namespace vkvo;

// Deterministic texture (the timing does not depend on the content except for the few post-processing ms).
cv::Mat bench_image(int width, int height) {
  cv::Mat image(height, width, CV_8UC1);
  cv::RNG rng(1);
  rng.fill(image, cv::RNG::UNIFORM, 0, 255);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      image.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(0.5 * image.at<std::uint8_t>(y, x) + 64 +
                                                                     60 * std::sin(0.05 * x) * std::cos(0.07 * y));
  return image;
}

void bench_size(features::SuperPoint& sp, int width, int height, int repeat) {
  const cv::Mat image = bench_image(width, height);
  // Timed as the VO runs it, without per-command timestamps; then as many profiled runs for the command table.
  sp.set_profiling(false);
  sp.detect(image);  // warm-up: buffers, recording, first touch
  std::vector<double> wall;
  std::size_t keypoints = 0;
  for (int i = 0; i < repeat; ++i) {
    const auto start = std::chrono::steady_clock::now();
    keypoints = sp.detect(image).size();
    wall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  sp.set_profiling(true);
  sp.detect(image);
  std::vector<std::vector<double>> per_command;
  std::vector<std::string> labels;
  for (int i = 0; i < repeat; ++i) {
    sp.detect(image);
    const auto timings = sp.last_timings();
    per_command.resize(timings.size());
    labels.resize(timings.size());
    for (std::size_t c = 0; c < timings.size(); ++c)
      per_command[c].push_back(timings[c].ms), labels[c] = timings[c].label;
  }
  const double ms = app::median_ms(wall);
  const double gflop = features::SuperPoint::network_flops(width, height) * 1e-9;
  fmt::print(
      "superpoint {:>5} {}x{}: {:8.1f} ms median detect ({} runs), {:6.1f} GFLOP/s ({:.1f} GFLOP), "
      "{} keypoints\n",
      rt::to_string(sp.precision()), width, height, ms, repeat, gflop / (ms * 1e-3), gflop, keypoints);
  if (labels.empty()) return;
  // Commands sharing a label (a Winograd layer's bands) are summed into one row, in the order they first ran.
  std::vector<std::pair<std::string, double>> rows;
  double total = 0;
  for (std::size_t c = 0; c < labels.size(); ++c) {
    const double t = app::median_ms(per_command[c]);
    total += t;
    const auto row = std::find_if(rows.begin(), rows.end(), [&](const auto& r) { return r.first == labels[c]; });
    if (row == rows.end())
      rows.emplace_back(labels[c], t);
    else
      row->second += t;
  }
  fmt::print("  {:<32} {:>9} {:>6}\n", "command (GPU timestamps)", "ms", "%");
  for (const auto& [label, t] : rows) fmt::print("  {:<32} {:9.2f} {:5.1f}%\n", label, t, 100.0 * t / total);
  fmt::print("  {:<32} {:9.2f}\n", "sum", total);
}

int run(const rt::Context& context, const app::BenchOptions& options) {
  if (options.model.empty()) {
    fmt::print(stderr, "--superpoint needs --model PACK (vkvo convert --onnx superpoint_v1.onnx --out PACK)\n");
    return 1;
  }
  const io::ModelPack pack = io::ModelPack::load(options.model, io::NetworkKind::superpoint);
  for (const auto precision : options.precisions) {
    features::SuperPointParams params;
    params.precision = precision;
    params.winograd = *features::parse_winograd(options.winograd);
    if (options.winograd_tile) params.winograd_tile = *features::winograd_tile_from_side(options.winograd_tile);
    features::SuperPoint sp(context, pack, params);
    for (const auto& [w, h] : {std::pair{640, 480}, std::pair{752, 480}}) bench_size(sp, w, h, options.repeat);
  }
  return 0;
}

app::NetworkBenchRegistration registration{
    {"superpoint", "SuperPoint detect at 640x480 and 752x480 (needs --model)", run}};

}  // namespace
