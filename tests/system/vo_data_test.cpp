// The VO on the real EuRoC MH_01 subset (130 stereo pairs, label `data`), with the OpenCV test frontend
// (tests/system/opencv_frontend.*) standing in for SuperPoint while SuperPoint on lavapipe takes tens of seconds
// per frame. What it checks is the VO itself on real images: rectification, stereo initialisation, tracking,
// keyframes, BA, against the ORB-SLAM3 left-camera ground truth.
#include <gtest/gtest.h>

#include "common/gpu.hpp"
#include "common/test_support.hpp"
#include "io/model_pack.hpp"
#include "system/network_frontend.hpp"
#include "system/vo_harness.hpp"
#include "tools/convert/convert.hpp"

namespace vkvo::system {
namespace {

// Every frame processed and written, none lost, one map segment.
void expect_every_frame_tracked(const test::VoRun& run, std::size_t frames) {
  EXPECT_EQ(run.result.frames, frames);
  EXPECT_EQ(run.result.frames_skipped, 0u);
  EXPECT_EQ(run.result.tracking_losses, 0);
  EXPECT_EQ(run.result.segments, 1);
  EXPECT_EQ(run.evaluation.associated_poses, frames);
}

TEST(VoData, EurocMh01SubsetWithTheOpencvFrontend) {
  VKVO_REQUIRE_DATA(dataset, "datasets/euroc_mh01_subset/MH_01_easy");
  const auto config = load_vo_config(test::source_dir() / "config" / "euroc.yaml");
  const auto dir = test::temp_dir("vo_data");
  const auto run = test::run_vo_with_opencv_frontend(dataset, config, {}, dir / "out");
  expect_every_frame_tracked(run, 130);
  // Measured: 3.9 mm RMSE (max 8.6 mm) over the 1.8 m path, 46 keyframes, no loss. The target for the
  // real SuperPoint + NN matcher is 3 cm; this frontend is bound at 1.5 cm (margin for run-to-run variation: the
  // feature stage runs ahead of the tracker by a timing-dependent number of frames, which changes which keyframe
  // a frame is first matched against). Only the translation ATE is checked: MH01_GT.txt gives cam0 positions,
  // but its orientations are not the cam0 orientation (ATE rot ~90 deg after alignment while the relative
  // rotation angles of estimate and ground truth agree to 0.25 deg), so rotation metrics against it are moot.
  EXPECT_LT(run.evaluation.ate.translation_m.rmse, 0.015);
}

// The product configuration: the real SuperPoint (converted from the shared ONNX export) and the NN matcher on
// the device, on the first 40 EuRoC pairs (the whole 130-pair run takes ~8 minutes on lavapipe with two cores,
// too long for CI; its figures are in the closing notes). Measured: ATE 4.7 mm (max 8.2 mm), 3 keyframes, no
// loss, 0.24 frames/s under the validation layer. Bound: the 3 cm and no tracking loss.
TEST(VoData, EurocMh01FirstFramesWithRealSuperPointAndNnMatcher) {
  VKVO_REQUIRE_DATA(dataset, "datasets/euroc_mh01_subset/MH_01_easy");
  VKVO_REQUIRE_DATA(onnx, "models/superpoint_v1.onnx");
  const auto config = load_vo_config(test::source_dir() / "config" / "euroc.yaml");
  const auto dir = test::temp_dir("vo_data_superpoint");
  convert::convert_file(onnx, dir / "superpoint.vkvopack", io::NetworkKind::superpoint);
  const auto pack = io::ModelPack::load(dir / "superpoint.vkvopack", io::NetworkKind::superpoint);
  const auto feature_frontend = make_network_frontend(test::gpu(), pack, nullptr, config);
  const auto stereo_frontend = make_network_frontend(test::gpu(), pack, nullptr, config);
  constexpr std::size_t kFrames = 40;
  const auto run = test::run_vo_on(dataset, config, *feature_frontend, *stereo_frontend, dir / "out",
                                   {.first = 0, .last = kFrames - 1});
  expect_every_frame_tracked(run, kFrames);
  EXPECT_LT(run.evaluation.ate.translation_m.rmse, 0.03);
}

TEST(VoData, Kitti01SubsetWithTheOpencvFrontend) {
  VKVO_REQUIRE_DATA(dataset, "datasets/kitti_seq01_f000-050/KITTI_sequence_2");
  const auto config = load_vo_config(test::source_dir() / "config" / "kitti.yaml");
  const auto dir = test::temp_dir("vo_data");
  const auto run = test::run_vo_with_opencv_frontend(dataset, config, {}, dir / "out");
  expect_every_frame_tracked(run, 51);
  // Measured: 0.74 m RMSE (SE3) over the 51.8 m path = 1.4% (ATE rot 0.68 deg), 45 keyframes: highway at ~1 m
  // per frame keeps the tracked count under keyframe.max_tracked. The bound is the target for the real
  // system (2% of the path); the frontend meets it with 28% margin.
  const double path = run.evaluation.drift.path_length_m;
  EXPECT_GT(path, 50.0);
  EXPECT_LT(run.evaluation.ate.translation_m.rmse, 0.02 * path);
}

}  // namespace
}  // namespace vkvo::system
