#pragma once
/// @file subprocess.hpp
/// Runs `manta` subcommands as child processes, several at once, for `manta demo`: each child's
/// output (stdout and stderr) goes to its own log file, and a status line per running child (its
/// latest output line) is printed periodically, so a long pipeline shows its progress throughout.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace manta::cli {

/// One child process.
struct ChildJob {
    std::string name;               ///< shown before its status lines ("optimise immelmann")
    std::vector<std::string> args;  ///< argv after the program
    std::filesystem::path log;      ///< where its output goes (the folder is created)
};

/// What became of a child.
struct ChildResult {
    std::string name;
    int exit_code = 0;          ///< the child's exit status; 128 + signal when it was killed
    double wall_seconds = 0.0;  ///< from start to end
    std::string last_line;      ///< its last non-empty output line
};

/// Options of `run_children`.
struct RunChildrenOptions {
    int jobs = 1;                  ///< children running at once (>= 1)
    double status_interval = 5.0;  ///< seconds between status lines of a running child
    bool quiet = false;            ///< print nothing
    /// Environment settings added for every child ("NAME=value").
    std::vector<std::string> environment;
    /// Called when a child ends, in the order they end.
    std::function<void(const ChildResult&)> on_exit;
};

/// The path of the running executable (/proc/self/exe).
[[nodiscard]] std::filesystem::path self_executable();

/// Run `program` once per job, at most `options.jobs` at a time, in the order given; returns the
/// results in the order of `jobs`. A child that cannot be started is an IoError.
std::vector<ChildResult> run_children(const std::filesystem::path& program,
                                      const std::vector<ChildJob>& jobs,
                                      const RunChildrenOptions& options);

}  // namespace manta::cli
