#include "system/odometry_stream.hpp"

#include <stdexcept>

#include <spdlog/spdlog.h>

namespace vkvo::system {

OdometryStream::OdometryStream(StereoOdometry& odometry, PoseCallback on_pose, StreamOptions options)
    : odometry_(&odometry), on_pose_(std::move(on_pose)), when_full_(options.when_full) {
  if (options.queue_capacity == 0) throw std::invalid_argument("odometry stream: queue_capacity must be at least 1");
  waiting_.set_capacity(static_cast<std::ptrdiff_t>(options.queue_capacity));
  featured_.set_capacity(1);  // the optimisation stage works on one frame while the next one's features run
  feature_thread_ = std::thread([this] { run_features(); });
  optimisation_thread_ = std::thread([this] { run_optimisation(); });
}

OdometryStream::~OdometryStream() { finish(); }

void OdometryStream::push(const cv::Mat& left, const cv::Mat& right, std::int64_t timestamp_ns,
                          std::optional<std::size_t> frame_index) {
  if (finished_) throw std::logic_error("odometry stream: push after finish");
  auto frame =
      std::make_shared<FrameInput>(odometry_->prepare(left, right, timestamp_ns, frame_index.value_or(pushed_)));
  ++pushed_;
  if (when_full_ == QueueFull::block) {
    waiting_.push(std::move(frame));
    return;
  }
  while (!waiting_.try_push(frame)) {
    FramePtr oldest;
    if (waiting_.try_pop(oldest)) {
      ++dropped_;
      spdlog::debug("odometry stream: queue full, frame {} dropped", oldest->index);
    }
  }
}

void OdometryStream::finish() {
  if (finished_) return;
  finished_ = true;
  waiting_.push(nullptr);
  feature_thread_.join();
  optimisation_thread_.join();
}

template <typename Work>
void OdometryStream::drain(FrameQueue& queue, const char* stage, Work work) {
  for (;;) {
    FramePtr frame;
    queue.pop(frame);
    if (!frame) return;
    const std::size_t index = frame->index;  // `work` may move the frame on
    try {
      work(frame);
    } catch (const std::exception& e) {
      ++failed_;
      spdlog::error("frame {}: {} failed: {}", index, stage, e.what());
    }
  }
}

void OdometryStream::run_features() {
  drain(waiting_, "feature stage", [this](FramePtr& frame) {
    odometry_->extract_features(*frame);
    featured_.push(std::move(frame));
  });
  featured_.push(nullptr);
}

void OdometryStream::run_optimisation() {
  drain(featured_, "optimisation stage or pose callback",
        [this](const FramePtr& frame) { on_pose_(odometry_->optimise(*frame)); });
}

}  // namespace vkvo::system
