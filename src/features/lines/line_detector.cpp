#include "features/lines/line_detector.hpp"

#include <algorithm>
#include <stdexcept>

#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc/fast_line_detector.hpp>

#include "features/lines/line_merge.hpp"

namespace vkvo::features {
namespace {

int lsd_refine_flag(LsdParams::Refine refine) {
  switch (refine) {
    case LsdParams::Refine::kNone: return cv::LSD_REFINE_NONE;
    case LsdParams::Refine::kStandard: return cv::LSD_REFINE_STD;
    case LsdParams::Refine::kAdvanced: return cv::LSD_REFINE_ADV;
  }
  return cv::LSD_REFINE_STD;
}

cv::Mat to_gray8(const cv::Mat& image) {
  if (image.empty()) throw std::runtime_error("LineDetector: empty image");
  if (image.type() == CV_8UC1) return image;
  cv::Mat gray;
  if (image.type() == CV_8UC3) {
    cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  } else if (image.type() == CV_8UC4) {
    cv::cvtColor(image, gray, cv::COLOR_BGRA2GRAY);
  } else {
    throw std::runtime_error("LineDetector: expected an 8-bit gray or BGR image, got OpenCV type " +
                             std::to_string(image.type()));
  }
  return gray;
}

}  // namespace

LineDetector::LineDetector(LineDetectorParams params) : params_(std::move(params)) {
  if (!(params_.scale > 0.0f && params_.scale <= 1.0f))
    throw std::runtime_error("LineDetector: scale must lie in (0, 1]");
}

std::vector<LineSegment> LineDetector::detect_raw(const cv::Mat& image) const {
  const cv::Mat gray = to_gray8(image);
  cv::Mat small = gray;
  // The resize maps full-resolution pixel centre x to (x + 0.5) * s - 0.5; inverted below.
  const double sx = params_.scale == 1.0f ? 1.0 : std::max(1, cvRound(gray.cols * params_.scale)) / double(gray.cols);
  const double sy = params_.scale == 1.0f ? 1.0 : std::max(1, cvRound(gray.rows * params_.scale)) / double(gray.rows);
  if (params_.scale != 1.0f)
    cv::resize(gray, small, cv::Size(cvRound(gray.cols * sx), cvRound(gray.rows * sy)), 0, 0, cv::INTER_AREA);

  std::vector<cv::Vec4f> raw;
  if (params_.method == LineDetectorMethod::kFastLineDetector) {
    const FldParams& f = params_.fld;
    auto fld = cv::ximgproc::createFastLineDetector(f.length_threshold, f.distance_threshold, f.canny_threshold1,
                                                    f.canny_threshold2, f.canny_aperture, /*do_merge=*/false);
    fld->detect(small, raw);
  } else {
    auto lsd = cv::createLineSegmentDetector(lsd_refine_flag(params_.lsd.refine));
    lsd->detect(small, raw);
  }

  std::vector<LineSegment> segments;
  segments.reserve(raw.size());
  auto to_full = [&](float x, float y) {
    return Eigen::Vector2f(static_cast<float>((x + 0.5) / sx - 0.5), static_cast<float>((y + 0.5) / sy - 0.5));
  };
  for (const cv::Vec4f& v : raw) segments.push_back({to_full(v[0], v[1]), to_full(v[2], v[3])});
  return segments;
}

std::vector<LineSegment> LineDetector::detect(const cv::Mat& image) const {
  std::vector<LineSegment> segments = detect_raw(image);
  for (const MergeStage& stage : params_.merge_stages) {
    segments = merge_segments(std::move(segments), stage.merge);
    filter_short_segments(segments, stage.min_length_after);
  }
  filter_short_segments(segments, params_.min_length);
  return segments;
}

}  // namespace vkvo::features
