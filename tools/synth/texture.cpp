#include "tools/synth/texture.hpp"

#include <opencv2/imgproc.hpp>

namespace vkvo::synth {

Texture::Texture(const cv::Mat& albedo, double texels_per_meter) : tpm_(static_cast<float>(texels_per_meter)) {
  CV_Assert(albedo.type() == CV_8UC1 && !albedo.empty() && texels_per_meter > 0);
  mats_.push_back(albedo.clone());
  // Box-filtered halvings down to a few texels: level l holds the mean albedo over 2^l x 2^l base texels.
  while (mats_.back().cols > 2 || mats_.back().rows > 2) {
    const cv::Mat& prev = mats_.back();
    cv::Mat next;
    cv::resize(prev, next, cv::Size(std::max(1, (prev.cols + 1) / 2), std::max(1, (prev.rows + 1) / 2)), 0, 0,
               cv::INTER_AREA);
    mats_.push_back(next);
  }
  index_levels();
}

Texture Texture::constant(double albedo) {
  return Texture(cv::Mat(1, 1, CV_8UC1, cv::Scalar(std::clamp(albedo, 0.0, 1.0) * 255.0)), 1.0);
}

void Texture::index_levels() {
  levels_.clear();
  for (const cv::Mat& m : mats_) {
    // Scale from the actual size so that rounding up odd sizes keeps the level registered to the surface.
    const float scale = tpm_ * static_cast<float>(m.cols) / static_cast<float>(mats_.front().cols);
    levels_.push_back(Level{m.ptr<uint8_t>(), m.cols, m.rows, m.step[0], scale});
  }
}

}  // namespace vkvo::synth
