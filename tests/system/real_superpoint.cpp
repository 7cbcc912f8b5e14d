#include "system/real_superpoint.hpp"

#include "common/gpu.hpp"
#include "common/test_support.hpp"
#include "system/network_frontend.hpp"
#include "tools/convert/convert.hpp"
#include "tools/synth/perturb.hpp"

namespace vkvo::test {
namespace {

io::ModelPack convert_pack(const std::filesystem::path& onnx, const std::filesystem::path& pack) {
  convert::convert_file(onnx, pack, io::NetworkKind::superpoint);
  return io::ModelPack::load(pack, io::NetworkKind::superpoint);
}

}  // namespace

RealSuperPoint::RealSuperPoint(const std::filesystem::path& onnx, const system::VoConfig& config,
                               const std::filesystem::path& dir)
    : pack_(convert_pack(onnx, dir / "superpoint.vkvopack")),
      feature_network_(system::make_network_frontend(gpu(), pack_, nullptr, config)),
      stereo_network_(system::make_network_frontend(gpu(), pack_, nullptr, config)),
      cache_(feature_cache_dir(), system::detector_identity(gpu(), pack_, config)),
      feature_frontend_(*feature_network_, cache_),
      stereo_frontend_(*stereo_network_, cache_) {}

VoRun RealSuperPoint::run(const std::filesystem::path& dataset, const system::VoConfig& config,
                          const std::filesystem::path& out_dir, const io::FrameRange& range) {
  return run_vo_on(dataset, config, feature_frontend_, stereo_frontend_, out_dir, range);
}

std::filesystem::path perturbed_copy(const std::filesystem::path& dataset,
                                     const std::vector<synth::IlluminationEvent>& events,
                                     const std::filesystem::path& dir, const synth::PerturbOptions& options) {
  const std::filesystem::path copy = dir / dataset.filename();
  synth::perturb_sequence(dataset, copy, events, options);
  // The EuRoC reader finds the cam0 ground truth next to the sequence (<parent>/groundtruth), outside the copy.
  if (const auto groundtruth = dataset.parent_path() / "groundtruth"; std::filesystem::is_directory(groundtruth))
    std::filesystem::copy(groundtruth, dir / "groundtruth", std::filesystem::copy_options::recursive);
  return copy;
}

}  // namespace vkvo::test
