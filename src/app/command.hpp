#pragma once
// Subcommand registry of the `vkvo` CLI. Each src/app/cmd_<name>.cpp defines one subcommand and registers it
// with a static CommandRegistration; main.cpp builds the CLI11 app from the registry.
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace vkvo::app {

struct Command {
  std::string name;
  std::string description;
  // Adds the subcommand's options to `sub`; returns the action run when the subcommand is chosen (exit code).
  std::function<std::function<int()>(CLI::App& sub)> setup;
};

std::vector<Command>& command_registry();

struct CommandRegistration {
  explicit CommandRegistration(Command command) { command_registry().push_back(std::move(command)); }
};

}  // namespace vkvo::app
