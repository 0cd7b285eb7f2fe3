#pragma once
/// @file process.hpp
/// Running one external command to its end: the argument vector looked up on PATH, its output
/// (stdout and stderr) into a log file, the exit status back. Used where a library object hands
/// work to another process (the table campaign's Euler samples through a user's launcher such as
/// `mpirun -np 2`, docs/tables.md#launching-euler-samples).

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace manta::core {

/// What became of a command.
struct ProcessResult {
    int exit_code = 0;          ///< its exit status; 128 + signal when a signal ended it
    double wall_seconds = 0.0;  ///< from start to end
    std::string last_line;      ///< the last non-empty line of its log (for messages)
};

/// Run `argv` (argv[0] looked up on PATH) with `extra_environment` ("NAME=value") added to this
/// process's environment, stdout and stderr appended to `log` (its folder created), and wait for
/// it. The child is sent SIGTERM when this process dies. IoError when `argv` is empty, the log
/// cannot be opened or the command cannot be started (naming it).
[[nodiscard]] ProcessResult run_process(const std::vector<std::string>& argv,
                                        const std::filesystem::path& log,
                                        const std::vector<std::string>& extra_environment = {});

/// Split a command line into words as a POSIX shell would without expansions: whitespace
/// separates words, single quotes keep everything literal, double quotes keep whitespace (a
/// backslash escapes `"` and `\` inside them and any character outside quotes). No variables,
/// globs, pipes or redirections. InputError naming `where` for an unterminated quote.
[[nodiscard]] std::vector<std::string> split_command(std::string_view command,
                                                     std::string_view where);

}  // namespace manta::core
