#include "io/frame_status.hpp"

#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

namespace vkvo::io {
namespace {

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '\n' || c == '\r') c = ' ';
    quoted += c;
    if (c == '"') quoted += '"';
  }
  return quoted + "\"";
}

// The fields of one CSV line (quotes as RFC 4180); nullopt-like empty vector for an unterminated quote.
std::vector<std::string> split_csv(const std::string& line, bool& ok) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  ok = true;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        fields.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  ok = !quoted;
  return fields;
}

template <typename T>
T number(const std::string& text, const std::filesystem::path& file, std::size_t line, const char* field) {
  try {
    std::size_t used = 0;
    const long long value = std::stoll(text, &used);
    if (used != text.size()) throw std::invalid_argument(text);
    return static_cast<T>(value);
  } catch (const std::exception&) {
    throw std::runtime_error(fmt::format("{}:{}: {} '{}' is not an integer", file.string(), line, field, text));
  }
}

}  // namespace

std::string format_frame_status(const FrameStatus& s) {
  return fmt::format("{},{},{},{},{},{},{},{}\n", s.index, s.timestamp_ns, s.state, s.segment, s.keyframe ? 1 : 0,
                     s.point_inliers, s.line_inliers, csv_field(s.note));
}

std::vector<FrameStatus> read_frame_status(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open the frame status file", file.string()));
  std::vector<FrameStatus> out;
  std::string line;
  std::size_t number_of_line = 0;
  while (std::getline(in, line)) {
    ++number_of_line;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (number_of_line == 1) {
      if (line != kFrameStatusHeader)
        throw std::runtime_error(fmt::format("{}:1: not a frame status file (header '{}', expected '{}')",
                                             file.string(), line, kFrameStatusHeader));
      continue;
    }
    if (line.empty()) continue;
    bool ok = false;
    const auto fields = split_csv(line, ok);
    if (!ok || fields.size() != 8)
      throw std::runtime_error(fmt::format("{}:{}: expected 8 comma-separated fields, found {}{}", file.string(),
                                           number_of_line, fields.size(), ok ? "" : " (unterminated quote)"));
    FrameStatus s;
    s.index = number<std::size_t>(fields[0], file, number_of_line, "index");
    s.timestamp_ns = number<std::int64_t>(fields[1], file, number_of_line, "timestamp_ns");
    s.state = fields[2];
    s.segment = number<int>(fields[3], file, number_of_line, "segment");
    s.keyframe = number<int>(fields[4], file, number_of_line, "keyframe") != 0;
    s.point_inliers = number<int>(fields[5], file, number_of_line, "point_inliers");
    s.line_inliers = number<int>(fields[6], file, number_of_line, "line_inliers");
    s.note = fields[7];
    out.push_back(std::move(s));
  }
  if (number_of_line == 0) throw std::runtime_error(fmt::format("{}: empty frame status file", file.string()));
  return out;
}

}  // namespace vkvo::io
