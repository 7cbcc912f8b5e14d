// The product configuration on the real clips (label `data`): the real SuperPoint, converted in the test from the
// shared ONNX export, and the NN matcher on the device; each test runs its clip clean and then under photometric
// stress (issue 7), with one pack and one pair of frontends. SuperPoint on lavapipe costs seconds per image, so
// the clips are cut to what CI can afford; the measured figures and the reasons are at each test.
#include <algorithm>
#include <memory>

#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include "common/gpu.hpp"
#include "common/test_support.hpp"
#include "io/model_pack.hpp"
#include "system/network_frontend.hpp"
#include "system/vo_harness.hpp"
#include "tools/convert/convert.hpp"
#include "tools/synth/perturb.hpp"

namespace vkvo::system {
namespace {

namespace fs = std::filesystem;

// The real SuperPoint pack and the two frontends a run needs (feature stage, keyframes' right images).
class RealSuperPoint {
 public:
  RealSuperPoint(const fs::path& onnx, const VoConfig& config, const fs::path& dir)
      : pack_(convert_pack(onnx, dir / "superpoint.vkvopack")),
        feature_frontend_(make_network_frontend(test::gpu(), pack_, nullptr, config)),
        stereo_frontend_(make_network_frontend(test::gpu(), pack_, nullptr, config)) {}

  // The first `frames` pairs of `dataset`.
  test::VoRun run(const fs::path& dataset, const VoConfig& config, const fs::path& out_dir, std::size_t frames) {
    return test::run_vo_on(dataset, config, *feature_frontend_, *stereo_frontend_, out_dir,
                           {.first = 0, .last = frames - 1});
  }

 private:
  static io::ModelPack convert_pack(const fs::path& onnx, const fs::path& pack) {
    convert::convert_file(onnx, pack, io::NetworkKind::superpoint);
    return io::ModelPack::load(pack, io::NetworkKind::superpoint);
  }

  io::ModelPack pack_;
  std::unique_ptr<PointFrontend> feature_frontend_, stereo_frontend_;
};

struct FrameSpan {
  int first = 0, last = 0;  // inclusive, 0-based frames of the clip
};

// The photometric stress, in three separate stretches so each one's effect can be told apart: the gain
// dropped to 25%, black frames (gain 0: no keypoint at all, so tracking must be lost and regained), and a gamma
// flicker (v^0.5 and v^2.0 on alternate frames).
struct PhotometricStress {
  FrameSpan dim, black, gamma;

