#include "features/superpoint.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "features/superpoint/network.hpp"
#include "io/config.hpp"

namespace vkvo::features {

std::optional<SuperPointParams::Winograd> parse_winograd(std::string_view text) {
  if (text == "auto") return SuperPointParams::Winograd::automatic;
  if (text == "on") return SuperPointParams::Winograd::on;
  if (text == "off") return SuperPointParams::Winograd::off;
  return std::nullopt;
}

std::optional<rt::WinogradConv3x3::Tile> winograd_tile_from_side(int side) {
  if (side == 4) return rt::WinogradConv3x3::Tile::f43;
  if (side == 6) return rt::WinogradConv3x3::Tile::f63;
  return std::nullopt;
}

SuperPointParams load_superpoint_params(const YAML::Node& section) {
  SuperPointParams params;
  io::read_param(section, "keypoint_threshold", params.keypoint_threshold);
  io::read_param(section, "nms_radius", params.nms_radius);
  io::read_param(section, "remove_borders", params.remove_borders);
  io::read_param(section, "max_keypoints", params.max_keypoints);
  io::read_param(section, "subpixel", params.subpixel);
  std::string precision = "auto";
  io::read_param(section, "precision", precision);
  if (precision == "auto") {
    params.precision.reset();
  } else if (const auto p = rt::parse_precision(precision)) {
    params.precision = *p;
  } else {
    throw std::runtime_error(
        fmt::format("config key 'precision': expected auto, fp32, fp16s or fp16, got '{}'", precision));
  }
  std::string winograd = "auto";
  io::read_param(section, "winograd", winograd);
  if (const auto choice = parse_winograd(winograd))
    params.winograd = *choice;
  else
    throw std::runtime_error(fmt::format("config key 'winograd': expected auto, on or off, got '{}'", winograd));
  int tile_side = static_cast<int>(params.winograd_tile);
  io::read_param(section, "winograd_tile", tile_side);
  if (const auto tile = winograd_tile_from_side(tile_side))
    params.winograd_tile = *tile;
  else
    throw std::runtime_error(fmt::format("config key 'winograd_tile': expected 4 or 6, got {}", tile_side));
  if (params.keypoint_threshold < 0.0f) throw std::runtime_error("config key 'keypoint_threshold': must be >= 0");
  if (params.nms_radius < 0) throw std::runtime_error("config key 'nms_radius': must be >= 0");
  return params;
}

SuperPoint::SuperPoint(const rt::Context& context, const io::ModelPack& pack, const SuperPointParams& params)
    : context_(context), params_(params), precision_(params.precision.value_or(context.profile().precision)) {
  if (pack.kind() != io::NetworkKind::superpoint)
    throw std::runtime_error(fmt::format("model pack '{}' is not a SuperPoint pack", pack.source()));
  context.caps().require(precision_, "SuperPoint");
  if (params.keypoint_threshold < 0.0f || params.nms_radius < 0)
    throw std::invalid_argument("SuperPoint: keypoint_threshold and nms_radius must be >= 0");
  if (pack.has("detector_channels") && pack.integer("detector_channels") != 65)
    throw std::runtime_error(fmt::format("model pack '{}': detector_channels must be 65", pack.source()));
  network_ = std::make_unique<SuperPointNetwork>(context, pack, precision_, params.tiled_kernels, params.winograd,
                                                 params.winograd_tile);
  descriptor_dim_ = static_cast<int>(network_->convs[convDb].out_channels);
}

SuperPoint::~SuperPoint() = default;

SuperPointPlan& SuperPoint::plan_for(int width, int height) {
  auto& plan = plans_[{width, height}];
  if (!plan) plan = std::make_unique<SuperPointPlan>(context_, *network_, params_, width, height, profiling_);
  return *plan;
}

PointFeatures SuperPoint::detect(const cv::Mat& image, SuperPointDense* dense) {
  if (image.empty() || image.type() != CV_8UC1)
    throw std::invalid_argument("SuperPoint::detect: expected a non-empty 8-bit grayscale image (CV_8UC1)");
  if (image.cols < 16 || image.rows < 16)
    throw std::invalid_argument(
        fmt::format("SuperPoint::detect: image {}x{} is smaller than 16x16", image.cols, image.rows));
  SuperPointPlan& plan = plan_for(image.cols, image.rows);
  last_plan_ = &plan;
  last_candidates_ = plan.run(image.ptr<std::uint8_t>(0), image.step[0]);
  const std::uint32_t count = plan.keypoint_count(last_candidates_);

  PointFeatures result;
  result.image_width = image.cols;
  result.image_height = image.rows;
  std::vector<float> xy, descriptors;
  plan.download(count, xy, result.scores, descriptors);
  result.keypoints.resize(count);
  for (std::uint32_t i = 0; i < count; ++i) result.keypoints[i] = {xy[2 * i], xy[2 * i + 1]};
  result.descriptors.resize(count, descriptor_dim_);
  if (count) std::copy(descriptors.begin(), descriptors.end(), result.descriptors.data());
  if (dense) {
    dense->cells_h = static_cast<int>(plan.cells_h());
    dense->cells_w = static_cast<int>(plan.cells_w());
    plan.download_dense(dense->scores, dense->descriptors);
  }
  return result;
}

void SuperPoint::set_profiling(bool on) {
  if (on == profiling_) return;
  profiling_ = on;
  plans_.clear();  // rebuilt with or without timestamps at the next detect()
  last_plan_ = nullptr;
}

std::vector<rt::CommandTiming> SuperPoint::last_timings() const {
  return last_plan_ ? last_plan_->sequence().timings() : std::vector<rt::CommandTiming>{};
}

double SuperPoint::network_flops(int width, int height) {
  double flops = 0;
  double h = height, w = width;
  const auto conv = [&](double in, double out, double k) { flops += 2.0 * h * w * in * out * k * k; };
  conv(1, 64, 3), conv(64, 64, 3);
  h = height / 2, w = width / 2;
  conv(64, 64, 3), conv(64, 64, 3);
  h = height / 4, w = width / 4;
  conv(64, 128, 3), conv(128, 128, 3);
  h = height / 8, w = width / 8;
  conv(128, 128, 3), conv(128, 128, 3);
  conv(128, 256, 3), conv(256, 65, 1), conv(128, 256, 3), conv(256, 256, 1);
  return flops;
}

}  // namespace vkvo::features
