#pragma once
/// @file commands.hpp
/// Registration of the `manta` subcommands. Each subcommand lives in its own cmd_<name>.cpp and
/// adds itself to the app; its callback stores the action to run in `Action`, so errors are
/// handled in one place (main.cpp): manta::Error -> one line on stderr and its exit code.

#include <CLI/CLI.hpp>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

namespace manta::cli {

/// What a parsed subcommand runs; returns the process exit code.
using Action = std::function<int()>;

void add_atmosphere(CLI::App& app, Action& action);
void add_config(CLI::App& app, Action& action);
void add_trim(CLI::App& app, Action& action);
void add_modes(CLI::App& app, Action& action);
void add_simulate(CLI::App& app, Action& action);
void add_demo(CLI::App& app, Action& action);

/// Print a JSON object on stdout (one object, 2-space indented).
void print_json(const nlohmann::json& j);

}  // namespace manta::cli
