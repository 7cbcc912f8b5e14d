// The appearance comparison shared by stereo and keyframe line pairing: the strips' ZNCC ignores gain and offset,
// sees a flat strip or one outside the image as no correlation, and follows the sampled points; the choice of
// clear winners is one-to-one, honours the margin both ways and does not depend on the order of the rows.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "features/lines/line_appearance.hpp"

namespace vkvo::features {
namespace {

// A vertical edge at x = 40 with a pattern along it (rows), on a 100 x 80 image.
cv::Mat edge_image(double gain, double offset) {
  cv::Mat image(80, 100, CV_8UC1);
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      const double value = (x < 40 ? 60.0 : 140.0) + 30.0 * ((y / 5) % 2) * (x < 40 ? 1.0 : -1.0);
      image.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(gain * value + offset);
    }
  return image;
}

StripSamples vertical_strip(float x_a, float x_b) {
  StripSamples strip;
  for (int y = 10; y < 70; ++y) {
    strip.along_a.emplace_back(x_a, static_cast<float>(y));
    strip.along_b.emplace_back(x_b, static_cast<float>(y));
  }
  return strip;
}

TEST(LineAppearance, StripZnccIgnoresGainAndOffset) {
  const cv::Mat bright = edge_image(1.0, 0.0), dim = edge_image(0.2, 5.0);
  EXPECT_NEAR(strip_zncc(bright, dim, vertical_strip(39.5f, 39.5f), 3), 1.0f, 0.02f);
  // The same edge with its polarity reversed (sampled from the other side) anti-correlates.
  StripSamples flipped = vertical_strip(39.5f, 39.5f);
  flipped.across_b = -flipped.across_b;
  EXPECT_LT(strip_zncc(bright, dim, flipped, 3), -0.9f);
}

TEST(LineAppearance, StripZnccFollowsTheSampledPoints) {
  const cv::Mat image = edge_image(1.0, 0.0);
  // Sampled 20 px off the edge in the second image: a flat-sided strip with only the row pattern left.
  EXPECT_LT(strip_zncc(image, image, vertical_strip(39.5f, 19.5f), 3), 0.5f);
  // A flat image, and samples outside the image: no correlation.
  const cv::Mat flat(80, 100, CV_8UC1, cv::Scalar(90));
  EXPECT_EQ(strip_zncc(image, flat, vertical_strip(39.5f, 39.5f), 3), kNoCorrelation);
  EXPECT_EQ(strip_zncc(image, image, vertical_strip(39.5f, 500.0f), 3), kNoCorrelation);
}

TEST(LineAppearance, ClearWinnersAreOneToOneAndHonourTheMargin) {
  // Rows 0-3 against columns 0-2.
  const std::vector<float> score = {
      0.95f, 0.30f, kNoCorrelation,  // row 0: column 0 clearly
      0.90f, 0.20f, 0.10f,           // row 1: also column 0, within the margin of row 0
      0.10f, 0.85f, 0.80f,           // row 2: column 1 by 0.05 only
      0.20f, 0.10f, 0.65f,           // row 3: column 2, below min_score 0.75
  };
  std::vector<int> partner(4, -1);
  assign_clear_winners(score, 4, 3, 0.75f, 0.1f, partner);
  // Column 0 is the best of rows 0 and 1, 0.95 against 0.90: not a clear winner for either.
  EXPECT_EQ(partner, (std::vector<int>{-1, -1, -1, -1}));

  // Row 1 gone: row 0 takes column 0; row 2 still lacks its margin, and row 3's column 2 is row 2's runner-up
  // at 0.80, so from the column's side 0.65 is no clear winner either.
  std::vector<float> without_row1 = score;
  for (int c = 0; c < 3; ++c) without_row1[3 + c] = kNoCorrelation;
  partner.assign(4, -1);
  assign_clear_winners(without_row1, 4, 3, 0.6f, 0.1f, partner);
  EXPECT_EQ(partner, (std::vector<int>{0, -1, -1, -1}));

  // Row 2's runner-up lowered to 0.30: row 2 takes column 1 and row 3 column 2.
  std::vector<float> clear = without_row1;
  clear[2 * 3 + 2] = 0.30f;
  partner.assign(4, -1);
  assign_clear_winners(clear, 4, 3, 0.6f, 0.1f, partner);
  EXPECT_EQ(partner, (std::vector<int>{0, -1, 1, 2}));

  // A row already paired keeps its partner; its column carries no score (the caller's part), so row 2, whose
  // best it was, now takes column 2 (0.80 against 0.65) and row 3 loses it.
  std::vector<float> column1_taken = without_row1;
  for (int r = 0; r < 4; ++r) column1_taken[r * 3 + 1] = kNoCorrelation;
  partner = {-1, 1, -1, -1};
  assign_clear_winners(column1_taken, 4, 3, 0.6f, 0.1f, partner);
  EXPECT_EQ(partner, (std::vector<int>{0, 1, 2, -1}));
}

}  // namespace
}  // namespace vkvo::features
