#pragma once
// Line segment extraction: OpenCV FastLineDetector or LSD on an optionally downscaled image, coordinates mapped
// back to full resolution, then merge passes and length filters (see line_merge.hpp).
#include <vector>

#include <opencv2/core.hpp>

#include "features/lines/line_params.hpp"
#include "features/lines/line_segment.hpp"

namespace vkvo::features {

class LineDetector {
 public:
  explicit LineDetector(LineDetectorParams params);

  // `image`: 8-bit grayscale (or BGR, converted). Returns segments in full-resolution pixel coordinates
  // (pixel centres at integers). Thread-safe: every call uses its own OpenCV detector object.
  std::vector<LineSegment> detect(const cv::Mat& image) const;

  // The raw detector output (before merging and filtering), in full-resolution coordinates.
  std::vector<LineSegment> detect_raw(const cv::Mat& image) const;

  const LineDetectorParams& params() const { return params_; }

 private:
  LineDetectorParams params_;
};

}  // namespace vkvo::features
