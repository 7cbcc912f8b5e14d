#include "io/image_io.hpp"

#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace vkvo::io {

namespace fs = std::filesystem;

namespace {

cv::Mat to_gray8(const cv::Mat& raw, const std::string& source) {
  cv::Mat gray = raw;
  if (raw.channels() == 3)
    cv::cvtColor(raw, gray, cv::COLOR_BGR2GRAY);
  else if (raw.channels() == 4)
    cv::cvtColor(raw, gray, cv::COLOR_BGRA2GRAY);
  else if (raw.channels() != 1)
    throw std::runtime_error(fmt::format("{}: unsupported channel count {}", source, raw.channels()));
  if (gray.depth() == CV_16U)
    gray.convertTo(gray, CV_8U, 1.0 / 256.0);
  else if (gray.depth() != CV_8U)
    throw std::runtime_error(fmt::format("{}: unsupported pixel depth (expected 8 or 16 bit)", source));
  return gray;
}

}  // namespace

void check_image_size(const cv::Size& size, const std::string& source, const ImageLimits& limits) {
  if (size.width < limits.min_side || size.height < limits.min_side)
    throw std::runtime_error(fmt::format("{}: image is {}x{}, smaller than the {}x{} minimum", source, size.width,
                                         size.height, limits.min_side, limits.min_side));
  const long long pixels = static_cast<long long>(size.width) * size.height;
  if (size.width > limits.max_side || size.height > limits.max_side || pixels > limits.max_pixels)
    throw std::runtime_error(fmt::format(
        "{}: image is {}x{} ({:.1f} Mpx), beyond the limit of {} pixels a side and "
        "{:.1f} Mpx",
        source, size.width, size.height, pixels / 1048576.0, limits.max_side, limits.max_pixels / 1048576.0));
}

cv::Mat decode_gray_image(const std::vector<unsigned char>& bytes, const std::string& source,
                          const ImageLimits& limits) {
  cv::Mat raw;
  try {
    raw = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(fmt::format("{}: cannot decode image ({})", source, e.what()));
  }
  if (raw.empty()) throw std::runtime_error(fmt::format("{}: cannot decode image (corrupt or unsupported)", source));
  cv::Mat gray = to_gray8(raw, source);
  check_image_size(gray.size(), source, limits);
  return gray;
}

cv::Mat read_gray_image(const fs::path& file, const ImageLimits& limits) {
  if (fs::is_directory(file)) throw std::runtime_error(fmt::format("{}: is a directory, not an image", file.string()));
  if (!fs::is_regular_file(file)) throw std::runtime_error(fmt::format("{}: image file is missing", file.string()));
  cv::Mat raw;
  try {
    raw = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(fmt::format("{}: cannot decode image ({})", file.string(), e.what()));
  }
  if (raw.empty())
    throw std::runtime_error(fmt::format("{}: cannot decode image (corrupt or unsupported)", file.string()));
  cv::Mat gray = to_gray8(raw, file.string());
  check_image_size(gray.size(), file.string(), limits);
  return gray;
}

}  // namespace vkvo::io
