#pragma once
// Output files written whole or not at all: the content goes to `<file>.tmp`, is flushed and closed with every
// step checked, and only then renamed over `file`, so a failed write (a full disk) never replaces a good file.
#include <filesystem>
#include <functional>
#include <ostream>
#include <stdexcept>
#include <string>

namespace vkvo::io {

// An output that could not be written; the CLI maps it to its own exit code (docs/bad-input.md).
class OutputWriteError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Creates `folder` and its parents; throws OutputWriteError naming the folder and the reason (an output failure,
// exit code 3, not bad input).
void create_output_folder(const std::filesystem::path& folder);

// Creates the parent folders, writes through `fill` and renames; throws OutputWriteError naming the file and the
// step that failed (the temporary file is removed).
void write_file_atomically(const std::filesystem::path& file, const std::function<void(std::ostream&)>& fill,
                           std::ios::openmode mode = std::ios::out);

}  // namespace vkvo::io
