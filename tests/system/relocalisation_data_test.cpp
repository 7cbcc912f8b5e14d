// Through the dark and back onto the same map (label `data`): the real SuperPoint and the NN matcher on the shared
// clips, with the lights switched off where the motion curves and with a stretch of frames removed (a kidnap).
// Each test also runs the same input without relocalisation, as the VO behaved before it existed, and checks that
// it fails what the test asks: the test measures the feature, not the clip. The features of every image come from
// the feature cache shared with the other data tests (test::RealSuperPoint), so only the darkened images run the
// network here.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include "common/test_support.hpp"
#include "eval/alignment.hpp"
#include "eval/association.hpp"
#include "eval/metrics.hpp"
#include "system/real_superpoint.hpp"
#include "system/trajectory_record.hpp"
#include "system/vo_harness.hpp"

namespace vkvo::system {
namespace {

namespace fs = std::filesystem;

struct Span {
  int first = 0, last = 0;  // frames of the clip, inclusive
};

// ATE over the poses outside [t0, t1] (seconds), aligned on them.
double ate_outside(const io::Trajectory& estimate, const io::Trajectory& groundtruth, double t0, double t1) {
  io::Trajectory kept;
  for (const auto& pose : estimate)
    if (pose.t < t0 - 1e-6 || pose.t > t1 + 1e-6) kept.push_back(pose);
  return eval::evaluate(kept, groundtruth).ate.translation_m.rmse;
}

// The errors of the poses inside [t0, t1] under the alignment fitted on the poses outside it, for `estimate` as
// written and for the same poses bridged by a straight line at constant speed between the poses around the gap
// (the motion model the VO had before).
struct GapErrors {
  double written_rmse = 0, linear_rmse = 0;
};
GapErrors gap_errors(const io::Trajectory& estimate, const io::Trajectory& groundtruth, double t0, double t1) {
  const eval::AssociatedPoses poses = eval::associate(estimate, groundtruth);
  std::vector<Eigen::Vector3d> outside_estimate, outside_truth;
  std::size_t before = 0, after = poses.size();  // the last pose before the gap, the first after it
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const bool inside = poses.t[i] >= t0 - 1e-6 && poses.t[i] <= t1 + 1e-6;
    if (!inside) {
      outside_estimate.push_back(poses.estimate[i].translation());
      outside_truth.push_back(poses.groundtruth[i].translation());
    }
    if (poses.t[i] < t0 - 1e-6) before = i;
    if (poses.t[i] > t1 + 1e-6 && after == poses.size()) after = i;
  }
  const eval::Similarity alignment = eval::align_positions(outside_estimate, outside_truth, eval::AlignmentMode::se3);
  std::vector<double> written, linear;
  for (std::size_t i = before + 1; i < after; ++i) {
    const double fraction = (poses.t[i] - poses.t[before]) / (poses.t[after] - poses.t[before]);
    const Eigen::Isometry3d straight = interpolate_pose(poses.estimate[before], poses.estimate[after], fraction);
    written.push_back(
        (alignment.apply(Eigen::Vector3d(poses.estimate[i].translation())) - poses.groundtruth[i].translation())
            .norm());
    linear.push_back(
        (alignment.apply(Eigen::Vector3d(straight.translation())) - poses.groundtruth[i].translation()).norm());
  }
  return {eval::compute_stats(written).rmse, eval::compute_stats(linear).rmse};
}

VoConfig without_relocalisation(VoConfig config) {
  config.relocalisation.enabled = false;
  return config;
}

struct LightsOff {
  test::VoRun clean, dark, dark_before;  // dark_before: the same input without relocalisation
  double t0 = 0, t1 = 0;                 // the dark stretch's timestamps
};

// The clip clean, then with `span` black (no light at all), with and without relocalisation.
LightsOff run_lights_off(const fs::path& dataset, const fs::path& onnx, const VoConfig& config, Span span) {
  const auto dir = test::temp_dir("lights_off");
  test::RealSuperPoint superpoint(onnx, config, dir);
  LightsOff runs;
  runs.clean = superpoint.run(dataset, config, dir / "clean");
  auto off = synth::make_event(synth::EventKind::lights_off, span.first, span.last);
  off.gain = 0.0;
  const fs::path dark = test::perturbed_copy(dataset, {off}, dir / "input");
  runs.dark = superpoint.run(dark, config, dir / "dark");
  runs.dark_before = superpoint.run(dark, without_relocalisation(config), dir / "dark_before");
  runs.t0 = runs.clean.trajectory.at(static_cast<std::size_t>(span.first)).t;
  runs.t1 = runs.clean.trajectory.at(static_cast<std::size_t>(span.last)).t;
  return runs;
}

// What the issue asks of a lights-off: one map segment at the end, every frame with a pose, the frames outside the
// gap within 1.3x of the clean run's ATE over the same frames, the gap's poses no further from the truth than 1.5x
// a straight line at constant speed between the same ends (the bridge follows the end velocities, which beats the
// chord on a curve with good ends, trajectory_record_test; on KITTI the relocalised frame's own error tilts its end
// velocity, and runs gave 0.60-0.81 m against a chord of 0.59-0.68 m).
void expect_one_map_through_the_dark(const LightsOff& runs, std::size_t frames, Span span) {
  const test::VoRun& dark = runs.dark;
  const double clean_outside = ate_outside(runs.clean.trajectory, runs.clean.groundtruth, runs.t0, runs.t1);
  const double dark_outside = ate_outside(dark.trajectory, dark.groundtruth, runs.t0, runs.t1);
  const double before_outside =
      ate_outside(runs.dark_before.trajectory, runs.dark_before.groundtruth, runs.t0, runs.t1);
  const GapErrors gap = gap_errors(dark.trajectory, dark.groundtruth, runs.t0, runs.t1);
  const GapErrors gap_before = gap_errors(runs.dark_before.trajectory, runs.dark_before.groundtruth, runs.t0, runs.t1);
  spdlog::info(
      "lights off {}-{}: ATE outside the gap clean {:.4f} m | relocalised {:.4f} m ({:.2f}x) | without "
      "relocalisation {:.4f} m ({:.2f}x, {} segments); gap RMSE {:.4f} m (straight line between the same ends "
      "{:.4f} m; before {:.4f} m); {} relocalisations, {} merges, segments {}",
      span.first, span.last, clean_outside, dark_outside, dark_outside / clean_outside, before_outside,
      before_outside / clean_outside, runs.dark_before.result.segments, gap.written_rmse, gap.linear_rmse,
      gap_before.linear_rmse, dark.result.relocalisations, dark.result.merges, dark.result.segments);

  EXPECT_EQ(dark.result.frames, frames);
  EXPECT_EQ(dark.trajectory.size(), frames) << "every frame has a pose";
  EXPECT_EQ(dark.result.segments, 1);
  EXPECT_TRUE(dark.result.last_frame_tracked);
  for (const std::size_t frame : dark.result.untracked_frames)
    EXPECT_TRUE(static_cast<int>(frame) >= span.first && static_cast<int>(frame) <= span.last)
        << "frame " << frame << " untracked outside the dark stretch";
  EXPECT_LE(dark_outside, 1.3 * clean_outside);
  EXPECT_LT(gap.written_rmse, 1.5 * gap.linear_rmse);
  // The VO before relocalisation fails the same input: a split map, or the gap's jump in every later pose.
  EXPECT_TRUE(runs.dark_before.result.segments > 1 || before_outside > 1.3 * clean_outside)
      << "the input does not test relocalisation";
}

// EuRoC MH_01: lights off for 1 s (20 frames, 90-109) while the MAV slows down from 2.4 cm per frame, stops and
// turns back.
TEST(RelocalisationData, EurocLightsOffForOneSecondStaysOnOneMap) {
  VKVO_REQUIRE_DATA(dataset, "datasets/euroc_mh01_subset/MH_01_easy");
  VKVO_REQUIRE_DATA(onnx, "models/superpoint_v1.onnx");
  const auto config = load_vo_config(test::source_dir() / "config" / "euroc.yaml");
  const Span span{90, 109};
  expect_one_map_through_the_dark(run_lights_off(dataset, onnx, config, span), 130, span);
}

// KITTI 01: lights off for 1 s (10 frames, 15-24) in the curve (2.7 deg of yaw per frame at 10 m/s): the car
// comes out 10 m and 27 deg further on.
TEST(RelocalisationData, KittiLightsOffForTenFramesStaysOnOneMap) {
  VKVO_REQUIRE_DATA(dataset, "datasets/kitti_seq01_f000-050/KITTI_sequence_2");
  VKVO_REQUIRE_DATA(onnx, "models/superpoint_v1.onnx");
  const auto config = load_vo_config(test::source_dir() / "config" / "kitti.yaml");
  const Span span{15, 24};
  expect_one_map_through_the_dark(run_lights_off(dataset, onnx, config, span), 51, span);
}

// KITTI 01 at 3 % of the light with 2 DN of read noise for 1 s (frames 20-29): SuperPoint still finds 100-150
// corners per dark frame, but their descriptors have drifted so far that the first one keeps a single NN match to
// the bright keyframe, and the frames after it match only each other, without map points. Matched to the local
// map's points near their projections (tracking.point_projection, on by default), every dark frame is tracked, and
// the first bright frame after them finds the points mapped before the dark, so the map stays one segment;
// without, the whole stretch is lost and the map splits.
TEST(RelocalisationData, KittiDimFramesAreTrackedOnTheMapsPointsByProjectionOnOneMap) {
  VKVO_REQUIRE_DATA(dataset, "datasets/kitti_seq01_f000-050/KITTI_sequence_2");
  VKVO_REQUIRE_DATA(onnx, "models/superpoint_v1.onnx");
  const auto config = load_vo_config(test::source_dir() / "config" / "kitti.yaml");
  ASSERT_TRUE(config.tracking.point_projection.enabled) << "the shipped config tracks dark frames by projection";
  const Span span{20, 29};
  const auto dir = test::temp_dir("dim_projection");
  test::RealSuperPoint superpoint(onnx, config, dir);
  auto dim = synth::make_event(synth::EventKind::lights_off, span.first, span.last);
  dim.gain = 0.03;
  const fs::path input = test::perturbed_copy(dataset, {dim}, dir / "input", {.noise_sigma = 2.0, .seed = 1});
  VoConfig without = config;
  without.tracking.point_projection.enabled = false;
  const test::VoRun on = superpoint.run(input, config, dir / "on");
  const test::VoRun off = superpoint.run(input, without, dir / "off");
  const auto untracked_in_span = [&](const test::VoRun& run) {
    return std::count_if(run.result.untracked_frames.begin(), run.result.untracked_frames.end(), [&](std::size_t f) {
      return static_cast<int>(f) >= span.first && static_cast<int>(f) <= span.last;
    });
  };
  spdlog::info(
      "KITTI 3 % for frames 20-29: untracked there {} with projection, {} without; segments {} / {}; ATE {:.3f} / "
      "{:.3f} m",
      untracked_in_span(on), untracked_in_span(off), on.result.segments, off.result.segments,
      on.evaluation.ate.translation_m.rmse, off.evaluation.ate.translation_m.rmse);
  EXPECT_EQ(on.result.frames, 51u);
  EXPECT_EQ(untracked_in_span(on), 0) << "every dark frame tracked";
  EXPECT_EQ(on.result.segments, 1) << "the frame where the light returns found the map seen before the dark";
  EXPECT_GE(untracked_in_span(off), 5) << "the input does not test the projection";
  EXPECT_GT(off.result.segments, 1);
}

// A kidnap on EuRoC MH_01: frames 60-99 never reach the VO, so frame 100 shows the camera 2 s later, elsewhere
// in the mapped space. It must be relocalised into the same map. (Shorter kidnaps on this clip, 50-79 say, are
// now tracked from the last keyframe without relocalisation: the input must fail the VO without it.)
TEST(RelocalisationData, EurocKidnapIsRelocalisedIntoTheSameMap) {
  VKVO_REQUIRE_DATA(dataset, "datasets/euroc_mh01_subset/MH_01_easy");
  VKVO_REQUIRE_DATA(onnx, "models/superpoint_v1.onnx");
  const auto config = load_vo_config(test::source_dir() / "config" / "euroc.yaml");
  const auto dir = test::temp_dir("kidnap");
  test::RealSuperPoint superpoint(onnx, config, dir);
  const test::VoRun clean = superpoint.run(dataset, config, dir / "clean");
  io::FrameRange range;
  range.skip = {{60, 99}};
  const test::VoRun kidnapped = superpoint.run(dataset, config, dir / "kidnapped", range);
  const test::VoRun before = superpoint.run(dataset, without_relocalisation(config), dir / "before", range);
  spdlog::info(
      "kidnap 60-99: ATE clean {:.4f} m | relocalised {:.4f} m, {} relocalisations, {} segments | without "
      "relocalisation {:.4f} m, {} segments",
      clean.evaluation.ate.translation_m.rmse, kidnapped.evaluation.ate.translation_m.rmse,
      kidnapped.result.relocalisations, kidnapped.result.segments, before.evaluation.ate.translation_m.rmse,
      before.result.segments);
  EXPECT_EQ(kidnapped.result.frames, 90u);
  EXPECT_EQ(kidnapped.result.segments, 1);
  EXPECT_GE(kidnapped.result.relocalisations, 1);
  EXPECT_LE(kidnapped.evaluation.ate.translation_m.rmse, 1.3 * clean.evaluation.ate.translation_m.rmse);
  EXPECT_TRUE(before.result.segments > 1 ||
              before.evaluation.ate.translation_m.rmse > 1.3 * clean.evaluation.ate.translation_m.rmse)
      << "the input does not test relocalisation";
}

}  // namespace
}  // namespace vkvo::system
