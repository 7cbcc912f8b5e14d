// vkvo: the command-line entry point. Subcommands live in cmd_*.cpp (see command.hpp).
#include <algorithm>
#include <exception>
#include <memory>
#include <string>

#include <spdlog/spdlog.h>

#include "app/bench_registry.hpp"
#include "app/command.hpp"
#include "app/exit_codes.hpp"
#include "io/atomic_file.hpp"
#include "io/console_log.hpp"

namespace vkvo::app {
std::vector<Command>& command_registry() {
  static std::vector<Command> registry;
  return registry;
}
std::vector<NetworkBench>& network_bench_registry() {
  static std::vector<NetworkBench> registry;
  return registry;
}
}  // namespace vkvo::app

int main(int argc, char** argv) {
  using namespace vkvo::app;
  CLI::App cli{"vkvo: illumination-robust stereo visual odometry with networks on any Vulkan GPU"};
  cli.require_subcommand(1);
  bool verbose = false;
  bool quiet = false;
  std::string log_level;
  cli.add_flag("-v,--verbose", verbose, "debug logging");
  cli.add_flag("-q,--quiet", quiet, "warnings and errors only");
  cli.add_option("--log-level", log_level, "trace|debug|info|warn|error|critical|off (overrides -v/-q)")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "warning", "error", "critical", "off"}));
  cli.footer(vkvo::app::kExitCodeHelp);
  // Results and progress go to stdout, warnings and errors to stderr.
  vkvo::io::install_console_logger(spdlog::level::info);

  auto& registry = command_registry();
  std::sort(registry.begin(), registry.end(), [](const Command& a, const Command& b) { return a.name < b.name; });
  std::vector<std::pair<CLI::App*, std::function<int()>>> actions;
  for (const auto& command : registry) {
    CLI::App* sub = cli.add_subcommand(command.name, command.description);
    actions.emplace_back(sub, command.setup(*sub));
  }
  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = cli.exit(e);  // prints the help, or the error on stderr
    return code == 0 ? kExitOk : kExitBadInput;
  }
  spdlog::set_level(!log_level.empty() ? vkvo::io::parse_log_level(log_level)
                    : verbose          ? spdlog::level::debug
                    : quiet            ? spdlog::level::warn
                                       : spdlog::level::info);
  for (auto& [sub, action] : actions) {
    if (!sub->parsed()) continue;
    try {
      return action();
    } catch (const vkvo::io::OutputWriteError& e) {
      spdlog::error("{}", e.what());
      return kExitWriteFailed;
    } catch (const std::exception& e) {
      spdlog::error("vkvo {}: {}", sub->get_name(), e.what());
      return kExitBadInput;
    }
  }
  return kExitBadInput;
}
