// Every reproducer the fuzzers found (fuzz/regressions/<target>/) and every in-tree seed (fuzz/seeds/<target>/) fed
// to its harness in the normal build: each must be accepted or rejected with an exception, never crash (issue 36).
// The sanitizer build (tools/fuzz.sh) replays the same files under ASan and UBSan.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "fuzz/harnesses.hpp"

namespace fs = std::filesystem;

namespace {

std::size_t replay(const fs::path& folder) {
  std::size_t count = 0;
  for (const auto& harness : vkvo::fuzz::harnesses()) {
    const fs::path dir = folder / std::string(harness.name);
    if (!fs::is_directory(dir)) continue;
    for (const auto& entry : fs::directory_iterator(dir)) {
      std::ifstream in(entry.path(), std::ios::binary);
      const std::vector<char> bytes(std::istreambuf_iterator<char>(in), {});
      SCOPED_TRACE(entry.path().string());
      EXPECT_NO_THROW(harness.run(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
      ++count;
    }
  }
  return count;
}

}  // namespace

TEST(FuzzRegressions, ReproducersAreRejectedCleanly) {
  const fs::path folder = vkvo::test::source_dir() / "fuzz" / "regressions";
  if (!fs::is_directory(folder) || fs::is_empty(folder)) GTEST_SKIP() << "no reproducers kept yet";
  EXPECT_GT(replay(folder), 0u);
}

TEST(FuzzRegressions, TextSeedsParse) { EXPECT_GT(replay(vkvo::test::source_dir() / "fuzz" / "seeds"), 5u); }

TEST(FuzzRegressions, EveryTargetHasAHarness) {
  std::ifstream in(vkvo::test::source_dir() / "fuzz" / "targets.txt");
  std::string name;
  std::size_t count = 0;
  while (std::getline(in, name)) {
    EXPECT_NE(vkvo::fuzz::find_harness(name), nullptr) << name;
    ++count;
  }
  EXPECT_EQ(count, vkvo::fuzz::harnesses().size());
}
