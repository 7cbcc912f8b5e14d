// The whole threaded pipeline (reader -> feature stage -> optimisation stage -> outputs) on a KITTI-layout folder
// of tagged placeholder images, with the oracle point frontend: no GPU needed, every output checked.
#include <algorithm>
#include <fstream>

#include <fmt/format.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "common/test_support.hpp"
#include "io/dataset.hpp"
#include "io/frame_status.hpp"
#include "io/trajectory.hpp"
#include "system/oracle_frontend.hpp"
#include "system/pipeline.hpp"
#include "viz/overlay.hpp"
#include "viz/topdown.hpp"
#include "viz/video_recorder.hpp"

namespace vkvo::system {
namespace {

namespace fs = std::filesystem;

// KITTI odometry layout: image_0/1, calib.txt (P0, P1), times.txt.
fs::path write_kitti_folder(const test::SyntheticScene& scene, const test::OracleFrontend& oracle, int frames,
                            const fs::path& dir) {
  fs::create_directories(dir / "image_0");
  fs::create_directories(dir / "image_1");
  const auto& c = scene.stereo.camera;
  std::ofstream calib(dir / "calib.txt");
  calib << fmt::format("P0: {} 0 {} 0 0 {} {} 0 0 0 1 0\n", c.fx, c.cx, c.fy, c.cy);
  calib << fmt::format("P1: {} 0 {} {} 0 {} {} 0 0 0 1 0\n", c.fx, c.cx, -c.fx * scene.stereo.baseline, c.fy, c.cy);
  std::ofstream times(dir / "times.txt");
  for (int f = 0; f < frames; ++f) {
    times << fmt::format("{:.6e}\n", 0.05 * f);
    cv::imwrite((dir / "image_0" / fmt::format("{:06d}.png", f)).string(), oracle.image(f, false));
    cv::imwrite((dir / "image_1" / fmt::format("{:06d}.png", f)).string(), oracle.image(f, true));
  }
  return dir;
}

VoConfig points_only_config() {
  VoConfig config;
  config.tracking.use_lines = false;  // the placeholder images have no lines
  config.triangulation.max_depth = 20.0;
  return config;
}

// Every trajectory line within `tolerance_m` of the truth (world = first camera; KITTI is rectified, so no
// rectifying rotation), in time order.
void expect_trajectory_near_truth(const fs::path& file, const test::SyntheticScene& scene, std::size_t lines,
                                  double tolerance_m) {
  const auto trajectory = io::read_tum(file);
  ASSERT_EQ(trajectory.size(), lines);
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    const auto& pose = trajectory[i];
    if (i > 0) {
      EXPECT_GT(pose.t, trajectory[i - 1].t) << "line " << i;
    }
    const int f = static_cast<int>(std::lround(pose.t / 0.05));
    const Eigen::Isometry3d truth = scene.T_world_left[0].inverse() * scene.T_world_left[f];
    EXPECT_LT((pose.pose.translation() - truth.translation()).norm(), tolerance_m) << "frame " << f;
  }
}

// A synthetic scene written as a KITTI-layout folder (dir/seq) of placeholder images, the oracle front ends that
// read them, and the threaded VO run on it with outputs in dir/out.
struct SyntheticRun {
  SyntheticRun(int frames, std::uint32_t seed, const std::string& tag)
      : scene(test::SyntheticScene::make(frames, 600, seed)),
        feature_oracle(scene, 0.0, 1),
        stereo_oracle(scene, 0.0, 2),
        dir(test::temp_dir(tag)) {
    write_kitti_folder(scene, feature_oracle, frames, dir / "seq");
  }
  RunResult run(RunObserver* observer = nullptr) {
    const auto dataset = io::open_dataset(dir / "seq");
    RunOptions options;
    options.output_dir = dir / "out";
    options.progress = false;
    options.observer = observer;
    return run_vo(*dataset, points_only_config(), feature_oracle, stereo_oracle, options);
  }

