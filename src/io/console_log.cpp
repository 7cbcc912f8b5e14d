#include "io/console_log.hpp"

#include <stdexcept>
#include <string>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

namespace vkvo::io {

LevelSplitSink::LevelSplitSink(spdlog::sink_ptr low, spdlog::sink_ptr high)
    : low_(std::move(low)), high_(std::move(high)) {}

void LevelSplitSink::log(const spdlog::details::log_msg& message) {
  if (!should_log(message.level)) return;
  if (message.level >= spdlog::level::warn) {
    low_->flush();  // keep the order of the two streams on a shared terminal
    high_->log(message);
  } else {
    low_->log(message);
  }
}

void LevelSplitSink::flush() {
  low_->flush();
  high_->flush();
}

void LevelSplitSink::set_pattern(const std::string& pattern) {
  low_->set_pattern(pattern);
  high_->set_pattern(pattern);
}

void LevelSplitSink::set_formatter(std::unique_ptr<spdlog::formatter> formatter) {
  high_->set_formatter(formatter->clone());
  low_->set_formatter(std::move(formatter));
}

spdlog::level::level_enum parse_log_level(std::string_view name) {
  if (name == "warn") return spdlog::level::warn;
  for (int level = spdlog::level::trace; level <= spdlog::level::off; ++level) {
    const auto value = static_cast<spdlog::level::level_enum>(level);
    const auto text = spdlog::level::to_string_view(value);
    if (name == std::string_view(text.data(), text.size())) return value;
  }
  throw std::invalid_argument("log level '" + std::string(name) +
                              "' is not one of trace, debug, info, warning, error, critical, off");
}

void install_console_logger(spdlog::level::level_enum level) {
  auto sink = std::make_shared<LevelSplitSink>(std::make_shared<spdlog::sinks::stdout_color_sink_mt>(),
                                               std::make_shared<spdlog::sinks::stderr_color_sink_mt>());
  auto logger = std::make_shared<spdlog::logger>("", std::move(sink));  // unnamed, as spdlog's own default
  logger->set_level(level);
  spdlog::set_default_logger(std::move(logger));
}

}  // namespace vkvo::io
