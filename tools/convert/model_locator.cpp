#include "tools/convert/model_locator.hpp"

#include <cstdlib>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "tools/convert/convert.hpp"

namespace vkvo::convert {
namespace {

namespace fs = std::filesystem;

fs::path cache_dir() {
  if (const char* dir = std::getenv("VKVO_CACHE_DIR"); dir && *dir) return dir;
  if (const char* dir = std::getenv("XDG_CACHE_HOME"); dir && *dir) return fs::path(dir) / "vkvo";
  if (const char* home = std::getenv("HOME"); home && *home) return fs::path(home) / ".cache" / "vkvo";
  return fs::temp_directory_path() / "vkvo-cache";
}

// A pack for `file`: itself when it is one, else its conversion, cached by name, size and modification time.
LocatedModel as_pack(const fs::path& file, const std::string& how) {
  if (!fs::is_regular_file(file)) throw std::runtime_error(fmt::format("model file {} does not exist", file.string()));
  if (file.extension() != ".onnx") return {file, how};
  const auto stamp = fs::last_write_time(file).time_since_epoch().count();
  const fs::path pack = cache_dir() / fmt::format("{}-{}-{:x}.vkvopack", file.stem().string(), fs::file_size(file),
                                                  static_cast<unsigned long long>(stamp));
  if (!fs::exists(pack)) {
    fs::create_directories(pack.parent_path());
    spdlog::info("converting {} -> {} (once)", file.string(), pack.string());
    const fs::path tmp = pack.string() + ".tmp";
    convert_file(file, tmp);
    fs::rename(tmp, pack);
  }
  return {pack, fmt::format("{} (converted from {})", how, file.string())};
}

std::optional<LocatedModel> find_in(const fs::path& dir, const std::string& stem, const std::string& how) {
  for (const char* ext : {".vkvopack", ".onnx"}) {
    const fs::path file = dir / (stem + ext);
    if (fs::is_regular_file(file)) return as_pack(file, how);
  }
  return std::nullopt;
}

}  // namespace

ModelSearch default_model_search(const fs::path& checkout) {
  ModelSearch search;
  if (const char* models = std::getenv("VKVO_MODELS"); models && *models)
    search.folders.push_back({models, "$VKVO_MODELS"});
  if (!checkout.empty()) search.folders.push_back({checkout / "models", "the checkout's models/"});
  if (const char* data = std::getenv("VKVO_DATA"); data && *data)
    search.folders.push_back({fs::path(data) / "models", "shared data ($VKVO_DATA)"});
  search.folders.push_back({fs::current_path() / ".." / "shared" / "models", "shared data"});
  if (!checkout.empty()) search.folders.push_back({checkout / ".." / "shared" / "models", "shared data"});
  return search;
}

std::optional<LocatedModel> locate_model(const std::string& stem, const fs::path& explicit_path,
                                         const ModelSearch& search) {
  if (!explicit_path.empty()) return as_pack(explicit_path, "given");
  for (const auto& folder : search.folders)
    if (auto found = find_in(folder.path, stem, folder.how)) return found;
  return std::nullopt;
}

std::string superpoint_help() {
  return "no SuperPoint weights found. vkvo looks for superpoint_v1.vkvopack or superpoint_v1.onnx in --model, "
         "$VKVO_MODELS, the checkout's models/ folder, then $VKVO_DATA/models or ../shared/models. To make one: "
         "export Magic Leap's superpoint_v1.pth (SuperPointPretrainedNetwork, non-commercial research licence) to "
         "ONNX with torch.onnx.export (opset 13, input 1x1xHxW with dynamic H/W), or take the superpoint_v1.onnx "
         "that AirVO ships, and put it in models/ (converted on first use), or run `vkvo convert --onnx "
         "superpoint_v1.onnx --out models/superpoint_v1.vkvopack` (models/README.md).";
}

VoModels load_vo_models(const fs::path& superpoint, const fs::path& superglue, bool use_superglue,
                        const ModelSearch& search) {
  VoModels models;
  auto superpoint_file = locate_model("superpoint_v1", superpoint, search);
  if (!superpoint_file) throw std::runtime_error(superpoint_help());
  spdlog::info("SuperPoint: {} [{}]", superpoint_file->pack.string(), superpoint_file->how);
  models.superpoint = io::ModelPack::load(superpoint_file->pack, io::NetworkKind::superpoint);
  models.superpoint_file = std::move(*superpoint_file);
  if (!use_superglue) return models;
  if (superglue.empty()) {
    spdlog::warn(
        "no SuperGlue pack configured (models.superglue / --superglue): matching with the "
        "mutual-nearest-neighbour matcher");
    return models;
  }
  models.superglue_file = locate_model("superglue", superglue, search);  // an explicit path: found or thrown
  spdlog::info("SuperGlue: {} [{}]", models.superglue_file->pack.string(), models.superglue_file->how);
  models.superglue = io::ModelPack::load(models.superglue_file->pack, io::NetworkKind::superglue);
  return models;
}

}  // namespace vkvo::convert
