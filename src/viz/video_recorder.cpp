#include "viz/video_recorder.hpp"

#include <algorithm>
#include <cctype>
#include <stdexcept>
#include <string>
#include <system_error>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "system/timing.hpp"
#include "viz/overlay.hpp"
#include "viz/topdown.hpp"

namespace vkvo::viz {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const fs::path& file, const std::string& problem) {
  throw std::runtime_error(fmt::format("video file {}: {}", file.string(), problem));
}

// The codec for the file's extension: mp4v in .mp4, MJPG in .avi.
int fourcc_for(const fs::path& file) {
  std::string extension = file.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".mp4") return cv::VideoWriter::fourcc('m', 'p', '4', 'v');
  if (extension == ".avi") return cv::VideoWriter::fourcc('M', 'J', 'P', 'G');
  fail(file, fmt::format("unsupported extension '{}' (use .mp4 or .avi)", extension));
}

}  // namespace

VideoFormat video_format(const io::StereoDataset& dataset) {
  const auto& c = dataset.calibration();
  VideoFormat format{.image_size = {c.left.width, c.left.height}};
  if (dataset.size() >= 2) {
    const double span = dataset.frame(dataset.size() - 1).timestamp_s - dataset.frame(0).timestamp_s;
    if (span > 0) format.fps = static_cast<double>(dataset.size() - 1) / span;
  }
  return format;
}

VideoRecorder::VideoRecorder(fs::path file, const VideoFormat& format, std::size_t queue_capacity)
    : file_(std::move(file)), format_(format) {
  const int fourcc = fourcc_for(file_);
  if (format_.image_size.width <= 0 || format_.image_size.height <= 0)
    fail(file_, fmt::format("no frame size ({}x{})", format_.image_size.width, format_.image_size.height));
  if (const fs::path folder = file_.parent_path(); !folder.empty()) {
    std::error_code error;
    fs::create_directories(folder, error);
    if (error) fail(file_, fmt::format("cannot create its folder: {}", error.message()));
  }
  // FFmpeg writes both containers; naming it keeps OpenCV from trying (and logging) its other backends.
  if (!writer_.open(file_.string(), cv::CAP_FFMPEG, fourcc, format_.fps, overlay_size(format_.image_size)))
    fail(file_, "OpenCV's video writer cannot open it for writing (is the folder writable?)");
  queue_.set_capacity(static_cast<std::ptrdiff_t>(std::max<std::size_t>(1, queue_capacity)));
  thread_ = std::thread([this] { write_frames(); });
}

VideoRecorder::~VideoRecorder() { close(); }

void VideoRecorder::frame(const system::OdometryPose& pose) {
  if (closed_) return;
  queue_.push(std::make_shared<const system::OdometryPose>(pose));
}

void VideoRecorder::close() {
  if (closed_) return;
  closed_ = true;
  queue_.push(nullptr);
  thread_.join();
  writer_.release();
}

void VideoRecorder::finish(const io::MapGeometry& map) {
  close();
  try {
    if (!cv::imwrite(topdown_file().string(), draw_topdown(map)))
      spdlog::error("top-down picture {}: OpenCV could not write it", topdown_file().string());
  } catch (const cv::Exception& e) {
    spdlog::error("top-down picture {}: {}", topdown_file().string(), e.what());
  }
}

fs::path VideoRecorder::topdown_file() const { return file_.parent_path() / (file_.stem().string() + "_topdown.png"); }

VideoRecorder::Stats VideoRecorder::stats() const {
  const std::lock_guard lock(stats_mutex_);
  return stats_;
}

void VideoRecorder::write_frames() {
  const cv::Size size = overlay_size(format_.image_size);
  for (;;) {
    std::shared_ptr<const system::OdometryPose> pose;
    queue_.pop(pose);
    if (!pose) return;
    try {
      system::Stopwatch watch;
      cv::Mat overlay = draw_overlay(*pose, format_.image_size);
      if (overlay.size() != size) cv::resize(overlay, overlay, size);  // an image not of the calibration's size
      const double draw_ms = watch.lap();
      writer_.write(overlay);
      const double encode_ms = watch.lap();
      const std::lock_guard lock(stats_mutex_);
      ++stats_.frames;
      stats_.draw_ms += draw_ms;
      stats_.encode_ms += encode_ms;
    } catch (const std::exception& e) {
      spdlog::error("video file {}: frame {} not written: {}", file_.string(), pose->frame_index, e.what());
      const std::lock_guard lock(stats_mutex_);
      ++stats_.failed;
    }
  }
}

}  // namespace vkvo::viz
