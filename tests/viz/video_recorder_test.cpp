// VideoRecorder: every queued frame ends up in a file OpenCV reads back, for both containers; paths it cannot
// write fail at construction, naming the file.
#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/videoio.hpp>

#include "common/test_support.hpp"
#include "viz/overlay.hpp"
#include "viz/video_recorder.hpp"

namespace vkvo::viz {
namespace {

namespace fs = std::filesystem;

// Frames OpenCV decodes from the file (not the container's count, which some writers only estimate).
int frames_in(const fs::path& file) {
  cv::VideoCapture capture(file.string());
  if (!capture.isOpened()) return -1;
  int frames = 0;
  cv::Mat image;
  while (capture.read(image)) ++frames;
  return frames;
}

system::OdometryPose pose_with_image(std::size_t index, cv::Size size) {
  auto o = std::make_shared<system::FrameObservations>();
  o->left = cv::Mat(size, CV_8UC1, cv::Scalar(static_cast<double>(10 * index % 250)));
  o->keypoints = {{10.0 + index, 10.0}};
  o->roles = {system::KeypointRole::inlier};
  system::OdometryPose pose;
  pose.frame_index = index;
  pose.observations = o;
  return pose;
}

TEST(VideoRecorder, WritesEveryFrameInBothContainers) {
  const auto dir = test::temp_dir("video");
  const cv::Size size(95, 60);  // odd width: the overlay is rounded up to even
  for (const char* name : {"run.mp4", "nested/run.avi"}) {
    const fs::path file = dir / name;
    constexpr std::size_t kFrames = 13;
    {
      VideoRecorder recorder(file, {.image_size = size, .fps = 10}, 2);
      for (std::size_t i = 0; i < kFrames; ++i) recorder.frame(pose_with_image(i, size));
      recorder.close();
      EXPECT_EQ(recorder.stats().frames, kFrames) << name;
      EXPECT_EQ(recorder.stats().failed, 0u) << name;
    }
    EXPECT_EQ(frames_in(file), static_cast<int>(kFrames)) << name;
    cv::VideoCapture capture(file.string());
    EXPECT_EQ(capture.get(cv::CAP_PROP_FRAME_WIDTH), overlay_size(size).width) << name;
    EXPECT_EQ(capture.get(cv::CAP_PROP_FRAME_HEIGHT), overlay_size(size).height) << name;
  }
}

TEST(VideoRecorder, DestroyedWithoutFinishKeepsThePlayableFramesSoFar) {
  const fs::path file = test::temp_dir("video") / "stopped.mp4";
  const cv::Size size(64, 48);
  {
    VideoRecorder recorder(file, {.image_size = size, .fps = 20});
    for (std::size_t i = 0; i < 5; ++i) recorder.frame(pose_with_image(i, size));
  }  // as when a run throws: no finish(), no top-down picture
  EXPECT_EQ(frames_in(file), 5);
  EXPECT_FALSE(fs::exists(file.parent_path() / "stopped_topdown.png"));
}

TEST(VideoRecorder, FinishWritesTheTopDownPictureBesideTheVideo) {
  const fs::path file = test::temp_dir("video") / "clip.avi";
  VideoRecorder recorder(file, {.image_size = {32, 32}, .fps = 20});
  io::MapGeometry map;
  map.trajectory = {{0, 0, 0}, {1, 0, 1}};
  recorder.finish(map);
  EXPECT_EQ(recorder.topdown_file(), file.parent_path() / "clip_topdown.png");
  EXPECT_TRUE(fs::exists(recorder.topdown_file()));
  EXPECT_EQ(frames_in(file), 0);
}

TEST(VideoRecorder, UnusablePathsFailAtOnceNamingTheFile) {
  const auto dir = test::temp_dir("video");
  const fs::path mkv = dir / "out.mkv";
  const std::string extension_error = test::error_of([&] { VideoRecorder recorder(mkv, {.image_size = {32, 32}}); });
  EXPECT_NE(extension_error.find(mkv.string()), std::string::npos) << extension_error;
  EXPECT_NE(extension_error.find("'.mkv'"), std::string::npos) << extension_error;
  EXPECT_FALSE(fs::exists(mkv));

  const fs::path no_extension = dir / "out";
  EXPECT_NE(test::error_of([&] {
              VideoRecorder recorder(no_extension, {.image_size = {32, 32}});
            }).find("unsupported extension"),
            std::string::npos);

  // A folder that cannot be made: a file stands where it would be.
  test::write_text(dir / "taken", "a file");
  const fs::path blocked = dir / "taken" / "out.mp4";
  const std::string folder_error = test::error_of([&] { VideoRecorder recorder(blocked, {.image_size = {32, 32}}); });
  EXPECT_NE(folder_error.find(blocked.string()), std::string::npos) << folder_error;

  // The writer does not open: a folder has the video's name.
  const fs::path folder = dir / "folder.mp4";
  fs::create_directories(folder);
  const std::string writer_error = test::error_of([&] { VideoRecorder recorder(folder, {.image_size = {32, 32}}); });
  EXPECT_NE(writer_error.find(folder.string()), std::string::npos) << writer_error;
  EXPECT_NE(writer_error.find("cannot open"), std::string::npos) << writer_error;
}

}  // namespace
}  // namespace vkvo::viz
