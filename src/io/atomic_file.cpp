#include "io/atomic_file.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

#include <fmt/format.h>

namespace vkvo::io {

namespace fs = std::filesystem;

void create_output_folder(const fs::path& folder) {
  if (folder.empty()) return;
  std::error_code error;
  fs::create_directories(folder, error);
  if (error)
    throw OutputWriteError(fmt::format("output folder {}: cannot create it ({})", folder.string(), error.message()));
}

void write_file_atomically(const fs::path& file, const std::function<void(std::ostream&)>& fill,
                           std::ios::openmode mode) {
  const fs::path temporary = fs::path(file.string() + ".tmp");
  auto fail = [&](const std::string& step) {
    const std::string reason = errno ? std::strerror(errno) : "stream error";
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw OutputWriteError(
        fmt::format("{}: {} failed ({}); the previous file, if any, is kept", file.string(), step, reason));
  };
  create_output_folder(file.parent_path());
  std::error_code error;
  errno = 0;
  std::ofstream out(temporary, mode | std::ios::out | std::ios::trunc);
  if (!out) fail("opening " + temporary.string());
  fill(out);
  if (!out) fail("writing");
  out.flush();
  if (!out) fail("flushing");
  out.close();
  if (out.fail()) fail("closing");
  fs::rename(temporary, file, error);
  if (error) {
    errno = error.value();
    fail("renaming " + temporary.string());
  }
}

}  // namespace vkvo::io
