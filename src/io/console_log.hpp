#pragma once
// Where the CLI's messages go: results and progress (info and below) on stdout, warnings and errors on stderr,
// so that a script can tell them apart (`vkvo run ... 2>errors.txt`).
#include <memory>
#include <string>
#include <string_view>

#include <spdlog/common.h>
#include <spdlog/sinks/sink.h>

namespace vkvo::io {

// A sink that hands info-and-below messages to `low` and warn-and-above messages to `high`.
class LevelSplitSink final : public spdlog::sinks::sink {
 public:
  LevelSplitSink(spdlog::sink_ptr low, spdlog::sink_ptr high);
  void log(const spdlog::details::log_msg& message) override;
  void flush() override;
  void set_pattern(const std::string& pattern) override;
  void set_formatter(std::unique_ptr<spdlog::formatter> formatter) override;

 private:
  spdlog::sink_ptr low_, high_;
};

// Parses trace|debug|info|warn|error|critical|off; throws std::invalid_argument naming the accepted values.
spdlog::level::level_enum parse_log_level(std::string_view name);

// Makes spdlog's default logger a stdout/stderr split logger at `level`.
void install_console_logger(spdlog::level::level_enum level);

}  // namespace vkvo::io
