#pragma once
// Runs the full threaded VO (system::run_vo) on a dataset folder with the OpenCV test frontend and evaluates the
// trajectory against the dataset's ground truth. Shared by the synthetic end-to-end tests and the data tests.
// Set VKVO_TEST_VERBOSE=1 to get the tracker's per-frame debug log (keypoints, matches, inliers, keyframes).
#include <filesystem>

#include "eval/evaluate.hpp"
#include "io/dataset.hpp"
#include "io/map_ply.hpp"
#include "system/opencv_frontend.hpp"
#include "system/pipeline.hpp"
#include "system/vo_config.hpp"

namespace vkvo::test {

struct VoRun {
  system::RunResult result;
  eval::EvaluationResult evaluation;
  io::Trajectory trajectory;
  io::Trajectory groundtruth;
};

// Any pair of point frontends (the feature stage's and the keyframe stage's) on the frames in `range`.
VoRun run_vo_on(const std::filesystem::path& dataset_dir, const system::VoConfig& config,
                system::PointFrontend& feature_frontend, system::PointFrontend& stereo_frontend,
                const std::filesystem::path& out_dir, const io::FrameRange& range = {});

VoRun run_vo_with_opencv_frontend(const std::filesystem::path& dataset_dir, const system::VoConfig& config,
                                  const OpencvFrontendParams& frontend, const std::filesystem::path& out_dir);

// The evaluation of the poses the tracker optimised only: the predicted poses of untracked frames (which no
// image supports, e.g. black frames) are left out. Needs a run without skipped frames.
eval::EvaluationResult evaluate_tracked_frames(const VoRun& run);

// The map a run wrote (map.ply, io::write_map_ply's layout): its points and line segments, told apart by colour.
io::MapGeometry read_map_ply(const std::filesystem::path& file);

// Every frame processed, tracked and written, none lost, one map segment.
void expect_every_frame_tracked(const VoRun& run, std::size_t frames);

}  // namespace vkvo::test
