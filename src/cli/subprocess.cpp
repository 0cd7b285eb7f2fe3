/// @file subprocess.cpp
/// Child processes of `manta demo` (POSIX fork/exec, one pipe per child, poll). The children
/// end with the demo: each asks the kernel for SIGTERM when its parent dies (PR_SET_PDEATHSIG,
/// which covers a `kill -9` of the demo), and a SIGINT or SIGTERM to the demo is passed on to
/// the running children before the demo ends by it.

#include "subprocess.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>

#include "manta/core/error.hpp"

namespace manta::cli {

namespace fs = std::filesystem;

fs::path self_executable() {
    std::error_code ec;
    auto p = fs::read_symlink("/proc/self/exe", ec);
    if (ec) throw IoError("cannot find the running executable (/proc/self/exe): " + ec.message());
    return p;
}

namespace {

using Clock = std::chrono::steady_clock;

// The running children's process ids, for the signal handler (0: a free slot). A child beyond
// the slots still ends with the demo through PR_SET_PDEATHSIG.
std::array<std::atomic<pid_t>, 256> g_children{};
static_assert(std::atomic<pid_t>::is_always_lock_free);

void remember_child(pid_t pid) {
    for (auto& slot : g_children) {
        pid_t free = 0;
        if (slot.compare_exchange_strong(free, pid)) return;
    }
}

void forget_child(pid_t pid) {
    for (auto& slot : g_children) {
        pid_t p = pid;
        if (slot.compare_exchange_strong(p, 0)) return;
    }
}

// SIGINT/SIGTERM: the same signal to every running child, then the default action (the demo
// ends by the signal, as it would without the handler). Only async-signal-safe calls.
extern "C" void pass_signal_on(int sig) {
    for (auto& slot : g_children) {
        const pid_t p = slot.load();
        if (p > 0) ::kill(p, sig);
    }
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

// The handlers installed while children run; the previous ones back when they are done.
class PassSignalsOn {
public:
    PassSignalsOn() {
        struct sigaction sa {};
        sa.sa_handler = pass_signal_on;
        sigemptyset(&sa.sa_mask);
        sigaction(SIGINT, &sa, &old_int_);
        sigaction(SIGTERM, &sa, &old_term_);
    }
    ~PassSignalsOn() {
        sigaction(SIGINT, &old_int_, nullptr);
        sigaction(SIGTERM, &old_term_, nullptr);
    }
    PassSignalsOn(const PassSignalsOn&) = delete;
    PassSignalsOn& operator=(const PassSignalsOn&) = delete;

private:
    struct sigaction old_int_ {};
    struct sigaction old_term_ {};
};

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct Running {
    std::size_t index = 0;
    pid_t pid = -1;
    int fd = -1;
    std::ofstream log;
    std::string partial;  // output after the last line end
    std::string last;     // latest complete non-empty line
    std::string printed;  // the line last shown
    Clock::time_point started;
    Clock::time_point shown;
};

// Start `program args...` with stdout and stderr on a pipe; returns the running record.
std::unique_ptr<Running> spawn(const fs::path& program, const ChildJob& job, std::size_t index,
                               const std::vector<std::string>& environment) {
    auto r = std::make_unique<Running>();
    r->index = index;
    if (!job.log.parent_path().empty()) fs::create_directories(job.log.parent_path());
    r->log.open(job.log, std::ios::binary | std::ios::trunc);
    if (!r->log) throw IoError(fmt::format("{}: cannot write the log file", job.log.string()));
    r->log << "$ " << program.string();
    for (const auto& a : job.args) r->log << ' ' << a;
    r->log << '\n';
    int fds[2];
    if (pipe(fds) != 0) throw IoError(std::string("cannot create a pipe: ") + std::strerror(errno));
    std::vector<std::string> argv_s;
    argv_s.push_back(program.string());
    argv_s.insert(argv_s.end(), job.args.begin(), job.args.end());
    std::vector<char*> argv;
    for (auto& a : argv_s) argv.push_back(a.data());
    argv.push_back(nullptr);
    std::vector<std::string> env_s = environment;
    std::fflush(stdout);
    std::fflush(stderr);
    const pid_t parent = getpid();
    const pid_t pid = fork();
    if (pid < 0) throw IoError(std::string("cannot start a process: ") + std::strerror(errno));
    if (pid == 0) {
        // Child: output to the pipe, then exec (only async-signal-safe calls from here).
        // SIGTERM when the demo dies, however it dies; if it died before this line, end now.
        prctl(PR_SET_PDEATHSIG, SIGTERM);
        if (getppid() != parent) _exit(128 + SIGTERM);
        signal(SIGINT, SIG_DFL);
        signal(SIGTERM, SIG_DFL);
        close(fds[0]);
        dup2(fds[1], STDOUT_FILENO);
        dup2(fds[1], STDERR_FILENO);
        close(fds[1]);
        for (auto& e : env_s) putenv(e.data());
        execv(argv[0], argv.data());
        _exit(127);
    }
    close(fds[1]);
    remember_child(pid);
    fcntl(fds[0], F_SETFL, fcntl(fds[0], F_GETFL) | O_NONBLOCK);
    r->pid = pid;
    r->fd = fds[0];
    r->started = Clock::now();
    r->shown = r->started;
    return r;
}

// Read what is available; false at end of output.
bool drain(Running& r) {
    char buf[4096];
    for (;;) {
        const ssize_t n = read(r.fd, buf, sizeof buf);
        if (n > 0) {
            r.log.write(buf, n);
            for (ssize_t i = 0; i < n; ++i) {
                const char c = buf[i];
                if (c == '\n' || c == '\r') {
                    const auto b = r.partial.find_first_not_of(" \t");
                    if (b != std::string::npos) r.last = r.partial.substr(b);
                    r.partial.clear();
                } else {
                    r.partial += c;
                }
            }
            continue;
        }
        if (n == 0) return false;
        if (errno == EAGAIN || errno == EWOULDBLOCK) return true;
        if (errno == EINTR) continue;
        return false;
    }
}

std::string shorten(const std::string& s, std::size_t n = 140) {
    return s.size() <= n ? s : s.substr(0, n - 3) + "...";
}

}  // namespace

std::vector<ChildResult> run_children(const fs::path& program, const std::vector<ChildJob>& jobs,
                                      const RunChildrenOptions& options) {
    std::vector<ChildResult> results(jobs.size());
    const PassSignalsOn pass_signals;
    std::vector<std::unique_ptr<Running>> running;
    std::size_t next = 0;
    const int width = options.jobs < 1 ? 1 : options.jobs;
    auto say = [&](const std::string& s) {
        if (!options.quiet) {
            fmt::print("{}\n", s);
            std::fflush(stdout);
        }
    };
    while (next < jobs.size() || !running.empty()) {
        while (next < jobs.size() && static_cast<int>(running.size()) < width) {
            running.push_back(spawn(program, jobs[next], next, options.environment));
            say(fmt::format("      {}: started (log {})", jobs[next].name,
                            jobs[next].log.string()));
            ++next;
        }
        std::vector<pollfd> pfds;
        for (const auto& r : running) pfds.push_back({r->fd, POLLIN, 0});
        (void)poll(pfds.data(), pfds.size(), 250);
        for (std::size_t k = 0; k < running.size();) {
            Running& r = *running[k];
            const bool open = drain(r);
            if (open) {
                if (!r.last.empty() && r.last != r.printed &&
                    seconds_since(r.shown) >= options.status_interval) {
                    say(fmt::format("      {} [{:.0f} s]: {}", jobs[r.index].name,
                                    seconds_since(r.started), shorten(r.last)));
                    r.printed = r.last;
                    r.shown = Clock::now();
                }
                ++k;
                continue;
            }
            // End of output: the child is ending; collect its status.
            close(r.fd);
            if (!r.partial.empty()) r.last = r.partial;
            int status = 0;
            while (waitpid(r.pid, &status, 0) < 0 && errno == EINTR) {
            }
            forget_child(r.pid);
            ChildResult res;
            res.name = jobs[r.index].name;
            res.exit_code = WIFEXITED(status)     ? WEXITSTATUS(status)
                            : WIFSIGNALED(status) ? 128 + WTERMSIG(status)
                                                  : 1;
            res.wall_seconds = seconds_since(r.started);
            res.last_line = r.last;
            r.log.flush();
            if (res.exit_code == 0) {
                say(fmt::format("      {}: done in {:.1f} s", res.name, res.wall_seconds));
            } else {
                say(fmt::format("      {}: FAILED (exit {}) after {:.1f} s: {}", res.name,
                                res.exit_code, res.wall_seconds, shorten(res.last_line, 300)));
            }
            if (options.on_exit) options.on_exit(res);
            results[r.index] = res;
            running.erase(running.begin() + static_cast<std::ptrdiff_t>(k));
        }
    }
    return results;
}

}  // namespace manta::cli