  std::vector<synth::IlluminationEvent> events() const {
    auto dimmed = synth::make_event(synth::EventKind::lights_off, dim.first, dim.last);
    dimmed.gain = 0.25;
    auto dark = synth::make_event(synth::EventKind::lights_off, black.first, black.last);
    dark.gain = 0.0;
    auto flicker = synth::make_event(synth::EventKind::gamma_flicker, gamma.first, gamma.last);
    flicker.gain = 0.5;
    return {dimmed, dark, flicker};
  }
};

// The clip with the stress applied to its images (calibration, timestamps and ground truth unchanged).
fs::path stressed_copy(const fs::path& dataset, const PhotometricStress& stress, const fs::path& dir) {
  const fs::path copy = dir / dataset.filename();
  synth::perturb_sequence(dataset, copy, stress.events());
  // The EuRoC reader finds the cam0 ground truth next to the sequence (<parent>/groundtruth), outside the copy.
  if (const fs::path groundtruth = dataset.parent_path() / "groundtruth"; fs::is_directory(groundtruth))
    fs::copy(groundtruth, dir / "groundtruth", fs::copy_options::recursive);
  return copy;
}

// What the system must do under the stress: process every frame, and leave exactly the black frames untracked:
// they have no keypoint, so a pose "tracked" there would be made up; the dimmed and the gamma frames still carry
// structure; after the black frames it must track again (in the old map or a new segment) to the end.
void expect_recovered(const test::VoRun& run, std::size_t frames, const PhotometricStress& stress) {
  EXPECT_EQ(run.result.frames, frames);
  EXPECT_EQ(run.result.frames_skipped, 0u);
  EXPECT_EQ(run.evaluation.associated_poses, frames);
  EXPECT_EQ(static_cast<int>(run.result.untracked_frames.size()), stress.black.last - stress.black.first + 1);
  for (const std::size_t frame : run.result.untracked_frames)
    EXPECT_TRUE(static_cast<int>(frame) >= stress.black.first && static_cast<int>(frame) <= stress.black.last)
        << "frame " << frame << " untracked outside the black stretch";
  EXPECT_TRUE(run.result.last_frame_tracked);
  // Tracking resumed after the black stretch, so its poses were written interpolated across it.
  EXPECT_EQ(run.result.frames_bridged, stress.black.last - stress.black.first + 1);
}

// ATE of the stressed run, all frames and the tracked ones, next to the clean run's, in the test log.
void log_comparison(const test::VoRun& clean, const test::VoRun& stressed) {
  spdlog::info("ATE RMSE clean {:.4f} m | stressed {:.4f} m, over its tracked frames {:.4f} m | untracked {} | "
               "losses {} | segments {}",
               clean.evaluation.ate.translation_m.rmse, stressed.evaluation.ate.translation_m.rmse,
               test::evaluate_tracked_frames(stressed).ate.translation_m.rmse, stressed.result.untracked_frames.size(),
               stressed.result.tracking_losses, stressed.result.segments);
}

struct CleanAndStressed {
  test::VoRun clean, stressed;
};

// The first `frames` pairs of the clip clean, then with `stress` applied, on one converted pack; checks what every
// clip must show: the clean run tracks every frame, the stressed one recovers (expect_recovered).
CleanAndStressed run_clean_and_stressed(const fs::path& dataset, const fs::path& onnx, const VoConfig& config,
                                        std::size_t frames, const PhotometricStress& stress) {
  const auto dir = test::temp_dir("vo_superpoint");
  RealSuperPoint superpoint(onnx, config, dir);
  CleanAndStressed runs{superpoint.run(dataset, config, dir / "clean", frames),
                        superpoint.run(stressed_copy(dataset, stress, dir), config, dir / "stressed", frames)};
  log_comparison(runs.clean, runs.stressed);
  test::expect_every_frame_tracked(runs.clean, frames);
  expect_recovered(runs.stressed, frames, stress);
  return runs;
}

double ate_rmse(const eval::EvaluationResult& evaluation) { return evaluation.ate.translation_m.rmse; }

// The first 40 EuRoC pairs (the whole 130-pair run takes ~8 minutes on lavapipe with two cores, too long for CI),
// with the stress inside them: gain 25% on frames 6-11, black frames 16-18, gamma flicker on 24-29.
TEST(VoSuperPointData, EurocMh01FirstFramesCleanAndUnderPhotometricStress) {
  VKVO_REQUIRE_DATA(dataset, "datasets/euroc_mh01_subset/MH_01_easy");
  VKVO_REQUIRE_DATA(onnx, "models/superpoint_v1.onnx");
  const auto config = load_vo_config(test::source_dir() / "config" / "euroc.yaml");
  const PhotometricStress stress{.dim = {6, 11}, .black = {16, 18}, .gamma = {24, 29}};
  const auto [clean, stressed] = run_clean_and_stressed(dataset, onnx, config, 40, stress);
  // Measured (ctest, validation on, 2 cores): 225-397 s for both runs (110-200 s each). Clean: ATE
  // 4.7 mm (max 8.2 mm), 3 keyframes, no loss; bound: the 3 cm. Stressed: the three black frames are the
  // only untracked ones (frame 19 relocalises in the same map segment); ATE 3.1 mm over all frames (0.66x clean)
  // and over the tracked ones. The black frames' poses are interpolated between frames 15 and 19 once tracking
  // resumes (GapBridge): their constant-velocity predictions were off by up to 34 mm in this jerky pre-takeoff
  // motion and made the whole trajectory 7.2 mm (1.53x). Bound: the 1.5x, on both.
  EXPECT_LT(ate_rmse(clean.evaluation), 0.03);
  EXPECT_LE(ate_rmse(test::evaluate_tracked_frames(stressed)), 1.5 * ate_rmse(clean.evaluation));
  EXPECT_LE(ate_rmse(stressed.evaluation), 1.5 * ate_rmse(clean.evaluation));
}

// KITTI 01 (highway, ~1 m per frame), first 20 pairs: gain 25% on frames 3-6, black frames 9-10, gamma flicker on
// 13-16. SuperPoint costs ~5.8 s a frame here (1241x376, and every second frame is a keyframe that also runs the
// right image), 100-116 s for 20 frames: the whole 51-frame clip would take ~5 minutes a run, 10 for the pair.
TEST(VoSuperPointData, Kitti01FirstFramesCleanAndUnderPhotometricStress) {
  VKVO_REQUIRE_DATA(dataset, "datasets/kitti_seq01_f000-050/KITTI_sequence_2");
  VKVO_REQUIRE_DATA(onnx, "models/superpoint_v1.onnx");
  const auto config = load_vo_config(test::source_dir() / "config" / "kitti.yaml");
  const PhotometricStress stress{.dim = {3, 6}, .black = {9, 10}, .gamma = {13, 16}};
  const auto [clean, stressed] = run_clean_and_stressed(dataset, onnx, config, 20, stress);
  // Measured (ctest, validation on, 2 cores): 199-231 s for both runs (~100 s each). Clean: ATE 0.21-0.22 m (max
  // 0.38 m) over the ~18 m path (1.2%), 10 keyframes, no loss; bound: the 2% of the path. Stressed: only
  // the two black frames are untracked (frame 11 relocalises on the last keyframe by PnP, same segment); ATE
  // 0.226-0.237 m over all frames (1.06x clean; 0.333 m = 1.50x before the tracker carried its velocity through
  // lost frames; the black frames are now written interpolated, GapBridge) and 0.244-0.249 m over the tracked ones
  // (1.12x). Bound: the 1.5x, on both.
  const double path = clean.evaluation.drift.path_length_m;
  EXPECT_GT(path, 15.0);
  EXPECT_LT(ate_rmse(clean.evaluation), 0.02 * path);
  EXPECT_LE(ate_rmse(test::evaluate_tracked_frames(stressed)), 1.5 * ate_rmse(clean.evaluation));
  EXPECT_LE(ate_rmse(stressed.evaluation), 1.5 * ate_rmse(clean.evaluation));
}

}  // namespace
}  // namespace vkvo::system
