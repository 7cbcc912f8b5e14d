// The VO for live input (StereoOdometry, and OdometryStream's two threads): raw pairs pushed one at a time with the
// oracle point frontend (no GPU), poses against the truth of the synthetic scene, the input checks, the copy that
// protects a caller's buffers, and the stream's order, queue policies and failed frames.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <atomic>
#include <chrono>
#include <latch>
#include <thread>

#include "system/odometry_stream.hpp"
#include "system/oracle_frontend.hpp"
#include "system/stereo_odometry.hpp"

namespace vkvo::system {
namespace {

// The scene's rectified stereo camera as a calibration (KITTI-like: rectified, right camera at +baseline in x).
io::StereoCalibration calibration_of(const geometry::StereoCamera& stereo) {
  io::StereoCalibration c;
  const auto& k = stereo.camera;
  c.left = {.width = k.width, .height = k.height, .fx = k.fx, .fy = k.fy, .cx = k.cx, .cy = k.cy};
  c.right = c.left;
  c.right.T_body_camera.translation() = Eigen::Vector3d(stereo.baseline, 0, 0);
  c.rectified = true;
  return c;
}

VoConfig points_only_config() {
  VoConfig config;
  config.tracking.use_lines = false;  // the oracle's images have no lines
  config.triangulation.max_depth = 20.0;
  return config;
}

struct LiveRun {
  explicit LiveRun(int frames, const VoConfig& config = points_only_config())
      : scene(test::SyntheticScene::make(frames, 600, 21)),
        feature_oracle(scene, 0.0, 1),
        stereo_oracle(scene, 0.0, 2),
        odometry(config, calibration_of(scene.stereo), feature_oracle, stereo_oracle) {}
  static std::int64_t timestamp_ns(int frame) { return 1'000'000'000LL + 50'000'000LL * frame; }
  OdometryPose track(int frame) {
    return odometry.track(feature_oracle.image(frame, false), feature_oracle.image(frame, true), timestamp_ns(frame));
  }
  // The true pose of frame f in the odometry's world (the first frame's left camera).
  Eigen::Isometry3d truth(int frame) const { return scene.T_world_left[0].inverse() * scene.T_world_left[frame]; }

  test::SyntheticScene scene;
  test::OracleFrontend feature_oracle, stereo_oracle;
  StereoOdometry odometry;
};

TEST(StereoOdometry, TracksPairsPushedOneAtATime) {
  constexpr int kFrames = 30;
  LiveRun run(kFrames);
  int keyframes = 0;
  for (int f = 0; f < kFrames; ++f) {
    const OdometryPose pose = run.track(f);
    ASSERT_TRUE(pose.tracked) << "frame " << f;
    EXPECT_EQ(pose.timestamp_ns, LiveRun::timestamp_ns(f));
    EXPECT_EQ(pose.new_segment, f == 0);
    keyframes += pose.keyframe;
    EXPECT_LT((pose.T_world_camera.translation() - run.truth(f).translation()).norm(), 2e-3) << "frame " << f;
    const Eigen::AngleAxisd rotation_error(pose.T_world_camera.linear().transpose() * run.truth(f).linear());
    EXPECT_LT(rotation_error.angle(), 1e-3) << "frame " << f;
    if (f > 0) {
      EXPECT_GT(pose.tracked_points, 100) << "frame " << f;
    }
  }
  EXPECT_GE(keyframes, 2);
  EXPECT_EQ(run.odometry.keyframes(), keyframes);
  EXPECT_EQ(run.odometry.tracking_losses(), 0);
  EXPECT_EQ(run.odometry.segments(), 1);
  EXPECT_FALSE(run.odometry.map().points().empty());
  // Every frame's left image and every keyframe's right image ran the network.
  EXPECT_EQ(run.odometry.timing().stats(Module::PE).samples, static_cast<std::size_t>(kFrames + keyframes));
  EXPECT_EQ(run.odometry.timing().stats(Module::IPE).samples, static_cast<std::size_t>(kFrames - 1));
}

// Unusable images are refused with what is wrong, and leave the odometry as it was: the next good pair is still
// its first frame.
TEST(StereoOdometry, RefusesUnusableImagesWithoutChangingState) {
  LiveRun run(3);
  const cv::Mat left = run.feature_oracle.image(0, false), right = run.feature_oracle.image(0, true);
  auto message = [&](const cv::Mat& l, const cv::Mat& r) -> std::string {
    try {
      run.odometry.track(l, r, 0);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(message(cv::Mat(), right), "stereo odometry: the left image is empty");
  const std::string size = message(left, cv::Mat(50, 100, CV_8UC1, cv::Scalar(0)));
  EXPECT_NE(size.find("the right image is 100x50, the calibration's"), std::string::npos) << size;
  cv::Mat deep;
  left.convertTo(deep, CV_16U);
  EXPECT_NE(message(deep, right).find("8-bit grey or BGR is needed"), std::string::npos);
  EXPECT_EQ(run.odometry.timing().stats(Module::PE).samples, 0u);

  const OdometryPose first = run.track(0);
  EXPECT_TRUE(first.tracked);
  EXPECT_TRUE(first.new_segment);
}

// Colour input is converted to grey: the same poses as the grey images.
TEST(StereoOdometry, BgrPairsGiveTheSamePosesAsGrey) {
  LiveRun grey(12), colour(12);
  for (int f = 0; f < 12; ++f) {
    cv::Mat left, right;
    cv::cvtColor(colour.feature_oracle.image(f, false), left, cv::COLOR_GRAY2BGR);
    cv::cvtColor(colour.feature_oracle.image(f, true), right, cv::COLOR_GRAY2BGR);
    const OdometryPose a = grey.track(f);
    const OdometryPose b = colour.odometry.track(left, right, LiveRun::timestamp_ns(f));
    ASSERT_TRUE(b.tracked) << "frame " << f;
    EXPECT_TRUE(a.T_world_camera.isApprox(b.T_world_camera, 1e-12)) << "frame " << f;
  }
}

// A camera driver may refill its buffer while the frame is still in the pipeline: prepare keeps its own pixels
// even where rectification has nothing to remap.
TEST(StereoOdometry, PrepareKeepsItsOwnCopyOfThePixels) {
  LiveRun run(1);
  cv::Mat left = run.feature_oracle.image(0, false).clone(), right = run.feature_oracle.image(0, true).clone();
  const cv::Mat original = left.clone();
  const FrameInput in = run.odometry.prepare(left, right, 7, 3);
  left.setTo(cv::Scalar(255));
  EXPECT_EQ(cv::norm(in.left, original, cv::NORM_INF), 0.0);
  EXPECT_EQ(in.index, 3u);
  EXPECT_EQ(in.timestamp_ns, 7);
}

// The stream overlaps the stages on two threads and hands every pose back in push order, next to the truth.
TEST(OdometryStream, DeliversEveryPoseInOrderNearTheTruth) {
  constexpr int kFrames = 30;
  LiveRun run(kFrames);
  std::vector<OdometryPose> poses;
  {
    OdometryStream stream(run.odometry, [&](const OdometryPose& pose) { poses.push_back(pose); });
    for (int f = 0; f < kFrames; ++f)
      stream.push(run.feature_oracle.image(f, false), run.feature_oracle.image(f, true), LiveRun::timestamp_ns(f));
    stream.finish();
    EXPECT_EQ(stream.pushed(), static_cast<std::size_t>(kFrames));
    EXPECT_EQ(stream.dropped(), 0u);
    EXPECT_EQ(stream.failed(), 0u);
  }
  ASSERT_EQ(poses.size(), static_cast<std::size_t>(kFrames));
  for (int f = 0; f < kFrames; ++f) {
    EXPECT_EQ(poses[f].timestamp_ns, LiveRun::timestamp_ns(f));
    EXPECT_EQ(poses[f].frame_index, static_cast<std::size_t>(f));
    EXPECT_TRUE(poses[f].tracked) << "frame " << f;
    EXPECT_LT((poses[f].T_world_camera.translation() - run.truth(f).translation()).norm(), 2e-3) << "frame " << f;
  }
}

// The feature stage runs ahead of the tracker, so it may match a frame against a keyframe that the tracker has
// replaced by then (the slow subscriber here makes that happen at most keyframes); the tracker then makes the
// same choice again against the last keyframe. The poses are therefore those of the one-thread API, bit for bit,
// however the threads were scheduled. A high min_num_match makes the previous-frame fallback part of that choice.
TEST(OdometryStream, GivesTheSamePosesAsOneThreadBitForBit) {
  constexpr int kFrames = 40;
  VoConfig config = points_only_config();
  config.tracking.min_num_match = 250;
  LiveRun serial(kFrames, config), streamed(kFrames, config);
  std::vector<Eigen::Isometry3d> expected;
  for (int f = 0; f < kFrames; ++f) expected.push_back(serial.track(f).T_world_camera);
  std::vector<OdometryPose> poses;
  {
    OdometryStream stream(streamed.odometry,
                          [&](const OdometryPose& pose) {
                            poses.push_back(pose);
                            std::this_thread::sleep_for(std::chrono::milliseconds(10));
                          },
                          {.queue_capacity = 8, .when_full = QueueFull::block});
    for (int f = 0; f < kFrames; ++f)
      stream.push(streamed.feature_oracle.image(f, false), streamed.feature_oracle.image(f, true),
                  LiveRun::timestamp_ns(f));
    stream.finish();
  }
  ASSERT_EQ(poses.size(), static_cast<std::size_t>(kFrames));
  EXPECT_GE(serial.odometry.keyframes(), 2) << "a keyframe after the first: a reference that can go stale";
  for (int f = 0; f < kFrames; ++f) {
    EXPECT_TRUE(poses[f].tracked) << "frame " << f;
    EXPECT_EQ(poses[f].T_world_camera.matrix(), expected[f].matrix()) << "frame " << f;
  }
}

// A point frontend that fails on one image, as a lost device would.
class FailingFrontend final : public PointFrontend {
 public:
  FailingFrontend(PointFrontend& inner, cv::Mat poisoned) : inner_(&inner), poisoned_(std::move(poisoned)) {}
  features::PointFeatures detect(const cv::Mat& gray) override {
    if (gray.size() == poisoned_.size() && cv::norm(gray, poisoned_, cv::NORM_INF) == 0.0)
      throw std::runtime_error("device lost");
    return inner_->detect(gray);
  }
  features::PointMatches match(const features::PointFeatures& a, const features::PointFeatures& b) override {
    return inner_->match(a, b);
  }

 private:
  PointFrontend* inner_;
  cv::Mat poisoned_;
};

// A frame whose feature stage throws, and one whose pose callback throws, are counted as failed; the stream
// goes on with the frames after them, in order and still tracked.
TEST(OdometryStream, CountsFailedFramesAndGoesOn) {
  constexpr int kFrames = 16, kFeatureFailure = 7, kCallbackFailure = 12;
  const test::SyntheticScene scene = test::SyntheticScene::make(kFrames, 600, 21);
  test::OracleFrontend oracle(scene, 0.0, 1), stereo_oracle(scene, 0.0, 2);
  FailingFrontend failing(oracle, oracle.image(kFeatureFailure, false));
  StereoOdometry odometry(points_only_config(), calibration_of(scene.stereo), failing, stereo_oracle);
  std::vector<OdometryPose> poses;
  {
    OdometryStream stream(odometry, [&](const OdometryPose& pose) {
      if (pose.frame_index == kCallbackFailure) throw std::runtime_error("subscriber gone");
      poses.push_back(pose);
    });
    for (int f = 0; f < kFrames; ++f)
      stream.push(oracle.image(f, false), oracle.image(f, true), LiveRun::timestamp_ns(f));
    stream.finish();
    EXPECT_EQ(stream.pushed(), static_cast<std::size_t>(kFrames));
    EXPECT_EQ(stream.failed(), 2u);
  }
  ASSERT_EQ(poses.size(), static_cast<std::size_t>(kFrames - 2));
  std::size_t next = 0;
  for (int f = 0; f < kFrames; ++f) {
    if (f == kFeatureFailure || f == kCallbackFailure) continue;
    const OdometryPose& pose = poses[next++];
    EXPECT_EQ(pose.frame_index, static_cast<std::size_t>(f));
    EXPECT_TRUE(pose.tracked) << "frame " << f;
    const Eigen::Isometry3d truth = scene.T_world_left[0].inverse() * scene.T_world_left[f];
    EXPECT_LT((pose.T_world_camera.translation() - truth.translation()).norm(), 2e-3) << "frame " << f;
  }
}

// A point frontend whose first detection waits until the test lets it go: a device busy for as long as the test
// needs to push pairs behind it.
class HeldFrontend final : public PointFrontend {
 public:
  explicit HeldFrontend(PointFrontend& inner) : inner_(&inner) {}
  features::PointFeatures detect(const cv::Mat& gray) override {
    if (!started_.exchange(true)) {
      entered_.count_down();
      released_.wait();
    }
    return inner_->detect(gray);
  }
  features::PointMatches match(const features::PointFeatures& a, const features::PointFeatures& b) override {
    return inner_->match(a, b);
  }
  void wait_until_busy() { entered_.wait(); }
  void release() { released_.count_down(); }

 private:
  PointFrontend* inner_;
  std::atomic<bool> started_ = false;
  std::latch entered_{1}, released_{1};
};

// A camera faster than the VO: while the device is busy with frame 0, frames 1-19 arrive at a queue of one with
// drop_oldest, so each one pushes out the one before: 18 dropped, the newest (19) kept, and the answers (0, 19)
// in time order. An unusable pair is refused at push and the stream goes on; a push after finish is an error.
TEST(OdometryStream, DropsTheOldestPairsWhenTheCameraOutpacesIt) {
  constexpr int kFrames = 20;
  const test::SyntheticScene scene = test::SyntheticScene::make(kFrames, 600, 21);
  test::OracleFrontend oracle(scene, 0.0, 1), stereo_oracle(scene, 0.0, 2);
  HeldFrontend held(oracle);
  StereoOdometry odometry(points_only_config(), calibration_of(scene.stereo), held, stereo_oracle);
  std::vector<OdometryPose> poses;
  OdometryStream stream(odometry, [&](const OdometryPose& pose) { poses.push_back(pose); },
                        {.queue_capacity = 1, .when_full = QueueFull::drop_oldest});
  auto push = [&](int f) { stream.push(oracle.image(f, false), oracle.image(f, true), LiveRun::timestamp_ns(f)); };
  push(0);
  held.wait_until_busy();
  for (int f = 1; f < kFrames; ++f) push(f);
  EXPECT_THROW(stream.push(cv::Mat(), oracle.image(0, true), 0), std::invalid_argument);
  held.release();
  stream.finish();
  EXPECT_THROW(push(0), std::logic_error);

  EXPECT_EQ(stream.pushed(), static_cast<std::size_t>(kFrames));
  EXPECT_EQ(stream.dropped(), static_cast<std::size_t>(kFrames - 2));
  EXPECT_EQ(stream.failed(), 0u);
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses[0].timestamp_ns, LiveRun::timestamp_ns(0));
  EXPECT_EQ(poses[1].timestamp_ns, LiveRun::timestamp_ns(kFrames - 1));
  EXPECT_EQ(poses[1].frame_index, static_cast<std::size_t>(kFrames - 1));
  EXPECT_TRUE(poses[1].tracked);  // 19 frames on, the oracle's scene is still in view
  const Eigen::Isometry3d truth = scene.T_world_left[0].inverse() * scene.T_world_left[kFrames - 1];
  EXPECT_LT((poses[1].T_world_camera.translation() - truth.translation()).norm(), 2e-3);
}

}  // namespace
}  // namespace vkvo::system
