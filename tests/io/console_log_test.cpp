// io::LevelSplitSink: results and progress on one stream, warnings and errors on the other (issue 36).
#include <sstream>

#include <gtest/gtest.h>
#include <spdlog/logger.h>
#include <spdlog/sinks/ostream_sink.h>

#include "io/console_log.hpp"

using namespace vkvo;

TEST(ConsoleLog, WarningsAndErrorsGoToTheDiagnosticStream) {
  std::ostringstream results, diagnostics;
  auto sink = std::make_shared<io::LevelSplitSink>(std::make_shared<spdlog::sinks::ostream_sink_st>(results),
                                                   std::make_shared<spdlog::sinks::ostream_sink_st>(diagnostics));
  spdlog::logger logger("test", sink);
  logger.set_pattern("%l %v");
  logger.set_level(spdlog::level::debug);
  logger.info("ate 0.1");
  logger.debug("detail");
  logger.warn("slow");
  logger.error("broken");
  EXPECT_EQ(results.str(), "info ate 0.1\ndebug detail\n");
  EXPECT_EQ(diagnostics.str(), "warning slow\nerror broken\n");
}

TEST(ConsoleLog, LevelNames) {
  EXPECT_EQ(io::parse_log_level("warn"), spdlog::level::warn);
  EXPECT_EQ(io::parse_log_level("warning"), spdlog::level::warn);
  EXPECT_EQ(io::parse_log_level("off"), spdlog::level::off);
  EXPECT_THROW(io::parse_log_level("loud"), std::invalid_argument);
}
