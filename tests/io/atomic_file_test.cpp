// io::write_file_atomically: a failed write never replaces a good file and is reported as OutputWriteError, which
// the CLI turns into exit code 3 (issue 36).
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "io/atomic_file.hpp"

using namespace vkvo;

namespace {
std::string read_all(const std::filesystem::path& file) {
  std::ifstream in(file);
  return std::string(std::istreambuf_iterator<char>(in), {});
}
}  // namespace

TEST(AtomicFile, WritesThroughATemporaryAndRenames) {
  const auto file = test::temp_dir("atomic_ok") / "sub" / "map.ply";
  io::write_file_atomically(file, [](std::ostream& out) { out << "ply\n"; });
  EXPECT_EQ(read_all(file), "ply\n");
  EXPECT_FALSE(std::filesystem::exists(file.string() + ".tmp"));
}

TEST(AtomicFile, FailedWriteKeepsThePreviousFile) {
  const auto file = test::temp_dir("atomic_fail") / "summary.json";
  io::write_file_atomically(file, [](std::ostream& out) { out << "good\n"; });
  try {
    io::write_file_atomically(file, [](std::ostream& out) {
      out << "partial";
      out.setstate(std::ios::badbit);  // what a full disk does to the stream
    });
    FAIL() << "no exception";
  } catch (const io::OutputWriteError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_NE(message.find("writing failed"), std::string::npos) << message;
  }
  EXPECT_EQ(read_all(file), "good\n");
  EXPECT_FALSE(std::filesystem::exists(file.string() + ".tmp"));
}

TEST(AtomicFile, UnwritableFolderIsAnOutputError) {
  const auto dir = test::temp_dir("atomic_folder");
  test::write_text(dir / "plain_file", "x");
  // A path under a regular file cannot be created, whoever runs the test (root ignores permissions).
  EXPECT_THROW(io::write_file_atomically(dir / "plain_file" / "out.json", [](std::ostream& out) { out << "{}"; }),
               io::OutputWriteError);
}
