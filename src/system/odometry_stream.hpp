#pragma once
// StereoOdometry for a live camera with the paper's two-stage overlap (Fig. 2): the caller pushes raw pairs as
// they arrive; a feature thread runs extract_features (the point task on the Vulkan device || the line task) while
// an optimisation thread runs optimise on the frame before, and each pose is handed to a callback, in frame order.
// Pairs wait in a bounded queue; when it is full, push either waits for room or drops the oldest waiting pair
// (a camera that outpaces the VO then costs frames, not latency). push and finish belong to one thread, the
// camera's.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <thread>

#include <tbb/concurrent_queue.h>
#include <opencv2/core.hpp>

#include "system/stereo_odometry.hpp"

namespace vkvo::system {

enum class QueueFull { block, drop_oldest };

struct StreamOptions {
  std::size_t queue_capacity = 2;  // pairs waiting for the feature stage (the config's tracking.queue_capacity)
  QueueFull when_full = QueueFull::block;
};

class OdometryStream {
 public:
  // Called on the optimisation thread, once per pair that was neither dropped nor failed, in push order.
  using PoseCallback = std::function<void(const OdometryPose&)>;

  // `odometry` must outlive the stream and be used by nothing else meanwhile.
  OdometryStream(StereoOdometry& odometry, PoseCallback on_pose, StreamOptions options = {});
  ~OdometryStream();  // finish()
  OdometryStream(const OdometryStream&) = delete;
  OdometryStream& operator=(const OdometryStream&) = delete;

  // Checks, converts and rectifies the pair on the caller's thread (StereoOdometry::prepare, which copies the
  // pixels: the caller may reuse its buffers at once), then queues it. An unusable image throws
  // std::invalid_argument here and nothing is queued. Pushing after finish() throws std::logic_error.
  // `frame_index` numbers the pair in logs and in its OdometryPose (default: the count of pairs pushed before).
  void push(const cv::Mat& left, const cv::Mat& right, std::int64_t timestamp_ns,
            std::optional<std::size_t> frame_index = std::nullopt);

  // Processes every queued pair, calls back for each, and ends the threads. Idempotent.
  void finish();

  std::size_t pushed() const { return pushed_; }
  std::size_t dropped() const { return dropped_; }  // by QueueFull::drop_oldest
  // Pairs whose feature or optimisation stage threw (logged with the frame and the reason), or whose callback did.
  std::size_t failed() const { return failed_; }

 private:
  using FramePtr = std::shared_ptr<FrameInput>;  // nullptr: the end of the stream
  using FrameQueue = tbb::concurrent_bounded_queue<FramePtr>;

  // Pops frames until the end of the stream and runs `work` on each; a frame whose work throws is counted as
  // failed and logged with `stage`, and the frames after it go on.
  template <typename Work>
  void drain(FrameQueue& queue, const char* stage, Work work);
  void run_features();
  void run_optimisation();

  StereoOdometry* odometry_;
  PoseCallback on_pose_;
  QueueFull when_full_;
  FrameQueue waiting_, featured_;
  std::atomic<std::size_t> pushed_ = 0, dropped_ = 0, failed_ = 0;
  bool finished_ = false;
  std::thread feature_thread_, optimisation_thread_;
};

}  // namespace vkvo::system
