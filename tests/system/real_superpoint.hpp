#pragma once
// The real SuperPoint (converted in the test from the shared ONNX export) for end-to-end runs on the shared clips:
// the two frontends a run needs (feature stage, keyframes' right images) behind one feature cache that keeps every
// image's features on disk under the build tree (test::feature_cache_dir), so that the data tests' processes run
// the network once per distinct image between them. Matching is the NN matcher on the device.
#include <filesystem>
#include <memory>
#include <vector>

#include "io/model_pack.hpp"
#include "system/feature_cache.hpp"
#include "system/vo_config.hpp"
#include "system/vo_harness.hpp"
#include "tools/synth/illumination.hpp"
#include "tools/synth/perturb.hpp"

namespace vkvo::test {

class RealSuperPoint {
 public:
  RealSuperPoint(const std::filesystem::path& onnx, const system::VoConfig& config, const std::filesystem::path& dir);

  // The whole of `dataset` (or `range` of it).
  VoRun run(const std::filesystem::path& dataset, const system::VoConfig& config, const std::filesystem::path& out_dir,
            const io::FrameRange& range = {});

  const system::FeatureCache& cache() const { return cache_; }

 private:
  io::ModelPack pack_;
  std::unique_ptr<system::PointFrontend> feature_network_, stereo_network_;
  system::FeatureCache cache_;
  system::CachedFrontend feature_frontend_, stereo_frontend_;
};

// A copy of the clip in `dir` with the events (and the options' read noise) applied to its images (calibration,
// timestamps and ground truth unchanged; EuRoC's ground truth folder beside the sequence is copied beside the copy).
std::filesystem::path perturbed_copy(const std::filesystem::path& dataset,
                                     const std::vector<synth::IlluminationEvent>& events,
                                     const std::filesystem::path& dir, const synth::PerturbOptions& options = {});

}  // namespace vkvo::test
