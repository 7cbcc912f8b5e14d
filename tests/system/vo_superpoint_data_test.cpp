// The product configuration on the real clips (label `data`): the real SuperPoint, converted in the test from the
// shared ONNX export, and the NN matcher on the device; each test runs its whole clip clean and then under
// photometric stress (issue 7), with one pack and one pair of frontends. SuperPoint on lavapipe costs seconds per
// image, so the stressed run takes the features of the frames the stress leaves unchanged (byte-identical images)
// from the clean run (test::RealSuperPoint's feature cache) and runs the network only on the images that differ;
// everything else (matching, tracking, mapping, BA) runs afresh. The measured figures: docs/accuracy.md (ATE) and
// docs/testing.md (time).
#include <algorithm>
#include <memory>
#include <optional>

#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include "common/test_support.hpp"
#include "system/real_superpoint.hpp"
#include "system/vo_harness.hpp"
#include "tools/synth/illumination.hpp"

namespace vkvo::system {
namespace {

namespace fs = std::filesystem;

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

  std::size_t frame_count() const {
    return static_cast<std::size_t>((dim.last - dim.first + 1) + (black.last - black.first + 1) +
                                    (gamma.last - gamma.first + 1));
  }
};

// The clip with the stress applied to its images (calibration, timestamps and ground truth unchanged).
fs::path stressed_copy(const fs::path& dataset, const PhotometricStress& stress, const fs::path& dir) {
  return test::perturbed_copy(dataset, stress.events(), dir);
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
  spdlog::info(
      "ATE RMSE clean {:.4f} m | stressed {:.4f} m, over its tracked frames {:.4f} m | untracked {} | "
      "losses {} | segments {}",
      clean.evaluation.ate.translation_m.rmse, stressed.evaluation.ate.translation_m.rmse,
      test::evaluate_tracked_frames(stressed).ate.translation_m.rmse, stressed.result.untracked_frames.size(),
      stressed.result.tracking_losses, stressed.result.segments);
}

struct CleanAndStressed {
  test::VoRun clean, stressed;
  std::optional<test::VoRun> clean_variant;  // the clean clip under another configuration, when asked for
};

// The whole clip (`frames` pairs) clean, then with `stress` applied, on one converted pack; checks what every clip
// must show: the clean run tracks every frame, the stressed one recovers (expect_recovered).
CleanAndStressed run_clean_and_stressed(const fs::path& dataset, const fs::path& onnx, const VoConfig& config,
                                        std::size_t frames, const PhotometricStress& stress,
                                        const std::optional<VoConfig>& clean_variant = std::nullopt) {
  const auto dir = test::temp_dir("vo_superpoint");
  test::RealSuperPoint superpoint(onnx, config, dir);
  CleanAndStressed runs;
  runs.clean = superpoint.run(dataset, config, dir / "clean");
  const std::size_t hits_before = superpoint.cache().hits();
  runs.stressed = superpoint.run(stressed_copy(dataset, stress, dir), config, dir / "stressed");
  // Every unstressed left image of the stressed run is one the clean run detected (its right images are the
  // keyframes', which may differ between the runs).
  const std::size_t stressed_frames = stress.frame_count();
  EXPECT_GE(superpoint.cache().hits() - hits_before, frames - stressed_frames);
  spdlog::info("SuperPoint ran on {} distinct images; the stressed run reused {} of the clean run's",
               superpoint.cache().size(), superpoint.cache().hits() - hits_before);
  log_comparison(runs.clean, runs.stressed);
  test::expect_every_frame_tracked(runs.clean, frames);
  expect_recovered(runs.stressed, frames, stress);
  if (clean_variant) runs.clean_variant = superpoint.run(dataset, *clean_variant, dir / "clean_variant");
  return runs;
}

double ate_rmse(const eval::EvaluationResult& evaluation) { return evaluation.ate.translation_m.rmse; }

// EuRoC MH_01, all 130 pairs (6.5 s, the MAV lifting off and moving): gain 25% on frames 30-37, black frames
// 60-62, gamma flicker on 90-97.
TEST(VoSuperPointData, EurocMh01CleanAndUnderPhotometricStress) {
  VKVO_REQUIRE_DATA(dataset, "datasets/euroc_mh01_subset/MH_01_easy");
  VKVO_REQUIRE_DATA(onnx, "models/superpoint_v1.onnx");
  const auto config = load_vo_config(test::source_dir() / "config" / "euroc.yaml");
  const PhotometricStress stress{.dim = {30, 37}, .black = {60, 62}, .gamma = {90, 97}};
  VoConfig unpaired = config;
  unpaired.lines.keyframe_matching.by_appearance = false;
  const auto [clean, stressed, clean_unpaired] = run_clean_and_stressed(dataset, onnx, config, 130, stress, unpaired);
  // Clean: bound the 3 cm. Stressed: only the black frames may be untracked; tracking resumes in the same
  // map segment and the gap is interpolated. Bound: the 1.5x the clean ATE, over all frames and over the
  // tracked ones. (Measured ATEs: docs/accuracy.md; run times: docs/testing.md.)
  EXPECT_LT(ate_rmse(clean.evaluation), 0.03);
  EXPECT_LE(ate_rmse(test::evaluate_tracked_frames(stressed)), 1.5 * ate_rmse(clean.evaluation));
  EXPECT_LE(ate_rmse(stressed.evaluation), 1.5 * ate_rmse(clean.evaluation));
  // Keyframes pair the lines the stereo pair left unplaced with their reference keyframe's (measured: 16 map lines
  // without a right-image view against 9 without the pairing, which are the lines through two mapped points).
  ASSERT_TRUE(clean_unpaired.has_value());
  EXPECT_GT(clean.result.map_mono_lines, clean_unpaired->result.map_mono_lines);
  EXPECT_GT(clean.result.map_lines, clean_unpaired->result.map_lines);
}

// KITTI 01 (highway, ~1 m per frame), all 51 pairs: gain 25% on frames 10-14, black frames 25-26, gamma flicker
// on 38-42.
TEST(VoSuperPointData, Kitti01CleanAndUnderPhotometricStress) {
  VKVO_REQUIRE_DATA(dataset, "datasets/kitti_seq01_f000-050/KITTI_sequence_2");
  VKVO_REQUIRE_DATA(onnx, "models/superpoint_v1.onnx");
  const auto config = load_vo_config(test::source_dir() / "config" / "kitti.yaml");
  const PhotometricStress stress{.dim = {10, 14}, .black = {25, 26}, .gamma = {38, 42}};
  const auto [clean, stressed, no_variant] = run_clean_and_stressed(dataset, onnx, config, 51, stress);
  // Every second frame is a keyframe, whose right image runs SuperPoint too (the slower of the two tests). Clean:
  // bound the 2% of the path. Stressed: only the two black frames may be untracked; tracking resumes in
  // the same segment and the gap is interpolated. Bound: the 1.5x, on both. (Measured ATEs:
  // docs/accuracy.md; run times: docs/testing.md.)
  const double path = clean.evaluation.drift.path_length_m;
  EXPECT_GT(path, 40.0);
  EXPECT_LT(ate_rmse(clean.evaluation), 0.02 * path);
  EXPECT_LE(ate_rmse(test::evaluate_tracked_frames(stressed)), 1.5 * ate_rmse(clean.evaluation));
  EXPECT_LE(ate_rmse(stressed.evaluation), 1.5 * ate_rmse(clean.evaluation));
}

}  // namespace
}  // namespace vkvo::system
