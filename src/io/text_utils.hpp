#pragma once
// Line-oriented parsing helpers for the plain-text dataset and trajectory files.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace vkvo::io {

// Calls `fn(line, line_number)` for every line that is neither empty nor a '#' comment, with CR and surrounding
// blanks removed. Throws std::runtime_error when the file cannot be opened.
void for_each_data_line(const std::filesystem::path& file,
                        const std::function<void(const std::string& line, std::size_t line_number)>& fn);

// Splits on `separator`, trimming blanks around every field.
std::vector<std::string> split_fields(const std::string& line, char separator);
// Splits on runs of blanks, and also on commas when the line has them.
std::vector<std::string> split_numbers(const std::string& line);

// Parses a number; throws std::runtime_error naming file:line when the text is not one.
double parse_double(const std::string& text, const std::filesystem::path& file, std::size_t line_number);
// Parses an integer nanosecond timestamp; accepts a trailing fraction ("1403636580863555584.0000000000").
std::int64_t parse_timestamp_ns(const std::string& text, const std::filesystem::path& file, std::size_t line_number);

// Checks a file's timestamps line by line: none negative, each later than the one before (a duplicate or a step
// back is an error naming both lines). `what` names the column in messages ("timestamp").
class TimestampSequence {
 public:
  TimestampSequence(std::filesystem::path file, std::string what = "timestamp");
  // long double holds int64 nanosecond timestamps exactly on x86-64 (64-bit mantissa).
  void add(long double timestamp, std::size_t line_number);

 private:
  std::filesystem::path file_;
  std::string what_;
  long double previous_ = 0;
  std::size_t previous_line_ = 0;  // 0: no timestamp yet
};

// A path read from a dataset index (e.g. data.csv's filename) that must stay inside the dataset folder: relative,
// without '..' components. Throws naming file:line otherwise.
void require_path_inside(const std::filesystem::path& entry, const std::filesystem::path& file,
                         std::size_t line_number);

}  // namespace vkvo::io
