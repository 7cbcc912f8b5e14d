#pragma once
// `vkvo run --video`: the overlay of every processed frame (viz/overlay.hpp) written to a video file as the run
// goes, and at the end the top-down picture (viz/topdown.hpp) beside it. The tracker only queues each pose; a
// writer thread draws and encodes, so the tracker waits only when the bounded queue is full (which keeps every
// frame). The writer is released when the recorder closes, also when a run is stopped or fails: the video then
// holds the frames so far.
#include <atomic>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <mutex>
#include <thread>

#include <tbb/concurrent_queue.h>
#include <opencv2/videoio.hpp>

#include "io/dataset.hpp"
#include "system/pipeline.hpp"

namespace vkvo::viz {

struct VideoFormat {
  cv::Size image_size;  // the rectified left image (the calibration's size)
  double fps = 20;
};

// The dataset's image size and recorded frame rate (20 when the timestamps do not give one).
VideoFormat video_format(const io::StereoDataset& dataset);

class VideoRecorder final : public system::RunObserver {
 public:
  struct Stats {
    std::size_t frames = 0;             // written to the video
    std::size_t failed = 0;             // frames the writer thread could not draw or encode (logged)
    double draw_ms = 0, encode_ms = 0;  // totals on the writer thread
  };

  // Opens `file` for writing, creating its folder: .mp4 as MPEG-4 part 2 ('mp4v'), .avi as Motion JPEG ('MJPG').
  // Throws std::runtime_error naming the file for any other extension or a writer that does not open.
  VideoRecorder(std::filesystem::path file, const VideoFormat& format, std::size_t queue_capacity = 8);
  ~VideoRecorder() override;  // close()
  VideoRecorder(const VideoRecorder&) = delete;
  VideoRecorder& operator=(const VideoRecorder&) = delete;

  // Queues the frame for the writer thread (waits only while the queue is full).
  void frame(const system::OdometryPose& pose) override;
  // close(), then writes the top-down picture; an error there is logged, the video stays.
  void finish(const io::MapGeometry& map) override;
  // Writes what is queued and releases the video file. Idempotent.
  void close();

  const std::filesystem::path& file() const { return file_; }
  std::filesystem::path topdown_file() const;  // <video stem>_topdown.png beside the video
  Stats stats() const;                         // complete after close()

 private:
  void write_frames();

  std::filesystem::path file_;
  VideoFormat format_;
  cv::VideoWriter writer_;
  tbb::concurrent_bounded_queue<std::shared_ptr<const system::OdometryPose>> queue_;  // nullptr: the end
  mutable std::mutex stats_mutex_;
  Stats stats_;
  bool closed_ = false;
  std::thread thread_;
};

}  // namespace vkvo::viz
