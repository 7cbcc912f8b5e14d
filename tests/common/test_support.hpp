#pragma once
// Helpers shared by all test executables.
#include <exception>
#include <filesystem>
#include <optional>
#include <string>

#include <gtest/gtest.h>

namespace vkvo::test {

// The shared data folder: $VKVO_DATA, else ../shared next to the checkout. nullopt when neither exists.
std::optional<std::filesystem::path> shared_data_dir();

// The project's source tree (for config/ files and the like).
std::filesystem::path source_dir();

// A fresh, empty directory unique to the calling test, under the build tree (tests/scratch/).
std::filesystem::path temp_dir(const std::string& tag);

// A folder under the build tree that outlives the tests (never emptied by them): the data tests' SuperPoint
// features, shared between their processes through system::FeatureCache.
std::filesystem::path feature_cache_dir();

// Writes `text` to `file` byte for byte, creating the parent directories.
void write_text(const std::filesystem::path& file, const std::string& text);
// The whole content of `file` (empty when it cannot be read).
std::string read_text(const std::filesystem::path& file);

// Sets (or, for nullptr, unsets) an environment variable for the scope and restores it afterwards.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value);
  ~ScopedEnv();
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  std::string name_;
  std::optional<std::string> old_;
};

// The what() of the exception `fn` throws, or "<no exception>".
template <typename Fn>
std::string error_of(Fn&& fn) {
  try {
    fn();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "<no exception>";
}

}  // namespace vkvo::test

// Skips the current test with a clear message when the shared data (or a file in it) is not there.
// Usage: VKVO_REQUIRE_DATA(dir, "golden/superpoint");  ->  dir is the full path afterwards.
#define VKVO_REQUIRE_DATA(var, relative)                                                 \
  const auto var##_root = ::vkvo::test::shared_data_dir();                               \
  if (!var##_root)                                                                       \
    GTEST_SKIP() << "shared data not found: set VKVO_DATA or put ../shared next to the " \
                    "checkout (needed: "                                                 \
                 << (relative) << ")";                                                   \
  const std::filesystem::path var = *var##_root / (relative);                            \
  if (!std::filesystem::exists(var)) GTEST_SKIP() << "shared data lacks " << var.string()
