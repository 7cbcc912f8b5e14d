// `vkvo match`: matches two keypoint sets written by `vkvo features` with SuperGlue (a model pack) or the mutual
// nearest-neighbour fallback (`--model nn`), on the chosen Vulkan device.
//   vkvo match --model PACK|nn --features0 DIR --features1 DIR --image-size WxH --out DIR [--dense]
// Input folders hold keypoints.npy (N x 2 float32, pixels), scores.npy (N) and descriptors.npy (N x D). Writes
// matches0.npy (int32, -1 = unmatched), matching_scores0.npy (float32) and with --dense (SuperGlue only)
// log_assignment.npy ((N+1) x (M+1), dustbins last).
#include <chrono>
#include <filesystem>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "app/command.hpp"
#include "app/device_options.hpp"
#include "features/nn_matcher.hpp"
#include "features/superglue.hpp"
#include "io/atomic_file.hpp"
#include "io/config.hpp"
#include "io/npy.hpp"
#include "system/vo_config.hpp"

namespace {

namespace fs = std::filesystem;
using namespace vkvo;

struct MatchOptions {
  std::string model, features0, features1, image_size, out, config;
  app::DeviceSelection device;
  float threshold = -1;
  bool dense = false;
};

features::PointFeatures read_features(const fs::path& dir, int width, int height) {
  const io::NpyArray kp = io::read_npy(dir / "keypoints.npy");
  const io::NpyArray scores = io::read_npy(dir / "scores.npy");
  const io::NpyArray desc = io::read_npy(dir / "descriptors.npy");
  const std::size_t n = kp.shape.empty() ? 0 : kp.shape[0];
  if (kp.shape.size() != 2 || kp.shape[1] != 2)
    throw std::runtime_error(fmt::format("{}: keypoints.npy must have shape (N, 2)", dir.string()));
  if (scores.element_count() != n || desc.shape.size() != 2 || desc.shape[0] != n)
    throw std::runtime_error(
        fmt::format("{}: scores.npy (N) and descriptors.npy (N x D) must agree with the {} "
                    "keypoints",
                    dir.string(), n));
  features::PointFeatures f;
  f.image_width = width;
  f.image_height = height;
  const auto xy = kp.to_floats();
  for (std::size_t i = 0; i < n; ++i) f.keypoints.emplace_back(xy[2 * i], xy[2 * i + 1]);
  f.scores = scores.to_floats();
  const auto d = desc.to_floats();
  f.descriptors.resize(Eigen::Index(n), Eigen::Index(desc.shape[1]));
  std::copy(d.begin(), d.end(), f.descriptors.data());
  return f;
}

std::pair<int, int> parse_size(const std::string& text) {
  int w = 0, h = 0;
  char x = 0;
  std::istringstream in(text);
  if (!(in >> w >> x >> h) || (x != 'x' && x != 'X') || w <= 0 || h <= 0)
    throw std::runtime_error(fmt::format("--image-size '{}': expected WxH, e.g. 752x480", text));
  return {w, h};
}

int run(const MatchOptions& o) {
  const auto [width, height] = parse_size(o.image_size);
  const auto a = read_features(o.features0, width, height);
  const auto b = read_features(o.features1, width, height);
  const rt::Context context(o.device.context_options());
  const system::VoConfig config = system::load_vo_config_or_defaults(o.config);

  features::PointMatches matches;
  Eigen::MatrixXf dense;
  const auto start = std::chrono::steady_clock::now();
  if (o.model == "nn") {
    features::NnMatcher matcher(context, config.nn_matcher);
    matches = matcher.match(a, b);
  } else {
    auto params = config.point_matcher;
    if (o.threshold >= 0) params.match_threshold = o.threshold;
    if (const auto precision = o.device.chosen_precision()) params.precision = precision;
    const auto pack = io::ModelPack::load(o.model, io::NetworkKind::superglue);
    features::SuperGlue superglue(context, pack, params);
    spdlog::info("SuperGlue: {} layers, precision {}", superglue.config().cross_layers.size(),
                 rt::to_string(superglue.precision()));
    matches = superglue.match(a, b, o.dense ? &dense : nullptr);
  }
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  spdlog::info("{} x {} keypoints: {} matches ({:.1f} ms)", a.size(), b.size(), matches.count(), ms);

  vkvo::io::create_output_folder(o.out);
  const fs::path out(o.out);
  io::write_npy(out / "matches0.npy", {matches.matches0.size()}, matches.matches0.data());
  io::write_npy(out / "matching_scores0.npy", {matches.scores0.size()}, matches.scores0.data());
  if (o.dense && o.model != "nn") {
    const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows = dense;
    io::write_npy(out / "log_assignment.npy", {std::size_t(rows.rows()), std::size_t(rows.cols())}, rows.data());
  } else if (o.dense) {
    spdlog::warn("--dense: the nearest-neighbour matcher has no log-assignment; not written");
  }
  return 0;
}

vkvo::app::CommandRegistration registration{
    {"match", "match two keypoint sets (SuperGlue model pack, or 'nn' for mutual nearest neighbours)",
     [](CLI::App& sub) {
       auto o = std::make_shared<MatchOptions>();
       sub.add_option("--model", o->model, "SuperGlue model pack (.vkvopack), or 'nn'")->required();
       sub.add_option("--features0", o->features0, "folder of image 0's keypoints/scores/descriptors .npy")->required();
       sub.add_option("--features1", o->features1, "folder of image 1's keypoints/scores/descriptors .npy")->required();
       sub.add_option("--image-size", o->image_size, "WxH of the images (keypoint normalisation)")->required();
       sub.add_option("--out", o->out, "output folder")->required();
       sub.add_flag("--dense", o->dense, "also write log_assignment.npy (SuperGlue)");
       sub.add_option("--config", o->config, "YAML with point_matcher / nn_matcher sections")->check(CLI::ExistingFile);
       sub.add_option("--threshold", o->threshold, "SuperGlue match threshold (default 0.2 or the config's)")
           ->check(CLI::Range(0.0, 1.0));
       app::add_precision_option(sub, o->device);
       app::add_device_option(sub, o->device);
       return std::function<int()>([o] { return run(*o); });
     }}};

}  // namespace
