#include "system/feature_cache.hpp"

#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string_view>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

namespace vkvo::system {
namespace {

namespace fs = std::filesystem;

constexpr std::array<char, 8> kMagic = {'V', 'K', 'V', 'O', 'F', 'C', '1', '\0'};

bool same_image(const cv::Mat& a, const cv::Mat& b) {
  if (a.rows != b.rows || a.cols != b.cols || a.type() != b.type()) return false;
  const std::size_t row_bytes = a.cols * a.elemSize();
  for (int y = 0; y < a.rows; ++y)
    if (std::memcmp(a.ptr(y), b.ptr(y), row_bytes) != 0) return false;
  return true;
}

template <typename T>
void put(std::ofstream& out, const T& value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof(T));
}
template <typename T>
bool get(std::ifstream& in, T& value) {
  return static_cast<bool>(in.read(reinterpret_cast<char*>(&value), sizeof(T)));
}
bool get_bytes(std::ifstream& in, void* data, std::size_t bytes) {
  return static_cast<bool>(in.read(static_cast<char*>(data), static_cast<std::streamsize>(bytes)));
}

fs::path entry_path(const fs::path& folder, std::size_t hash) { return folder / fmt::format("{:016x}.feat", hash); }

}  // namespace

std::size_t image_content_hash(const cv::Mat& gray) {
  std::size_t hash =
      std::hash<int>{}(gray.rows) ^ (std::hash<int>{}(gray.cols) << 1) ^ (std::hash<int>{}(gray.type()) << 2);
  const std::size_t row_bytes = gray.cols * gray.elemSize();
  for (int y = 0; y < gray.rows; ++y)
    hash = hash * 1099511628211ull ^
           std::hash<std::string_view>{}(std::string_view(reinterpret_cast<const char*>(gray.ptr(y)), row_bytes));
  return hash;
}

FeatureCache::FeatureCache(const fs::path& directory, const std::string& identity)
    : folder_(directory / fmt::format("{:016x}", std::hash<std::string>{}(identity))) {
  std::error_code error;
  fs::create_directories(*folder_, error);
  if (error) {
    spdlog::warn("feature cache: cannot create {} ({}); caching in memory only", folder_->string(), error.message());
    folder_.reset();
    return;
  }
  std::ofstream(*folder_ / "identity.txt") << identity << '\n';
}

const FeatureCache::Entry* FeatureCache::find_in_memory(const cv::Mat& gray, std::size_t hash) const {
  const auto [first, last] = entries_.equal_range(hash);
  for (auto it = first; it != last; ++it)
    if (same_image(it->second.image, gray)) return &it->second;
  return nullptr;
}

std::optional<FeatureCache::Entry> FeatureCache::read_entry(const cv::Mat& gray, std::size_t hash) const {
  if (!folder_) return std::nullopt;
  std::ifstream in(entry_path(*folder_, hash), std::ios::binary);
  if (!in) return std::nullopt;
  std::array<char, 8> magic{};
  std::int32_t rows = 0, cols = 0, type = 0;
  if (!get(in, magic) || magic != kMagic || !get(in, rows) || !get(in, cols) || !get(in, type)) return std::nullopt;
  if (rows != gray.rows || cols != gray.cols || type != gray.type()) return std::nullopt;
  Entry entry{cv::Mat(rows, cols, type), {}};
  if (!get_bytes(in, entry.image.data, entry.image.total() * entry.image.elemSize()) || !same_image(entry.image, gray))
    return std::nullopt;
  std::int32_t width = 0, height = 0, count = 0, dim = 0;
  if (!get(in, width) || !get(in, height) || !get(in, count) || !get(in, dim) || count < 0 || dim < 0)
    return std::nullopt;
  features::PointFeatures& f = entry.features;
  f.image_width = width;
  f.image_height = height;
  f.keypoints.resize(static_cast<std::size_t>(count));
  f.scores.resize(static_cast<std::size_t>(count));
  f.descriptors.resize(count, dim);
  if (!get_bytes(in, f.keypoints.data(), f.keypoints.size() * sizeof(Eigen::Vector2f)) ||
      !get_bytes(in, f.scores.data(), f.scores.size() * sizeof(float)) ||
      !get_bytes(in, f.descriptors.data(), static_cast<std::size_t>(f.descriptors.size()) * sizeof(float)))
    return std::nullopt;
  return entry;
}

