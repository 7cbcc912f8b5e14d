#include "system/network_frontend.hpp"

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

}  // namespace vkvo::system
