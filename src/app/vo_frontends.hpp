#pragma once
// What `vkvo run` and `vkvo robustness` set up before a run: the SuperPoint pack (and SuperGlue's, when the config
// matches with it) found and loaded, the Vulkan device, the two point frontends of the VO's stages and, on request,
// a feature cache in front of both.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "runtime/context.hpp"
#include "system/feature_cache.hpp"
#include "system/point_frontend.hpp"
#include "system/vo_config.hpp"
#include "tools/convert/model_locator.hpp"

namespace vkvo::app {

struct FrontendOptions {
  std::filesystem::path superpoint, superglue;         // overrides of the config's models (pack or ONNX)
  rt::ContextOptions device;                           // which Vulkan device
  std::optional<std::filesystem::path> feature_cache;  // a folder: features kept on disk across runs
  bool cache_in_memory = false;                        // no folder, but each image's features computed once
};

class VoFrontends {
 public:
  // Throws with the reason (no SuperPoint weights found, unusable pack, no device).
  VoFrontends(const system::VoConfig& config, const FrontendOptions& options);

  system::PointFrontend& feature() { return cached_feature_ ? *cached_feature_ : *feature_network_; }
  system::PointFrontend& stereo() { return cached_stereo_ ? *cached_stereo_ : *stereo_network_; }
  const std::optional<system::FeatureCache>& cache() const { return cache_; }
  // Device, host, matcher and model, for a run's summary.json.
  const nlohmann::json& description() const { return description_; }

 private:
  convert::VoModels models_;
  rt::Context context_;
  std::unique_ptr<system::PointFrontend> feature_network_, stereo_network_;
  std::optional<system::FeatureCache> cache_;
  std::optional<system::CachedFrontend> cached_feature_, cached_stereo_;
  nlohmann::json description_;
};

}  // namespace vkvo::app
