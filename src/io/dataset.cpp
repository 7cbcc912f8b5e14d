#include "io/dataset.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "io/config.hpp"
#include "io/image_io.hpp"

namespace vkvo::io {

namespace fs = std::filesystem;

const char* to_string(DatasetKind kind) {
  switch (kind) {
    case DatasetKind::euroc: return "euroc";
    case DatasetKind::kitti: return "kitti";
  }
  return "unknown";
}

std::pair<std::size_t, std::size_t> parse_frame_span(const std::string& text) {
  const auto number = [&](const std::string& part) {
    std::size_t used = 0;
    unsigned long long value = 0;
    try {
      value = std::stoull(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (part.empty() || used != part.size() || part.front() == '-' || part.front() == '+')
      throw std::invalid_argument(fmt::format("frame span '{}': expected A-B or A (frame indices)", text));
    return static_cast<std::size_t>(value);
  };
  const auto dash = text.find('-');
  const std::size_t first = number(text.substr(0, dash));
  const std::size_t last = dash == std::string::npos ? first : number(text.substr(dash + 1));
  if (last < first) throw std::invalid_argument(fmt::format("frame span '{}': the end comes before the start", text));
  return {first, last};
}

bool is_image_file(const fs::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* known : {".png", ".jpg", ".jpeg", ".pgm", ".ppm", ".bmp", ".tif", ".tiff"})
    if (ext == known) return true;
  return false;
}

DatasetOptions load_dataset_options(const YAML::Node& dataset_section, const YAML::Node& camera_section) {
  DatasetOptions options;
  const long first = param<long>(dataset_section, "first_frame", 0);
  const long last = param<long>(dataset_section, "last_frame", -1);
  const long stride = param<long>(dataset_section, "stride", 1);
  if (first < 0) throw std::runtime_error("config key 'first_frame': must be >= 0");
  if (stride < 1) throw std::runtime_error("config key 'stride': must be >= 1");
  options.range.first = static_cast<std::size_t>(first);
  if (last >= 0) options.range.last = static_cast<std::size_t>(last);
  options.range.stride = static_cast<std::size_t>(stride);
  for (const std::string& span : param<std::vector<std::string>>(dataset_section, "skip", {})) {
    try {
      options.range.skip.push_back(parse_frame_span(span));
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(fmt::format("config key 'skip': {}", e.what()));
    }
  }
  const double max_dt_ms = param<double>(dataset_section, "max_stereo_dt_ms", 1.0);
  if (!(max_dt_ms >= 0)) throw std::runtime_error("config key 'max_stereo_dt_ms': must be >= 0");
  options.max_stereo_dt_ns = static_cast<std::int64_t>(std::llround(max_dt_ms * 1e6));
  options.camera_overrides = camera_section;
  return options;
}

const StereoFrame& StereoDataset::frame(std::size_t i) const {
  if (i >= frames_.size())
    throw std::out_of_range(fmt::format("{}: frame {} requested, dataset has {}", name_, i, frames_.size()));
  return frames_[i];
}

StereoImages StereoDataset::load(std::size_t i) const { return {load_left(i), load_right(i)}; }

cv::Mat StereoDataset::load_left(std::size_t i) const { return load_image(frame(i).left, calibration_.left); }

cv::Mat StereoDataset::load_right(std::size_t i) const { return load_image(frame(i).right, calibration_.right); }

cv::Mat StereoDataset::load_image(const fs::path& file, const CameraCalibration& camera) const {
  // The test fixtures' frames are a few pixels wide; images too small for the networks are refused by them by name.
  const cv::Mat gray = read_gray_image(file, ImageLimits{.min_side = 1});
  if (camera.width > 0 && (gray.cols != camera.width || gray.rows != camera.height))
    throw std::runtime_error(fmt::format("{}: image is {}x{} but the calibration says {}x{}", file.string(), gray.cols,
                                         gray.rows, camera.width, camera.height));
  return gray;
}

cv::Size StereoDataset::image_size(const fs::path& file) {
  const cv::Mat image = cv::imread(file.string(), cv::IMREAD_GRAYSCALE);
  if (image.empty())
    throw std::runtime_error(fmt::format("{}: cannot decode image (corrupt or unsupported)", file.string()));
  return image.size();
}

void StereoDataset::finish(const DatasetOptions& options, const std::string& calibration_source) {
  std::string source = calibration_source;
  if (options.camera_overrides.IsDefined() && !options.camera_overrides.IsNull()) {
    calibration_ = apply_camera_overrides(options.camera_overrides, calibration_, options.config_file);
    source += " + config camera section";
  }
  validate_calibration(calibration_, source);

  const FrameRange& range = options.range;
  if (range.stride == 0) throw std::runtime_error("frame range: stride must be at least 1");
  const std::size_t total = frames_.size();
  const std::size_t last = std::min(range.last.value_or(total == 0 ? 0 : total - 1), total == 0 ? 0 : total - 1);
  if (total == 0 || range.first > last)
    throw std::runtime_error(fmt::format("{}: frame range [{}, {}] selects no frames (the sequence has {})",
                                         root_.string(), range.first,
                                         range.last ? std::to_string(*range.last) : std::string("end"), total));
  std::vector<StereoFrame> selected;
  selected.reserve((last - range.first) / range.stride + 1);
  const auto skipped = [&](std::size_t i) {
    return std::any_of(range.skip.begin(), range.skip.end(),
                       [&](const auto& s) { return i >= s.first && i <= s.second; });
  };
  for (std::size_t i = range.first; i <= last; i += range.stride)
    if (!skipped(i)) selected.push_back(frames_[i]);
  if (selected.empty())
    throw std::runtime_error(fmt::format("{}: the frames to skip leave none of the range", root_.string()));
  frames_ = std::move(selected);
  spdlog::info("dataset {} ({}): {} stereo frames of {}, {:.2f} s", name_, to_string(kind()), frames_.size(), total,
               frames_.back().timestamp_s - frames_.front().timestamp_s);
}

std::unique_ptr<StereoDataset> open_dataset(const fs::path& path, const DatasetOptions& options) {
  if (!fs::exists(path)) throw std::runtime_error(fmt::format("{}: dataset path does not exist", path.string()));
  if (EurocDataset::find_root(path)) return std::make_unique<EurocDataset>(path, options);
  if (KittiDataset::find_root(path)) return std::make_unique<KittiDataset>(path, options);
  throw std::runtime_error(
      fmt::format("{}: not a recognised dataset (expected EuRoC mav0/cam0,cam1 or KITTI image_0/image_1 + calib.txt)",
                  path.string()));
}

}  // namespace vkvo::io
