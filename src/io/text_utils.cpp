#include "io/text_utils.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

namespace vkvo::io {

namespace {
std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return {};
  const auto last = text.find_last_not_of(" \t\r\n");
  return text.substr(first, last - first + 1);
}
}  // namespace

void for_each_data_line(const std::filesystem::path& file,
                        const std::function<void(const std::string&, std::size_t)>& fn) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open file", file.string()));
  std::string raw;
  std::size_t line_number = 0;
  while (std::getline(in, raw)) {
    ++line_number;
    const std::string line = trim(raw);
    if (line.empty() || line.front() == '#') continue;
    fn(line, line_number);
  }
}

std::vector<std::string> split_fields(const std::string& line, char separator) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const auto end = line.find(separator, start);
    fields.push_back(trim(line.substr(start, end == std::string::npos ? std::string::npos : end - start)));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return fields;
}

std::vector<std::string> split_numbers(const std::string& line) {
  std::vector<std::string> fields;
  std::string current;
  for (char c : line) {
    if (c == ' ' || c == '\t' || c == ',') {
      if (!current.empty()) fields.push_back(std::move(current));
      current.clear();
    } else {
      current += c;
    }
  }
  if (!current.empty()) fields.push_back(std::move(current));
  return fields;
}

double parse_double(const std::string& text, const std::filesystem::path& file, std::size_t line_number) {
  // std::from_chars for double is available in libstdc++ 11+.
  double value = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end || !std::isfinite(value))
    throw std::runtime_error(fmt::format("{}:{}: '{}' is not a number", file.string(), line_number, text));
  return value;
}

std::int64_t parse_timestamp_ns(const std::string& text, const std::filesystem::path& file, std::size_t line_number) {
  const auto dot = text.find('.');
  const std::string integral = text.substr(0, dot);
  std::int64_t value = 0;
  const char* end = integral.data() + integral.size();
  const auto [ptr, ec] = std::from_chars(integral.data(), end, value);
  bool ok = ec == std::errc() && ptr == end && !integral.empty();
  if (ok && dot != std::string::npos) {  // a fraction of a nanosecond: must be digits, rounded away
    const std::string fraction = text.substr(dot + 1);
    ok = fraction.find_first_not_of("0123456789") == std::string::npos;
    if (ok && !fraction.empty() && fraction[0] >= '5') {
      ok = value < std::numeric_limits<std::int64_t>::max();
      if (ok) ++value;
    }
  }
  if (!ok)
    throw std::runtime_error(
        fmt::format("{}:{}: '{}' is not a nanosecond timestamp", file.string(), line_number, text));
  return value;
}

TimestampSequence::TimestampSequence(std::filesystem::path file, std::string what)
    : file_(std::move(file)), what_(std::move(what)) {}

void TimestampSequence::add(long double timestamp, std::size_t line_number) {
  // Nanosecond integers print whole, seconds as they were read.
  const auto text = [](long double t) {
    return t == std::floor(t) && std::fabs(t) < 1e19L ? fmt::format("{:.0f}", t)
                                                      : fmt::format("{}", static_cast<double>(t));
  };
  if (!std::isfinite(timestamp) || timestamp < 0)
    throw std::runtime_error(
        fmt::format("{}:{}: {} {} is negative or not finite", file_.string(), line_number, what_, text(timestamp)));
  if (previous_line_ != 0 && timestamp == previous_)
    throw std::runtime_error(fmt::format("{}:{}: duplicate {} {} (also on line {})", file_.string(), line_number, what_,
                                         text(timestamp), previous_line_));
  if (previous_line_ != 0 && timestamp < previous_)
    throw std::runtime_error(fmt::format("{}:{}: {} {} is earlier than {} on line {} (not increasing)", file_.string(),
                                         line_number, what_, text(timestamp), text(previous_), previous_line_));
  previous_ = timestamp;
  previous_line_ = line_number;
}

void require_path_inside(const std::filesystem::path& entry, const std::filesystem::path& file,
                         std::size_t line_number) {
  bool climbs = entry.is_absolute() || entry.has_root_name() || entry.has_root_directory() || entry.empty();
  for (const auto& part : entry) climbs = climbs || part == "..";
  if (climbs)
    throw std::runtime_error(fmt::format("{}:{}: path '{}' is empty, absolute or leaves the dataset folder with '..'",
                                         file.string(), line_number, entry.string()));
}

}  // namespace vkvo::io
