#pragma once
// Finding the network weights for `vkvo run` and the demo, in this order: an explicit path (a .vkvopack, or an
// .onnx converted on first use), $VKVO_MODELS, then the models/ folder of the shared data ($VKVO_DATA or
// ../shared next to the working directory or the checkout). ONNX files are converted into the cache folder once.
// Nothing is downloaded, and nothing falls back silently to weights that are not the real network.
#include <filesystem>
#include <optional>
#include <string>

namespace vkvo::app {

struct LocatedModel {
  std::filesystem::path pack;
  std::string how;  // "given", "converted from ...", for the log
};

// `stem`: "superpoint_v1" or "superglue_indoor" etc. `explicit_path`: --model or the config value (may be empty).
// Returns nullopt when nothing is found; throws when an explicit path is given but unusable.
std::optional<LocatedModel> locate_model(const std::string& stem, const std::filesystem::path& explicit_path);

// How to obtain and convert the official SuperPoint weights (printed when no pack is found).
std::string superpoint_help();

}  // namespace vkvo::app
