// The VO on the real EuRoC MH_01 subset (130 stereo pairs, label `data`), with the OpenCV test frontend
// (tests/system/opencv_frontend.*) standing in for SuperPoint, which costs seconds per frame on lavapipe (too slow
// for whole clips in CI; docs/testing.md). What it checks is the VO itself on real images: rectification, stereo
// initialisation, tracking,
// keyframes, BA, against the ORB-SLAM3 left-camera ground truth. The real SuperPoint runs are in
// vo_superpoint_data_test.cpp.
#include <filesystem>

#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "system/vo_harness.hpp"

namespace vkvo::system {
namespace {

// The whole clip with the config/ file of its dataset and the OpenCV frontend's default parameters.
test::VoRun run_whole_clip(const std::filesystem::path& dataset, const char* config_file) {
  const auto config = load_vo_config(test::source_dir() / "config" / config_file);
  return test::run_vo_with_opencv_frontend(dataset, config, {}, test::temp_dir("vo_data") / "out");
}

TEST(VoData, EurocMh01SubsetWithTheOpencvFrontend) {
  VKVO_REQUIRE_DATA(dataset, "datasets/euroc_mh01_subset/MH_01_easy");
  const auto run = run_whole_clip(dataset, "euroc.yaml");
  test::expect_every_frame_tracked(run, 130);
  // The target for the real SuperPoint + NN matcher is 3 cm; this frontend (measured: docs/accuracy.md)
  // is bound at 1.5 cm (margin for run-to-run variation: the
  // feature stage runs ahead of the tracker by a timing-dependent number of frames, which changes which keyframe
  // a frame is first matched against). MH01_GT.txt (ORB-SLAM3's) gives cam0 positions with world-to-camera
  // rotations; read inverted (io::GroundTruthOrientation::automatic), the rotation error after alignment is the
  // position-fitted alignment's own, a few degrees and nearly constant (read as written: docs/accuracy.md).
  EXPECT_LT(run.evaluation.ate.translation_m.rmse, 0.015);
  EXPECT_LT(run.evaluation.ate.rotation_deg.rmse, 5.0);
  EXPECT_LT(run.evaluation.ate.rotation_deg.std, 1.0);
}

TEST(VoData, Kitti01SubsetWithTheOpencvFrontend) {
  VKVO_REQUIRE_DATA(dataset, "datasets/kitti_seq01_f000-050/KITTI_sequence_2");
  const auto run = run_whole_clip(dataset, "kitti.yaml");
  test::expect_every_frame_tracked(run, 51);
  // Highway at ~1 m per frame keeps the tracked count under keyframe.max_tracked, so most frames become
  // keyframes. The bound is the target for the real system (2% of the path); the frontend's margin:
  // docs/accuracy.md.
  const double path = run.evaluation.drift.path_length_m;
  EXPECT_GT(path, 50.0);
  EXPECT_LT(run.evaluation.ate.translation_m.rmse, 0.02 * path);
}

}  // namespace
}  // namespace vkvo::system
