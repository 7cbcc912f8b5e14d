#include "app/vo_frontends.hpp"

#include <spdlog/spdlog.h>

#include "runtime/host.hpp"
#include "system/network_frontend.hpp"

namespace vkvo::app {

VoFrontends::VoFrontends(const system::VoConfig& config, const FrontendOptions& options)
    : models_(convert::load_vo_models(options.superpoint.empty() ? config.superpoint_model : options.superpoint,
                                      options.superglue.empty() ? config.superglue_model : options.superglue,
                                      config.matcher == "superglue", convert::default_model_search(VKVO_SOURCE_DIR))),
      context_(options.device) {
  const std::string host = rt::host_cpu().describe();
  spdlog::info("Vulkan device: {} ({}); host: {}", context_.caps().name, context_.caps().type, host);
  const io::ModelPack* superglue = models_.superglue ? &*models_.superglue : nullptr;
  feature_network_ = system::make_network_frontend(context_, models_.superpoint, superglue, config);
  stereo_network_ = system::make_network_frontend(context_, models_.superpoint, superglue, config);
  if (options.feature_cache)
    cache_.emplace(*options.feature_cache, system::detector_identity(context_, models_.superpoint, config));
  else if (options.cache_in_memory)
    cache_.emplace();
  if (cache_) {
    cached_feature_.emplace(*feature_network_, *cache_);
    cached_stereo_.emplace(*stereo_network_, *cache_);
  }
  description_ = {{"device", context_.caps().name},
                  {"host", host},
                  {"matcher", superglue ? "superglue" : "nn"},
                  {"superpoint_model", models_.superpoint_file.pack.string()}};
}

}  // namespace vkvo::app
