#include "common/test_support.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace vkvo::test {

std::optional<std::filesystem::path> shared_data_dir() {
  if (const char* env = std::getenv("VKVO_DATA"); env && *env) {
    if (std::filesystem::is_directory(env)) return std::filesystem::path(env);
    return std::nullopt;
  }
  const auto sibling = source_dir().parent_path() / "shared";
  if (std::filesystem::is_directory(sibling)) return sibling;
  return std::nullopt;
}

std::filesystem::path source_dir() { return VKVO_SOURCE_DIR; }

ScopedEnv::ScopedEnv(const char* name, const char* value) : name_(name) {
  if (const char* old = std::getenv(name)) old_ = old;
  if (value)
    ::setenv(name, value, 1);
  else
    ::unsetenv(name);
}

ScopedEnv::~ScopedEnv() {
  if (old_)
    ::setenv(name_.c_str(), old_->c_str(), 1);
  else
    ::unsetenv(name_.c_str());
}

std::filesystem::path temp_dir(const std::string& tag) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = tag;
  if (info) name += std::string("_") + info->test_suite_name() + "_" + info->name();
  for (char& c : name)
    if (c == '/') c = '_';
  const auto dir = std::filesystem::path(VKVO_TEST_SCRATCH_DIR) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::filesystem::path feature_cache_dir() {
  const auto dir = std::filesystem::path(VKVO_TEST_SCRATCH_DIR) / "feature_cache";
  std::filesystem::create_directories(dir);
  return dir;
}

void write_text(const std::filesystem::path& file, const std::string& text) {
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary) << text;
}

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace vkvo::test

#include "common/gpu.hpp"

#include <memory>

namespace vkvo::test {

rt::Context& gpu() {
  static std::unique_ptr<rt::Context> context = std::make_unique<rt::Context>();
  return *context;
}

}  // namespace vkvo::test
