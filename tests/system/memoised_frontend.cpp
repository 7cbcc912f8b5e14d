#include "system/memoised_frontend.hpp"

#include <cstring>
#include <string_view>

namespace vkvo::test {

std::size_t FeatureMemo::content_hash(const cv::Mat& gray) {
  std::size_t hash = std::hash<int>{}(gray.rows) ^ (std::hash<int>{}(gray.cols) << 1) ^
                     (std::hash<int>{}(gray.type()) << 2);
  const std::size_t row_bytes = gray.cols * gray.elemSize();
  for (int y = 0; y < gray.rows; ++y)
    hash = hash * 1099511628211ull ^
           std::hash<std::string_view>{}(std::string_view(reinterpret_cast<const char*>(gray.ptr(y)), row_bytes));
  return hash;
}

const FeatureMemo::Entry* FeatureMemo::find_locked(const cv::Mat& gray, std::size_t hash) const {
  const auto [first, last] = entries_.equal_range(hash);
  const std::size_t row_bytes = gray.cols * gray.elemSize();
  for (auto it = first; it != last; ++it) {
    const cv::Mat& stored = it->second.image;
    if (stored.rows != gray.rows || stored.cols != gray.cols || stored.type() != gray.type()) continue;
    bool equal = true;
    for (int y = 0; y < gray.rows && equal; ++y) equal = std::memcmp(stored.ptr(y), gray.ptr(y), row_bytes) == 0;
    if (equal) return &it->second;
  }
  return nullptr;
}

const features::PointFeatures* FeatureMemo::find(const cv::Mat& gray) const {
  const std::size_t hash = content_hash(gray);
  const std::lock_guard lock(mutex_);
  const Entry* entry = find_locked(gray, hash);
  if (entry != nullptr) ++hits_;
  return entry != nullptr ? &entry->features : nullptr;
}

void FeatureMemo::insert(const cv::Mat& gray, features::PointFeatures features) {
  const std::size_t hash = content_hash(gray);
  const std::lock_guard lock(mutex_);
  // Two threads may have detected the same image at once; the first insert wins (the features are the same).
  if (find_locked(gray, hash) == nullptr) entries_.emplace(hash, Entry{gray.clone(), std::move(features)});
}

std::size_t FeatureMemo::hits() const {
  const std::lock_guard lock(mutex_);
  return hits_;
}

std::size_t FeatureMemo::size() const {
  const std::lock_guard lock(mutex_);
  return entries_.size();
}

features::PointFeatures MemoisedFrontend::detect(const cv::Mat& gray) {
  if (const features::PointFeatures* stored = memo_->find(gray)) return *stored;
  auto features = inner_->detect(gray);
  memo_->insert(gray, features);
  return features;
}

}  // namespace vkvo::test
