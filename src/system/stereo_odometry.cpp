#include "system/stereo_odometry.hpp"

#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <tbb/parallel_invoke.h>
#include <opencv2/imgproc.hpp>

// Built with ThreadSanitizer: GCC defines __SANITIZE_THREAD__, clang answers __has_feature(thread_sanitizer).
#if defined(__SANITIZE_THREAD__)
#define VKVO_THREAD_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define VKVO_THREAD_SANITIZER 1
#endif
#endif

namespace vkvo::system {
namespace {

// The image as 8-bit grey, or an error that says what is wrong with it.
cv::Mat grey_image(const cv::Mat& image, const char* which, cv::Size expected) {
  if (image.empty()) throw std::invalid_argument(fmt::format("stereo odometry: the {} image is empty", which));
  if (image.size() != expected)
    throw std::invalid_argument(fmt::format("stereo odometry: the {} image is {}x{}, the calibration's {}x{}", which,
                                            image.cols, image.rows, expected.width, expected.height));
  if (image.type() == CV_8UC1) return image;
  if (image.type() == CV_8UC3) {
    cv::Mat grey;
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
    return grey;
  }
  throw std::invalid_argument(
      fmt::format("stereo odometry: the {} image has {} channel(s) of depth {} (OpenCV type "
                  "{}); 8-bit grey or BGR is needed",
                  which, image.channels(), image.depth(), image.type()));
}

// The point task: left-image network, then matches against the last keyframe, or against the previous frame
// when the keyframe gives fewer than `min_num_match`.
void run_point_task(FrameInput& in, PointFrontend& frontend, const MatchReference& reference,
                    const std::shared_ptr<const features::PointFeatures>& previous, int min_num_match) {
  const Stopwatch pe;
  in.points = frontend.detect(in.left);
  in.pe_ms = pe.ms();
  const Stopwatch pm;
  ReferenceMatches matched = match_to_reference(frontend, in.points, reference, previous.get(), min_num_match);
  in.matches = std::move(matched.matches);
  in.reference_keyframe = matched.keyframe;
  in.matched_previous_frame = matched.previous_frame;
  in.matched_against = reference.keyframe;
  in.previous_points = previous;
  in.pm_ms = pm.ms();
}

}  // namespace

StereoOdometry::StereoOdometry(const VoConfig& config, const io::StereoCalibration& calibration,
                               PointFrontend& feature_frontend, PointFrontend& stereo_frontend)
    : config_(config),
      rig_(calibration),
      // World frame = the raw left camera of the first frame; the tracker estimates the rectified one.
      T_rect_rawleft_(rig_.T_rawleft_rectified().inverse()),
      feature_frontend_(&feature_frontend),
      tracker_(config, rig_.stereo(), stereo_frontend, rig_.T_rawleft_rectified()),
      line_detector_(config.lines.detector) {}

FrameInput StereoOdometry::prepare(const cv::Mat& left, const cv::Mat& right, std::int64_t timestamp_ns,
                                   std::size_t index) const {
  FrameInput in;
  in.index = index;
  in.timestamp_ns = timestamp_ns;
  in.timestamp_s = static_cast<double>(timestamp_ns) * 1e-9;
  rig_.rectify(grey_image(left, "left", rig_.image_size()), grey_image(right, "right", rig_.image_size()), in.left,
               in.right);
  // Without remapping these still share the caller's pixels, which a camera driver may reuse for the next frame.
  if (in.left.data == left.data) in.left = in.left.clone();
  if (in.right.data == right.data) in.right = in.right.clone();
  return in;
}

void StereoOdometry::extract_features(FrameInput& in) {
  const MatchReference reference = tracker_.reference();
  const auto point_task = [&] {
    run_point_task(in, *feature_frontend_, reference, previous_, config_.tracking.min_num_match);
  };
  const auto line_task = [&] {
    if (!config_.tracking.use_lines) return;
    const Stopwatch le;
    in.lines = line_detector_.detect(in.left);
    in.le_ms = le.ms();
  };
#if defined(VKVO_THREAD_SANITIZER)
  // ThreadSanitizer cannot see a task handed to a TBB worker (libtbb is not built with it), so it would report
  // every access of the tasks as a race; in a -DVKVO_SANITIZE=thread build they run one after the other on the
  // feature thread, and what it checks is the stages' own threads, queues and the published reference.
  point_task();
  line_task();
#else
  tbb::parallel_invoke(point_task, line_task);
#endif
  previous_ = std::make_shared<const features::PointFeatures>(in.points);
}

OdometryPose StereoOdometry::optimise(const FrameInput& in) {
  timing_.add(Module::PE, in.pe_ms);
  if (in.le_ms > 0) timing_.add(Module::LE, in.le_ms);
  if (in.pm_ms > 0) timing_.add(Module::PM, in.pm_ms);
  TrackResult r = tracker_.track(in, timing_);
  auto observations = std::make_shared<FrameObservations>(std::move(r.observations));
  observations->left = in.left;
  return {.frame_index = in.index,
          .timestamp_ns = in.timestamp_ns,
          .T_world_camera = r.T_world_camera * T_rect_rawleft_,
          .tracked = r.tracked,
          .state = r.state,
          .keyframe = r.keyframe,
          .new_segment = r.new_segment,
          .segment = r.segment,
          .merge = r.merge,
          .tracked_points = r.tracked_points,
          .tracked_lines = r.tracked_lines,
          .note = r.note,
          .observations = std::move(observations)};
}

std::vector<std::pair<std::size_t, Eigen::Isometry3d>> StereoOdometry::refined_keyframes() const {
  std::vector<std::pair<std::size_t, Eigen::Isometry3d>> out;
  for (const auto& [id, kf] : tracker_.map().keyframes())
    out.emplace_back(static_cast<std::size_t>(kf.frame_id), kf.T_world_camera * T_rect_rawleft_);
  return out;
}

OdometryPose StereoOdometry::track(const cv::Mat& left, const cv::Mat& right, std::int64_t timestamp_ns) {
  FrameInput in = prepare(left, right, timestamp_ns, next_index_);
  extract_features(in);
  ++next_index_;
  return optimise(in);
}

}  // namespace vkvo::system
