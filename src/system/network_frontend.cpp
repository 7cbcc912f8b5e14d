#include "system/network_frontend.hpp"

#include <string_view>

#include <fmt/format.h>

#include "features/nn_matcher.hpp"
#include "features/superglue.hpp"
#include "features/superpoint.hpp"

namespace vkvo::system {
namespace {

class NetworkFrontend final : public PointFrontend {
 public:
  NetworkFrontend(const rt::Context& context, const io::ModelPack& superpoint, const io::ModelPack* superglue,
                  const VoConfig& config)
      : detector_(context, superpoint, config.point_detector) {
    if (superglue)
      matcher_ = std::make_unique<features::SuperGlue>(context, *superglue, config.point_matcher);
    else
      matcher_ = std::make_unique<features::NnMatcher>(context, config.nn_matcher);
  }

  features::PointFeatures detect(const cv::Mat& gray) override { return detector_.detect(gray); }
  features::PointMatches match(const features::PointFeatures& a, const features::PointFeatures& b) override {
    return matcher_->match(a, b);
  }

 private:
  features::SuperPoint detector_;
  std::unique_ptr<features::PointMatcher> matcher_;
};

}  // namespace

std::unique_ptr<PointFrontend> make_network_frontend(const rt::Context& context, const io::ModelPack& superpoint,
                                                     const io::ModelPack* superglue, const VoConfig& config) {
  return std::make_unique<NetworkFrontend>(context, superpoint, superglue, config);
}

std::string detector_identity(const rt::Context& context, const io::ModelPack& superpoint, const VoConfig& config) {
  const auto weights = superpoint.data_block();
  const auto& p = config.point_detector;
  return fmt::format(
      "superpoint weights {:016x} ({} bytes) | threshold {} nms {} borders {} max {} subpixel {} | precision {} | "
      "tiled {} winograd {} tile {} | device {}",
      std::hash<std::string_view>{}(std::string_view(reinterpret_cast<const char*>(weights.data()), weights.size())),
      weights.size(), p.keypoint_threshold, p.nms_radius, p.remove_borders, p.max_keypoints, p.subpixel,
      p.precision ? rt::to_string(*p.precision) : "auto", p.tiled_kernels, static_cast<int>(p.winograd),
      static_cast<int>(p.winograd_tile), context.caps().name);
}

}  // namespace vkvo::system