  test::SyntheticScene scene;
  test::OracleFrontend feature_oracle, stereo_oracle;
  fs::path dir;
};

TEST(Pipeline, RunsTheThreadedVoAndWritesEveryOutput) {
  constexpr int kFrames = 40;
  SyntheticRun synthetic(kFrames, 21, "pipeline");
  const auto& scene = synthetic.scene;
  // A corrupt image in the middle: the run must go on and say which frame it skipped.
  { std::ofstream(synthetic.dir / "seq" / "image_1" / "000020.png") << "not a png"; }
  const auto result = synthetic.run();

  EXPECT_EQ(result.frames, static_cast<std::size_t>(kFrames - 1));
  EXPECT_EQ(result.frames_skipped, 1u);
  EXPECT_EQ(result.tracking_losses, 0);
  EXPECT_EQ(result.frames_tracked, result.frames);
  EXPECT_TRUE(result.untracked_frames.empty());
  EXPECT_GE(result.keyframes, 2);
  expect_trajectory_near_truth(result.trajectory, scene, kFrames - 1, 2e-3);
  EXPECT_EQ(io::read_tum(result.keyframes_file).size(), static_cast<std::size_t>(result.keyframes));
  EXPECT_TRUE(fs::exists(synthetic.dir / "out" / "map.ply"));
  std::ifstream summary_file(result.summary);
  const auto summary = nlohmann::json::parse(summary_file);
  EXPECT_EQ(summary["frames"], kFrames - 1);
  EXPECT_EQ(summary["keyframes"], result.keyframes);
  for (const char* module : {"PE", "PM", "IPE", "BA"})
    EXPECT_GT(summary["timing"]["modules"][module]["samples"].get<int>(), 0) << module;

  // The inlier statistics are those of frames.csv's tracked rows (points only here: no line inliers).
  const auto rows = io::read_frame_status(result.frames_file);
  std::vector<int> point_inliers;
  for (const auto& row : rows)
    if (row.state == "tracked") point_inliers.push_back(row.point_inliers);
  ASSERT_EQ(point_inliers.size(), result.frames_tracked);
  std::sort(point_inliers.begin(), point_inliers.end());
  const auto& inliers = summary["inliers_per_tracked_frame"];
  EXPECT_EQ(inliers["frames"], point_inliers.size());
  EXPECT_EQ(inliers["points"]["min"], point_inliers.front());
  const std::size_t n = point_inliers.size();
  EXPECT_DOUBLE_EQ(inliers["points"]["median"].get<double>(),
                   n % 2 ? point_inliers[n / 2] : 0.5 * (point_inliers[n / 2 - 1] + point_inliers[n / 2]));
  EXPECT_GT(inliers["points"]["mean"].get<double>(), 20.0);
  EXPECT_EQ(inliers["lines"]["mean"], 0.0);
  EXPECT_EQ(inliers["frames_with_line_inliers"], 0);
}

// Black frames in the middle: they are untracked, their trajectory lines wait until tracking resumes and are then
// written interpolated between the tracked poses around the gap, in time order, next to the truth.
TEST(Pipeline, BlackFramesAreBridgedOnceTrackingResumes) {
  constexpr int kFrames = 30;
  SyntheticRun synthetic(kFrames, 23, "pipeline_black");
  const auto& scene = synthetic.scene;
  const cv::Mat black(synthetic.feature_oracle.image(0, false).size(), CV_8UC1, cv::Scalar(0));
  for (int f = 14; f <= 16; ++f)
    for (const char* side : {"image_0", "image_1"})
      cv::imwrite((synthetic.dir / "seq" / side / fmt::format("{:06d}.png", f)).string(), black);
  const auto result = synthetic.run();

  EXPECT_EQ(result.frames, static_cast<std::size_t>(kFrames));
  EXPECT_EQ(result.untracked_frames, (std::vector<std::size_t>{14, 15, 16}));
  EXPECT_EQ(result.frames_bridged, 3);
  EXPECT_TRUE(result.last_frame_tracked);
  // Interpolating over 4 frames of this smooth path: within 1 cm (what the tracked frames reach: docs/accuracy.md).
  expect_trajectory_near_truth(result.trajectory, scene, kFrames, 1e-2);
  std::ifstream summary_file(result.summary);
  EXPECT_EQ(nlohmann::json::parse(summary_file)["frames_bridged"], 3);
}

// --video: one video frame per processed frame, read back by OpenCV, and a top-down picture with the trajectory.
TEST(Pipeline, VideoHasAFramePerProcessedFrameAndATopDownPicture) {
  constexpr int kFrames = 12;
  SyntheticRun synthetic(kFrames, 25, "pipeline_video");
  const auto dataset = io::open_dataset(synthetic.dir / "seq");
  const fs::path file = synthetic.dir / "video" / "run.mp4";
  viz::VideoRecorder recorder(file, viz::video_format(*dataset), 2);
  const auto result = synthetic.run(&recorder);
  ASSERT_EQ(result.frames, static_cast<std::size_t>(kFrames));
  EXPECT_EQ(recorder.stats().frames, result.frames);

  cv::VideoCapture capture(file.string());
  ASSERT_TRUE(capture.isOpened());
  int frames = 0;
  cv::Mat image, first;
  while (capture.read(image))
    if (frames++ == 0) first = image.clone();
  EXPECT_EQ(frames, kFrames);
  // The first frame starts the map: its keypoints are new map points, drawn in their colour (lossy encoding: near).
  cv::Mat near_new;
  cv::inRange(first, viz::colour::new_point - cv::Scalar::all(60), viz::colour::new_point + cv::Scalar::all(60),
              near_new);
  EXPECT_GT(cv::countNonZero(near_new), 100);

  const cv::Mat topdown = cv::imread(recorder.topdown_file().string());
  ASSERT_FALSE(topdown.empty()) << recorder.topdown_file();
  cv::Mat trajectory;
  cv::inRange(topdown, viz::topdown_colour::trajectory, viz::topdown_colour::trajectory, trajectory);
  EXPECT_GT(cv::countNonZero(trajectory), 20);
  cv::Mat points;
  cv::inRange(topdown, viz::topdown_colour::point, viz::topdown_colour::point, points);
  EXPECT_GT(cv::countNonZero(points), 100);
}

}  // namespace
}  // namespace vkvo::system
