#pragma once
// Left-right line matching by appearance, for the lines that point matches leave unpaired. The paper pairs a left
// and a right line through the stereo point matches they share (eq. 2), so a line with fewer than two matched
// keypoints on it, which is most lines where texture or light is poor, gets no right partner and no triangulation
// of its own. In a rectified pair the two images of a line span the same rows, one shifted against the other by
// a disparity that the depth gates bound, and the image strips along them look alike: their zero-mean normalised
// cross-correlation (ZNCC, blind to gain and offset, so it holds in dim images) scores a candidate pair.
#include <vector>

#include <opencv2/core.hpp>

#include "features/lines/line_appearance.hpp"
#include "features/lines/line_params.hpp"
#include "features/lines/line_segment.hpp"

namespace vkvo::features {

// Disparities (left x minus right x) allowed along a stereo line [px]: from the depth gates, f b / depth.
struct DisparityRange {
  double min = 0.0, max = 0.0;
};

// One rectified 8-bit grey image and its line segments.
struct ImageLines {
  const cv::Mat& image;
  const std::vector<LineSegment>& segments;
};

// ZNCC of the image strips along `left` and `right` over the rows both span, or a value below -1 when they share
// too few rows or a strip is flat. The segments must not be horizontal.
float strip_correlation(const ImageLines& left, int left_line, const ImageLines& right, int right_line, int half_width);

// Gives a left line without a right partner (partner[l] < 0) the right line, not yet anyone's partner, that passes
// the row and disparity gates and correlates best, when the correlation reaches min_zncc and each of the two beats
// its own second best pairing by min_margin (so the result is one-to-one and independent of the lines' order).
// `partner` is sized like left.segments.
void add_stereo_partners_by_appearance(const ImageLines& left, const ImageLines& right, const DisparityRange& disparity,
                                       const StereoLineMatchParams& params, std::vector<int>& partner);

}  // namespace vkvo::features