void FeatureCache::write_entry(const Entry& entry, std::size_t hash) const {
  if (!folder_) return;
  const fs::path path = entry_path(*folder_, hash);
  if (fs::exists(path)) return;  // another image with this hash, or another process was first: keep it
  // Written under a temporary name and renamed, so a reader never sees half an entry.
  const fs::path partial = path.string() + fmt::format(".{:x}.partial", std::hash<const void*>{}(&entry));
  {
    std::ofstream out(partial, std::ios::binary);
    const features::PointFeatures& f = entry.features;
    put(out, kMagic);
    put(out, static_cast<std::int32_t>(entry.image.rows));
    put(out, static_cast<std::int32_t>(entry.image.cols));
    put(out, static_cast<std::int32_t>(entry.image.type()));
    out.write(reinterpret_cast<const char*>(entry.image.data),
              static_cast<std::streamsize>(entry.image.total() * entry.image.elemSize()));
    put(out, static_cast<std::int32_t>(f.image_width));
    put(out, static_cast<std::int32_t>(f.image_height));
    put(out, static_cast<std::int32_t>(f.size()));
    put(out, static_cast<std::int32_t>(f.descriptors.cols()));
    out.write(reinterpret_cast<const char*>(f.keypoints.data()),
              static_cast<std::streamsize>(f.keypoints.size() * sizeof(Eigen::Vector2f)));
    out.write(reinterpret_cast<const char*>(f.scores.data()),
              static_cast<std::streamsize>(f.scores.size() * sizeof(float)));
    out.write(reinterpret_cast<const char*>(f.descriptors.data()),
              static_cast<std::streamsize>(f.descriptors.size() * sizeof(float)));
    if (!out.flush()) {
      std::error_code ignored;
      fs::remove(partial, ignored);
      return;
    }
  }
  std::error_code error;
  fs::rename(partial, path, error);
  if (error) fs::remove(partial, error);
}

std::optional<features::PointFeatures> FeatureCache::find(const cv::Mat& gray) const {
  const std::size_t hash = image_content_hash(gray);
  const std::lock_guard lock(mutex_);
  const Entry* entry = find_in_memory(gray, hash);
  if (entry == nullptr) {
    if (auto stored = read_entry(gray, hash)) entry = &entries_.emplace(hash, std::move(*stored))->second;
  }
  if (entry == nullptr) return std::nullopt;
  ++hits_;
  return entry->features;
}

void FeatureCache::insert(const cv::Mat& gray, const features::PointFeatures& features) {
  const std::size_t hash = image_content_hash(gray);
  const std::lock_guard lock(mutex_);
  // Two threads may have detected the same image at once; the first insert wins (the features are the same).
  if (find_in_memory(gray, hash) != nullptr) return;
  const Entry& entry = entries_.emplace(hash, Entry{gray.clone(), features})->second;
  write_entry(entry, hash);
}

std::size_t FeatureCache::hits() const {
  const std::lock_guard lock(mutex_);
  return hits_;
}

std::size_t FeatureCache::size() const {
  const std::lock_guard lock(mutex_);
  return entries_.size();
}

features::PointFeatures CachedFrontend::detect(const cv::Mat& gray) {
  if (auto stored = cache_->find(gray)) return std::move(*stored);
  auto features = inner_->detect(gray);
  cache_->insert(gray, features);
  return features;
}

}  // namespace vkvo::system
