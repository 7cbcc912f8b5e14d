#pragma once
// Finding the network weights for `vkvo run`, in this order: an explicit path (a .vkvopack, or an .onnx converted
// on first use), $VKVO_MODELS, the checkout's models/ folder, then the models/ folder of the shared data
// ($VKVO_DATA, or ../shared next to the working directory or the checkout). In each folder `<stem>.vkvopack` is
// taken before `<stem>.onnx`. ONNX files are converted once into the cache folder ($VKVO_CACHE_DIR, else
// $XDG_CACHE_HOME/vkvo or ~/.cache/vkvo), keyed by name, size and modification time. Nothing is downloaded, and
// nothing falls back silently to weights that are not the real network.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/model_pack.hpp"

namespace vkvo::convert {

struct LocatedModel {
  std::filesystem::path pack;
  std::string how;  // "given", "$VKVO_MODELS", "... (converted from ...)", for the log
};

// The folders searched after an explicit path, in order, each with how it was chosen (for the log).
struct ModelSearch {
  struct Folder {
    std::filesystem::path path;
    std::string how;
  };
  std::vector<Folder> folders;
};

// $VKVO_MODELS, `checkout`/models (when `checkout` is not empty), $VKVO_DATA/models, ../shared/models next to
// the working directory and next to `checkout`: read from the environment now.
ModelSearch default_model_search(const std::filesystem::path& checkout);

// `stem`: "superpoint_v1" or "superglue_indoor" etc. `explicit_path`: --model or the config value (may be empty).
// Returns nullopt when nothing is found; throws when an explicit path is given but unusable, or a conversion fails.
std::optional<LocatedModel> locate_model(const std::string& stem, const std::filesystem::path& explicit_path,
                                         const ModelSearch& search);

// How to obtain and convert the official SuperPoint weights (printed when no pack is found).
std::string superpoint_help();

// The packs the VO runs with (`vkvo run`, and the Python Odometry and run): SuperPoint from `superpoint` (a pack
// or ONNX file; empty: "superpoint_v1" searched in `search`), and, when `use_superglue`, SuperGlue from
// `superglue` (empty: none, and the VO matches with the mutual-nearest-neighbour matcher, which is logged).
// Throws superpoint_help() when no SuperPoint is found, and naming the file when one cannot be used.
struct VoModels {
  io::ModelPack superpoint;
  std::optional<io::ModelPack> superglue;
  LocatedModel superpoint_file;
  std::optional<LocatedModel> superglue_file;
};
VoModels load_vo_models(const std::filesystem::path& superpoint, const std::filesystem::path& superglue,
                        bool use_superglue, const ModelSearch& search);

}  // namespace vkvo::convert
