// vkvo: the command-line entry point. Subcommands live in cmd_*.cpp (see command.hpp).
#include <algorithm>
#include <cstdio>
#include <exception>
#include <memory>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "app/bench_registry.hpp"
#include "app/command.hpp"

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
  cli.add_flag("-v,--verbose", verbose, "debug logging");

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
    return cli.exit(e);
  }
  spdlog::set_level(verbose ? spdlog::level::debug : spdlog::level::info);
  for (auto& [sub, action] : actions) {
    if (!sub->parsed()) continue;
    try {
      return action();
    } catch (const std::exception& e) {
      // On stderr, after what the command printed (spdlog's default logger writes to stdout).
      std::fflush(stdout);
      fmt::print(stderr, "vkvo {}: error: {}\n", sub->get_name(), e.what());
      return 1;
    }
  }
  return 1;
}
