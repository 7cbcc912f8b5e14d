#include "features/lines/line_detector.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <utility>

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

// The grey levels at the `fraction` and 1 - `fraction` quantiles of an 8-bit image.
std::pair<int, int> percentile_range(const cv::Mat& gray, double fraction) {
  std::array<int, 256> histogram{};
  for (int y = 0; y < gray.rows; ++y) {
    const uchar* row = gray.ptr<uchar>(y);
    for (int x = 0; x < gray.cols; ++x) ++histogram[row[x]];
  }
  const double tail = fraction * static_cast<double>(gray.total());
  int lo = 0, hi = 255;
  double below = histogram[0], above = histogram[255];  // pixels at or below lo, at or above hi
  while (lo < 255 && below <= tail) below += histogram[++lo];
  while (hi > 0 && above <= tail) above += histogram[--hi];
  return {lo, std::max(lo, hi)};
}

// A linear stretch of `gray` so that its 1st-99th percentile range spans `min_contrast` levels, when it spans less.
cv::Mat with_min_contrast(const cv::Mat& gray, float min_contrast) {
  if (min_contrast <= 0.0f) return gray;
  const auto [lo, hi] = percentile_range(gray, 0.01);
  const int range = std::max(hi - lo, 1);
  if (range >= min_contrast) return gray;
  const double gain = min_contrast / range;
  cv::Mat stretched;
  gray.convertTo(stretched, CV_8U, gain, -gain * lo);
  return stretched;
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

  small = with_min_contrast(small, params_.min_contrast);

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
