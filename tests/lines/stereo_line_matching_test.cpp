// Left-right line matching by appearance on rendered rectified pairs: bars whose left and right images differ by
// a known disparity. Vertical edges find their shifted images (also at a tenth of the light with sensor noise);
// edges without row extent, candidates outside the disparity range and ambiguous twins stay unpaired; partners
// from point matches are kept.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "features/lines/stereo_line_matching.hpp"

namespace vkvo::features {
namespace {

constexpr int kWidth = 320, kHeight = 240;

// A bright bar on the darker background, its columns [x, x + width) in the left image, rows [top, bottom), seen
// `disparity` pixels further left in the right image.
struct Bar {
  int x, width, top, bottom, disparity, grey;
};

struct RenderedPair {
  cv::Mat left, right;
  // The bars' vertical edges in the left and the right image: left edge of bar b at 2b, right edge at 2b + 1.
  std::vector<LineSegment> left_edges, right_edges;
};

LineSegment vertical_edge(float x, int top, int bottom) {
  return {{x, static_cast<float>(top)}, {x, static_cast<float>(bottom - 1)}};
}

// A mild horizontal ramp makes the background differ along each row, as real images do.
RenderedPair render(const std::vector<Bar>& bars) {
  RenderedPair pair;
  pair.left.create(kHeight, kWidth, CV_8UC1);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) pair.left.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(40 + x / 16);
  pair.right = pair.left.clone();
  for (const Bar& b : bars) {
    pair.left(cv::Rect(b.x, b.top, b.width, b.bottom - b.top)).setTo(b.grey);
    pair.right(cv::Rect(b.x - b.disparity, b.top, b.width, b.bottom - b.top)).setTo(b.grey);
    // The detected edge lies between the last background and the first bar pixel.
    for (const auto& [x, edges] : {std::pair{b.x, &pair.left_edges}, std::pair{b.x - b.disparity, &pair.right_edges}}) {
      edges->push_back(vertical_edge(static_cast<float>(x) - 0.5f, b.top, b.bottom));
      edges->push_back(vertical_edge(static_cast<float>(x + b.width) - 0.5f, b.top, b.bottom));
    }
  }
  return pair;
}

const DisparityRange kAnyDisparity{1.0, 200.0};
// Different heights, rows and disparities.
const std::vector<Bar> kThreeBars = {
    {40, 30, 20, 120, 12, 200}, {130, 20, 60, 220, 25, 230}, {230, 40, 10, 90, 6, 180}};

std::vector<int> match(const RenderedPair& pair, const std::vector<LineSegment>& left,
                       const std::vector<LineSegment>& right, const DisparityRange& disparity = kAnyDisparity,
                       std::vector<int> partner = {}) {
  if (partner.empty()) partner.assign(left.size(), -1);
  add_stereo_partners_by_appearance({pair.left, left}, {pair.right, right}, disparity, StereoLineMatchParams{},
                                    partner);
  return partner;
}

TEST(StereoLineMatching, EachVerticalEdgeFindsItsShiftedImage) {
  const RenderedPair pair = render(kThreeBars);
  // The right edges in another order, and the bars' horizontal top edges, which span no rows.
  std::vector<LineSegment> left = pair.left_edges, right;
  const std::vector<int> order = {3, 0, 5, 2, 4, 1};
  for (const int k : order) right.push_back(pair.right_edges[static_cast<std::size_t>(k)]);
  left.push_back({{40.0f, 19.5f}, {69.0f, 19.5f}});
  right.push_back({{28.0f, 19.5f}, {57.0f, 19.5f}});

  const std::vector<int> partner = match(pair, left, right);
  ASSERT_EQ(partner.size(), 7u);
  for (int l = 0; l < 6; ++l) {
    ASSERT_GE(partner[l], 0) << "edge " << l;
    EXPECT_EQ(order[static_cast<std::size_t>(partner[l])], l) << "edge " << l;
  }
  EXPECT_EQ(partner[6], -1) << "a horizontal edge has no rows to compare";
}

TEST(StereoLineMatching, HoldsAtATenthOfTheLightWithNoise) {
  RenderedPair pair = render(kThreeBars);
  cv::RNG rng(7);
  for (cv::Mat* image : {&pair.left, &pair.right}) {
    cv::Mat dim, noise(image->size(), CV_32F);
    image->convertTo(dim, CV_32F, 0.1);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 2.0);  // 2 DN of sensor noise against edges of 13-19 DN
    cv::Mat(dim + noise).convertTo(*image, CV_8U);
  }
  const std::vector<int> partner = match(pair, pair.left_edges, pair.right_edges);
  EXPECT_EQ(partner, (std::vector<int>{0, 1, 2, 3, 4, 5}));
}

TEST(StereoLineMatching, TwinEdgesNeedTheDisparityRangeToTellThemApart) {
  // Two equal bars on equal rows: each left edge has the same profile as its twin's image, 50 px away.
  RenderedPair flat = render({{100, 20, 40, 200, 10, 180}, {150, 20, 40, 200, 10, 180}});
  // A flat background, so that nothing but the gates can separate the twins.
  for (cv::Mat* image : {&flat.left, &flat.right}) image->setTo(60, *image != 180);
  EXPECT_EQ(match(flat, flat.left_edges, flat.right_edges), (std::vector<int>(4, -1)));
  // Depth gates that allow 5-40 px of disparity leave one candidate each.
  EXPECT_EQ(match(flat, flat.left_edges, flat.right_edges, {5.0, 40.0}), (std::vector<int>{0, 1, 2, 3}));
  // Disparities outside the range: nothing.
  EXPECT_EQ(match(flat, flat.left_edges, flat.right_edges, {20.0, 40.0}), (std::vector<int>(4, -1)));
}

TEST(StereoLineMatching, KeepsPartnersFromPointMatchesAndTheirRightLines) {
  const RenderedPair pair = render({{40, 30, 20, 120, 12, 200}, {130, 20, 60, 220, 25, 160}});
  // Left edge 0 already paired (say through point matches) with right line 1; the others are free.
  const std::vector<int> partner = match(pair, pair.left_edges, pair.right_edges, kAnyDisparity, {1, -1, -1, -1});
  EXPECT_EQ(partner, (std::vector<int>{1, -1, 2, 3}));
}

TEST(StereoLineMatching, StripCorrelationSeesPolarity) {
  const RenderedPair pair = render({{40, 30, 20, 120, 12, 200}});
  const ImageLines left{pair.left, pair.left_edges}, right{pair.right, pair.right_edges};
  EXPECT_GT(strip_correlation(left, 0, right, 0, 3), 0.99f);  // the same rising edge
  EXPECT_LT(strip_correlation(left, 0, right, 1, 3), -0.9f);  // a falling edge against a rising one
  // Segments without common rows.
  const std::vector<LineSegment> elsewhere = {vertical_edge(20.0f, 150, 200)};
  EXPECT_LT(strip_correlation(left, 0, {pair.right, elsewhere}, 0, 3), -1.0f);
  std::vector<int> wrong_size;
  EXPECT_THROW(add_stereo_partners_by_appearance(left, right, kAnyDisparity, {}, wrong_size), std::invalid_argument);
  std::vector<int> partner(pair.left_edges.size(), -1);
  const cv::Mat colour(kHeight, kWidth, CV_8UC3);
  EXPECT_THROW(add_stereo_partners_by_appearance({colour, pair.left_edges}, right, kAnyDisparity, {}, partner),
               std::invalid_argument);
}

}  // namespace
}  // namespace vkvo::features
