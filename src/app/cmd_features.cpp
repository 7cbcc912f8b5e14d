// `vkvo features`: SuperPoint on one image on the Vulkan device; writes the outputs as .npy in the layout of
// the golden outputs ($VKVO_DATA/golden/superpoint/*):
//   vkvo features --model superpoint.vkvopack --image IMG.png --out DIR [--precision fp16s] [--dense] [--config C]
// keypoints.npy (N x 2 float32 x,y), scores.npy (N), descriptors.npy (N x 256); with --dense also
// dense_scores.npy (H8 x W8) and dense_descriptors.npy (256 x H/8 x W/8).
#include <chrono>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <opencv2/imgcodecs.hpp>

#include "app/command.hpp"
#include "app/device_options.hpp"
#include "features/superpoint.hpp"
#include "io/atomic_file.hpp"
#include "io/image_io.hpp"
#include "io/model_pack.hpp"
#include "io/npy.hpp"
#include "runtime/context.hpp"
#include "system/vo_config.hpp"

namespace {

namespace fs = std::filesystem;
using namespace vkvo;

struct FeaturesOptions {
  std::string model, image, out, config;
  app::DeviceSelection device;
  bool dense = false;
};

int run_features(const FeaturesOptions& o) {
  features::SuperPointParams params = system::load_vo_config_or_defaults(o.config).point_detector;
  if (const auto precision = o.device.chosen_precision()) params.precision = *precision;
  const cv::Mat image = io::read_gray_image(o.image);
  const io::ModelPack pack = io::ModelPack::load(o.model, io::NetworkKind::superpoint);
  const rt::Context context(o.device.context_options());
  features::SuperPoint superpoint(context, pack, params);

  features::SuperPointDense dense;
  const auto start = std::chrono::steady_clock::now();
  const features::PointFeatures result = superpoint.detect(image, o.dense ? &dense : nullptr);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  spdlog::info("{}: {}x{}, {} keypoints ({} NMS candidates), {} on {}, {:.1f} ms (first run, includes setup)", o.image,
               image.cols, image.rows, result.size(), superpoint.last_candidate_count(),
               rt::to_string(superpoint.precision()), context.caps().name, ms);

  vkvo::io::create_output_folder(o.out);
  const fs::path out(o.out);
  std::vector<float> xy;
  for (const auto& k : result.keypoints) xy.insert(xy.end(), {k.x(), k.y()});
  io::write_npy(out / "keypoints.npy", {result.size(), 2}, xy.data());
  io::write_npy(out / "scores.npy", {result.size()}, result.scores.data());
  io::write_npy(out / "descriptors.npy", {result.size(), std::size_t(superpoint.descriptor_dim())},
                result.descriptors.data());
  if (o.dense) {
    const std::size_t ch = dense.cells_h, cw = dense.cells_w;
    io::write_npy(out / "dense_scores.npy", {ch * 8, cw * 8}, dense.scores.data());
    io::write_npy(out / "dense_descriptors.npy", {std::size_t(superpoint.descriptor_dim()), ch, cw},
                  dense.descriptors.data());
  }
  spdlog::info("wrote {}", out.string());
  return 0;
}

app::CommandRegistration registration{
    {"features", "SuperPoint keypoints + descriptors of one image on the Vulkan device (.npy outputs)",
     [](CLI::App& sub) {
       auto o = std::make_shared<FeaturesOptions>();
       sub.add_option("--model", o->model, "SuperPoint model pack (vkvo convert)")->required();
       sub.add_option("--image", o->image, "input image (converted to grayscale)")->required();
       sub.add_option("--out", o->out, "output folder")->required();
       app::add_precision_option(sub, o->device);
       sub.add_option("--config", o->config, "YAML config; its point_detector section sets the parameters")
           ->check(CLI::ExistingFile);
       app::add_device_option(sub, o->device);
       sub.add_flag("--dense", o->dense, "also write dense_scores.npy and dense_descriptors.npy");
       return std::function<int()>([o] { return run_features(*o); });
     }}};

}  // namespace
