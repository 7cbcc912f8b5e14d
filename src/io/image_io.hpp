#pragma once
// Reading the images a user gives (dataset frames, `vkvo features`/`lines` inputs): one decoder with clear errors
// and one size limit, so that an image the networks cannot take fails up front with its size and the limit.
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace vkvo::io {

struct ImageLimits {
  // SuperPoint works on 8x8 cells and drops a border; below two cells a side there is nothing to detect.
  int min_side = 16;
  // Beyond these the networks' activations need GiBs of device memory (docs/bad-input.md).
  int max_side = 8192;
  long long max_pixels = 16LL << 20;
};

// Throws std::runtime_error naming `source`, the size and the limit when `size` is outside `limits`.
void check_image_size(const cv::Size& size, const std::string& source, const ImageLimits& limits = {});

// Decodes an 8/16-bit gray, BGR or BGRA image file into 8-bit gray and checks its size. Throws naming the file
// when it is missing, a directory, undecodable, of another pixel format, or too small or too large.
cv::Mat read_gray_image(const std::filesystem::path& file, const ImageLimits& limits = {});

// The same from an encoded image in memory (what the fuzz target feeds); `source` names it in messages.
cv::Mat decode_gray_image(const std::vector<unsigned char>& bytes, const std::string& source,
                          const ImageLimits& limits = {});

}  // namespace vkvo::io
