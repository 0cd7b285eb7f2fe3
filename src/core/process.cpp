/// @file process.cpp
/// One external command run to its end (process.hpp).

#include "manta/core/process.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <fstream>

#include "manta/core/error.hpp"

extern char** environ;

namespace manta::core {

namespace {

std::string last_nonempty_line(const std::filesystem::path& log) {
    std::ifstream in(log);
    std::string line, last;
    while (std::getline(in, line))
        if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
    return last;
}

}  // namespace

ProcessResult run_process(const std::vector<std::string>& argv, const std::filesystem::path& log,
                          const std::vector<std::string>& extra_environment) {
    if (argv.empty()) throw IoError("run_process: no command given");
    std::error_code ec;
    if (log.has_parent_path()) std::filesystem::create_directories(log.parent_path(), ec);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (fd < 0)
        throw IoError(
            fmt::format("{}: cannot open the log ({})", log.string(), std::strerror(errno)));
    // Everything the child needs, prepared before fork (only async-signal-safe calls after it).
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    std::vector<std::string> env_strings;
    for (char** e = environ; e && *e; ++e) env_strings.emplace_back(*e);
    for (const std::string& e : extra_environment) env_strings.push_back(e);
    std::vector<char*> env;
    for (std::string& e : env_strings) env.push_back(e.data());
    env.push_back(nullptr);
    int error_pipe[2];
    if (::pipe2(error_pipe, O_CLOEXEC) != 0) {
        ::close(fd);
        throw IoError(fmt::format("cannot start '{}': pipe ({})", argv[0], std::strerror(errno)));
    }
    const pid_t parent = ::getpid();
    const auto t0 = std::chrono::steady_clock::now();
    const pid_t pid = ::fork();
    if (pid < 0) {
        ::close(fd);
        ::close(error_pipe[0]);
        ::close(error_pipe[1]);
        throw IoError(fmt::format("cannot start '{}': fork ({})", argv[0], std::strerror(errno)));
    }
    if (pid == 0) {
        ::prctl(PR_SET_PDEATHSIG, SIGTERM);
        if (::getppid() != parent) ::_exit(127);
        ::dup2(fd, STDOUT_FILENO);
        ::dup2(fd, STDERR_FILENO);
        const int in = ::open("/dev/null", O_RDONLY);
        if (in >= 0) ::dup2(in, STDIN_FILENO);
        ::execvpe(args[0], args.data(), env.data());
        const int err = errno;
        [[maybe_unused]] const ssize_t w = ::write(error_pipe[1], &err, sizeof err);
        ::_exit(127);
    }
    ::close(fd);
    ::close(error_pipe[1]);
    int exec_errno = 0;
    const ssize_t got = ::read(error_pipe[0], &exec_errno, sizeof exec_errno);
    ::close(error_pipe[0]);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (got == static_cast<ssize_t>(sizeof exec_errno))
        throw IoError(fmt::format("cannot start '{}': {}", argv[0], std::strerror(exec_errno)));
    ProcessResult r;
    r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.last_line = last_nonempty_line(log);
    return r;
}

std::vector<std::string> split_command(std::string_view command, std::string_view where) {
    std::vector<std::string> words;
    std::string word;
    bool in_word = false;
    for (std::size_t i = 0; i < command.size(); ++i) {
        const char c = command[i];
        if (c == ' ' || c == '\t' || c == '\n') {
            if (in_word) words.push_back(std::move(word));
            word.clear();
            in_word = false;
        } else if (c == '\'') {
            const std::size_t end = command.find('\'', i + 1);
            if (end == std::string_view::npos)
                throw InputError(
                    fmt::format("{}: '{}' has an unterminated single quote", where, command));
            word.append(command.substr(i + 1, end - i - 1));
            in_word = true;
            i = end;
        } else if (c == '"') {
            std::size_t j = i + 1;
            for (; j < command.size() && command[j] != '"'; ++j) {
                if (command[j] == '\\' && j + 1 < command.size() &&
                    (command[j + 1] == '"' || command[j + 1] == '\\'))
                    ++j;
                word += command[j];
            }
            if (j >= command.size())
                throw InputError(
                    fmt::format("{}: '{}' has an unterminated double quote", where, command));
            in_word = true;
            i = j;
        } else if (c == '\\' && i + 1 < command.size()) {
            word += command[++i];
            in_word = true;
        } else {
            word += c;
            in_word = true;
        }
    }
    if (in_word) words.push_back(std::move(word));
    return words;
}

}  // namespace manta::core
