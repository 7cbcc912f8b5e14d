#pragma once
// Two images of one line compared by appearance: the zero-mean normalised cross-correlation (ZNCC, blind to gain
// and offset, so it holds in dim images) of the image strips along them, sampled at corresponding points, and the
// one-to-one choice of clear winners from a table of such scores. Stereo pairs (same rows) and keyframe pairs
// (points transferred through a triangulated line) differ only in how they find the corresponding points.
#include <cstddef>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace vkvo::features {

// Below any correlation: the pair was not scored (gated out, too short an overlap, a flat strip).
constexpr float kNoCorrelation = -2.0f;

// Corresponding points along two images of one line, and in each image the step across the line (unit length,
// towards the same side of the 3D line in both).
struct StripSamples {
  std::vector<Eigen::Vector2f> along_a, along_b;
  Eigen::Vector2f across_a = Eigen::Vector2f::UnitX(), across_b = Eigen::Vector2f::UnitX();
};

// ZNCC over the samples at offsets -half_width ... half_width across the line at each corresponding point, or
// kNoCorrelation when fewer than three points' worth of samples fall inside both images or a strip is flat.
// Both images 8-bit grey.
float strip_zncc(const cv::Mat& image_a, const cv::Mat& image_b, const StripSamples& strip, int half_width);

// `score` holds rows x cols scores (row-major; kNoCorrelation for pairs not to be taken). Each row r with
// partner[r] < 0 takes its best column when that scores at least min_score and beats both the row's and the
// column's second best by min_margin: one-to-one, and independent of the rows' order since the scores do not
// change as pairs are taken. Columns already someone's partner must carry kNoCorrelation.
void assign_clear_winners(const std::vector<float>& score, std::size_t rows, std::size_t cols, float min_score,
                          float min_margin, std::vector<int>& partner);

}  // namespace vkvo::features
