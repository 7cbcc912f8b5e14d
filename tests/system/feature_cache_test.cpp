// FeatureCache / CachedFrontend: the robustness benchmark and the data tests rely on it to run SuperPoint once per
// distinct image, in one process and (on disk) across processes.
#include "system/feature_cache.hpp"

#include <filesystem>

#include <gtest/gtest.h>

#include "common/test_support.hpp"

namespace vkvo::system {
namespace {

// Counts its detections and tags each result with the count, so a test can tell a stored result from a fresh one.
class CountingFrontend : public PointFrontend {
 public:
  features::PointFeatures detect(const cv::Mat& gray) override {
    ++detections;
    features::PointFeatures features;
    features.image_width = gray.cols;
    features.image_height = gray.rows;
    features.keypoints.emplace_back(static_cast<float>(detections), 0.0f);
    features.scores.push_back(1.0f);
    return features;
  }
  features::PointMatches match(const features::PointFeatures& a, const features::PointFeatures&) override {
    ++matches;
    return {std::vector<int>(a.size(), 0), std::vector<float>(a.size(), 1.0f)};
  }
  int detections = 0;
  int matches = 0;
};

cv::Mat gradient(int rows, int cols) {
  cv::Mat image(rows, cols, CV_8UC1);
  for (int y = 0; y < rows; ++y)
    for (int x = 0; x < cols; ++x) image.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>((3 * x + 7 * y) % 256);
  return image;
}

TEST(FeatureCache, DetectsEachDistinctImageOnce) {
  CountingFrontend network;
  FeatureCache memo;
  CachedFrontend frontend(network, memo);
  const cv::Mat image = gradient(48, 64);

  const auto first = frontend.detect(image);
  const auto again = frontend.detect(image.clone());  // equal content, other buffer
  EXPECT_EQ(network.detections, 1);
  EXPECT_EQ(again.keypoints.at(0).x(), first.keypoints.at(0).x());
  EXPECT_EQ(memo.hits(), 1u);

  cv::Mat changed = image.clone();
  changed.at<std::uint8_t>(47, 63) ^= 1;  // one bit of the last pixel
  const auto fresh = frontend.detect(changed);
  EXPECT_EQ(network.detections, 2);
  EXPECT_EQ(fresh.keypoints.at(0).x(), 2.0f);

  // Same bytes, other shape: a different image.
  frontend.detect(image.reshape(1, 64));
  EXPECT_EQ(network.detections, 3);
  EXPECT_EQ(memo.size(), 3u);
}

TEST(FeatureCache, ComparesTheRegionOfANonContinuousView) {
  CountingFrontend network;
  FeatureCache memo;
  CachedFrontend frontend(network, memo);
  const cv::Mat big = gradient(64, 96);
  const cv::Mat view = big(cv::Rect(8, 4, 40, 30));  // rows are not contiguous
  ASSERT_FALSE(view.isContinuous());

  frontend.detect(view);
  frontend.detect(view.clone());
  EXPECT_EQ(network.detections, 1);
  cv::Mat shifted = big(cv::Rect(9, 4, 40, 30)).clone();
  frontend.detect(shifted);
  EXPECT_EQ(network.detections, 2);
}

TEST(FeatureCache, SharedBetweenFrontendsAndMatchingPassesThrough) {
  CountingFrontend left_network, right_network;
  FeatureCache memo;
  CachedFrontend left(left_network, memo), right(right_network, memo);
  const cv::Mat image = gradient(20, 30);
  const auto a = left.detect(image);
  const auto b = right.detect(image);
  EXPECT_EQ(left_network.detections + right_network.detections, 1);
  EXPECT_EQ(right.match(a, b).count(), 1u);
  EXPECT_EQ(right_network.matches, 1);
}

// Descriptors and scores survive the round trip through the disk bit for bit; another identity never reads them.
TEST(FeatureCache, DiskEntriesAreSharedBetweenCachesOfOneIdentity) {
  const auto dir = test::temp_dir("feature_cache");
  const cv::Mat image = gradient(30, 40);
  features::PointFeatures stored;
  stored.image_width = 40;
  stored.image_height = 30;
  stored.keypoints = {{1.5f, 2.25f}, {7.0f, 9.5f}};
  stored.scores = {0.75f, 0.125f};
  stored.descriptors.resize(2, 3);
  stored.descriptors << 0.6f, 0.8f, 0.0f, 0.0f, -1.0f, 1e-7f;
  {
    FeatureCache writer(dir, "superpoint A");
    writer.insert(image, stored);
  }
  FeatureCache reader(dir, "superpoint A");
  const auto found = reader.find(image.clone());
  ASSERT_TRUE(found.has_value());
  EXPECT_EQ(found->image_width, 40);
  EXPECT_EQ(found->image_height, 30);
  ASSERT_EQ(found->size(), 2u);
  EXPECT_EQ(found->keypoints[1], stored.keypoints[1]);
  EXPECT_EQ(found->scores, stored.scores);
  EXPECT_EQ(found->descriptors, stored.descriptors);
  EXPECT_EQ(reader.hits(), 1u);

  cv::Mat other = image.clone();
  other.at<std::uint8_t>(0, 0) ^= 1;
  EXPECT_FALSE(reader.find(other).has_value());
  EXPECT_FALSE(FeatureCache(dir, "superpoint B").find(image).has_value());
}

}  // namespace
}  // namespace vkvo::system
