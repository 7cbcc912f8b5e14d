#pragma once
// The PointFrontend of the real system: SuperPoint on the Vulkan device, matched by SuperGlue (when a pack is
// given) or by the mutual-nearest-neighbour matcher.
#include <memory>
#include <string>

#include "io/model_pack.hpp"
#include "runtime/context.hpp"
#include "system/point_frontend.hpp"
#include "system/vo_config.hpp"

namespace vkvo::system {

// `superglue` may be null: then the NN matcher with config.nn_matcher. Throws on an unusable pack or device.
std::unique_ptr<PointFrontend> make_network_frontend(const rt::Context& context, const io::ModelPack& superpoint,
                                                     const io::ModelPack* superglue, const VoConfig& config);

// Names everything SuperPoint's output depends on (weights, detector parameters, precision, device): the identity
// under which a FeatureCache keeps features on disk.
std::string detector_identity(const rt::Context& context, const io::ModelPack& superpoint, const VoConfig& config);

}  // namespace vkvo::system
