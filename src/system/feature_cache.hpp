#pragma once
// Features of images already seen. The point network is deterministic (same image, weights, parameters and device:
// same features), so a run that meets an image again (the robustness benchmark's frames that an event leaves
// unchanged, a second run of a sequence, the data tests' clean and stressed runs) takes its features from here.
// Entries live in memory and, when a folder is given, on disk under a subfolder per detector identity (a string
// naming the weights, parameters and device), so that separate processes share them.
//
// Images are compared whole, not by hash alone (the disk entries store the image), so a hash collision cannot hand
// back another image's features. Lookups and inserts are locked; detection itself is not, so one cache may serve
// the feature stage's and the keyframe stage's frontends on their threads.
#include <cstddef>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>

#include <opencv2/core.hpp>

#include "features/point_features.hpp"
#include "system/point_frontend.hpp"

namespace vkvo::system {

class FeatureCache {
 public:
  // In memory only.
  FeatureCache() = default;
  // Also on disk, in `directory`/<hash of identity>/ (created on first insert). Entries written by another identity
  // are never read.
  FeatureCache(const std::filesystem::path& directory, const std::string& identity);

  // The features stored for an image equal to `gray`, or nullopt.
  std::optional<features::PointFeatures> find(const cv::Mat& gray) const;
  void insert(const cv::Mat& gray, const features::PointFeatures& features);

  std::size_t hits() const;
  std::size_t size() const;  // entries in memory
  const std::optional<std::filesystem::path>& folder() const { return folder_; }

 private:
  struct Entry {
    cv::Mat image;  // an owned, continuous copy
    features::PointFeatures features;
  };
  const Entry* find_in_memory(const cv::Mat& gray, std::size_t hash) const;
  std::optional<Entry> read_entry(const cv::Mat& gray, std::size_t hash) const;
  void write_entry(const Entry& entry, std::size_t hash) const;

  std::optional<std::filesystem::path> folder_;
  mutable std::mutex mutex_;
  // Never erased; std::unordered_multimap keeps references to its elements valid across inserts.
  mutable std::unordered_multimap<std::size_t, Entry> entries_;
  mutable std::size_t hits_ = 0;
};

// A hash of an image's size, type and pixels.
std::size_t image_content_hash(const cv::Mat& image);

// A PointFrontend that runs another one's detect() once per distinct image (see FeatureCache).
class CachedFrontend final : public PointFrontend {
 public:
  CachedFrontend(PointFrontend& inner, FeatureCache& cache) : inner_(&inner), cache_(&cache) {}

  features::PointFeatures detect(const cv::Mat& gray) override;
  features::PointMatches match(const features::PointFeatures& a, const features::PointFeatures& b) override {
    return inner_->match(a, b);
  }

 private:
  PointFrontend* inner_;
  FeatureCache* cache_;
};

}  // namespace vkvo::system
