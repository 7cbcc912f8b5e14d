#pragma once
// A PointFrontend that runs another one's detect() once per distinct image. The photometric-stress tests run a
// clip clean and then with a few stretches of frames changed; the unchanged frames are byte-identical images, and
// SuperPoint on lavapipe costs seconds each, so running them twice would double a test's time for nothing (the
// network is deterministic: same image, same features). Every image that differs, by a single byte, is detected
// afresh. Images are compared whole, not by hash alone, so a collision cannot hand back another image's features.
//
// One FeatureMemo may be shared by several MemoisedFrontends on different threads (the feature stage's and the
// keyframe stage's frontends): lookups and inserts are locked, detection itself is not.
#include <cstddef>
#include <mutex>
#include <unordered_map>
#include <vector>

#include <opencv2/core.hpp>

#include "system/point_frontend.hpp"

namespace vkvo::test {

class FeatureMemo {
 public:
  // The features stored for an image equal to `gray`, or null.
  const features::PointFeatures* find(const cv::Mat& gray) const;
  void insert(const cv::Mat& gray, features::PointFeatures features);

  std::size_t hits() const;
  std::size_t size() const;

 private:
  struct Entry {
    cv::Mat image;  // an owned copy
    features::PointFeatures features;
  };
  static std::size_t content_hash(const cv::Mat& gray);
  const Entry* find_locked(const cv::Mat& gray, std::size_t hash) const;

  mutable std::mutex mutex_;
  // Entries are never erased, and std::unordered_multimap keeps references to its elements valid across inserts.
  std::unordered_multimap<std::size_t, Entry> entries_;
  mutable std::size_t hits_ = 0;
};

class MemoisedFrontend : public system::PointFrontend {
 public:
  MemoisedFrontend(system::PointFrontend& inner, FeatureMemo& memo) : inner_(&inner), memo_(&memo) {}

  features::PointFeatures detect(const cv::Mat& gray) override;
  features::PointMatches match(const features::PointFeatures& a, const features::PointFeatures& b) override {
    return inner_->match(a, b);
  }

 private:
  system::PointFrontend* inner_;
  FeatureMemo* memo_;
};

}  // namespace vkvo::test
