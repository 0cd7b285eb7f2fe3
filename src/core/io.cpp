#include "manta/core/io.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <ctime>
#include <fstream>
#include <limits>
#include <mutex>
#include <set>
#include <sstream>
#include <system_error>
#include <thread>
#include <utility>

#include "manta/core/error.hpp"
#include "manta/core/text.hpp"

namespace manta::core {

namespace fs = std::filesystem;

namespace {

/// The process id of a temporary's name NAME.tmpPID, or 0 when the name is not of that form.
long temporary_pid(const std::string& name) {
    const auto at = name.rfind(".tmp");
    if (at == std::string::npos || at == 0) return 0;
    const std::string_view digits = std::string_view(name).substr(at + 4);
    if (digits.empty() || digits.size() > 10) return 0;
    long pid = 0;
    const auto r = std::from_chars(digits.data(), digits.data() + digits.size(), pid);
    if (r.ec != std::errc() || r.ptr != digits.data() + digits.size()) return 0;
    return pid;
}

/// True while process `pid` exists (EPERM: it exists, owned by another user).
bool process_alive(long pid) {
    if (pid <= 0 || pid > std::numeric_limits<pid_t>::max()) return false;
    return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

/// Stale temporaries are removed once per folder and process, by the folder's first writer.
void clean_folder_once(const fs::path& dir) {
    static std::mutex m;
    static std::set<std::string> cleaned;
    std::error_code ec;
    const fs::path key = fs::weakly_canonical(dir.empty() ? fs::path(".") : dir, ec);
    {
        const std::lock_guard lock(m);
        if (!cleaned.insert(ec ? dir.string() : key.string()).second) return;
    }
    (void)remove_stale_temporaries(dir.empty() ? fs::path(".") : dir, false);
}

/// "OPTION PATH" for messages ("--out run"; the path alone without an option name).
std::string named(std::string_view option, const fs::path& path) {
    return option.empty() ? path.string() : fmt::format("{} {}", option, path.string());
}

/// prepare_output_folder of `dir`, for the output `given` (a folder, or a file in `dir`).
void prepare_folder(const fs::path& dir, std::string_view option, const fs::path& given) {
    const std::string who =
        named(option, given) + (given == dir ? "" : fmt::format(": folder {}", dir.string()));
    std::error_code ec;
    const fs::file_status st = fs::status(dir, ec);
    if (fs::exists(st) && !fs::is_directory(st))
        throw IoError(fmt::format("{}: is not a folder (a file of that name exists)", who));
    if (!fs::exists(st)) {
        ec.clear();
        fs::create_directories(dir, ec);
        if (ec) throw IoError(fmt::format("{}: cannot create the folder: {}", who, ec.message()));
    }
    // The write test: a file created and removed (named as a temporary, so a probe left by a
    // kill is removed like one).
    const fs::path probe =
        dir / fmt::format(".manta-write-test.tmp{}", static_cast<long>(::getpid()));
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (fd < 0)
        throw IoError(fmt::format("{}: cannot write in the folder: {}", who, std::strerror(errno)));
    ::close(fd);
    ::unlink(probe.c_str());
}

}  // namespace

std::size_t remove_stale_temporaries(const fs::path& dir, bool recursive) {
    std::size_t removed = 0;
    std::error_code ec;
    const auto visit = [&](const fs::directory_entry& e) {
        std::error_code fe;
        if (!e.is_regular_file(fe)) return;
        const long pid = temporary_pid(e.path().filename().string());
        if (pid == 0 || process_alive(pid)) return;
        if (fs::remove(e.path(), fe)) ++removed;
    };
    if (recursive) {
        fs::recursive_directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec);
        for (; !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) visit(*it);
    } else {
        fs::directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec);
        for (; !ec && it != fs::directory_iterator(); it.increment(ec)) visit(*it);
    }
    return removed;
}

void prepare_output_folder(const fs::path& dir, std::string_view option) {
    if (dir.empty())
        throw IoError(fmt::format("{} is empty; expected a folder path",
                                  option.empty() ? "the output folder" : option));
    prepare_folder(dir, option, dir);
}

void prepare_output_file(const fs::path& file, std::string_view option) {
    if (file.empty())
        throw IoError(fmt::format("{} is empty; expected a file path",
                                  option.empty() ? "the output file" : option));
    std::error_code ec;
    if (fs::is_directory(file, ec))
        throw IoError(fmt::format("{}: is a folder; expected a file path", named(option, file)));
    const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
    prepare_folder(dir, option, file);
}

// ------------------------------------------------------------------------------- run folder lock

RunFolderLock::RunFolderLock(const fs::path& dir, std::string_view command, std::string_view option)
    : dir_(dir) {
    prepare_output_folder(dir, option);
    const fs::path file = dir / file_name;
    fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0)
        throw IoError(fmt::format("{}: cannot create the lock file {}: {}", named(option, dir),
                                  file_name, std::strerror(errno)));
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
        const int err = errno;
        // The holder writes its record just after taking the lock: wait a little for it.
        std::string text;
        for (int i = 0; i < 50; ++i) {
            std::array<char, 512> buf{};
            const ssize_t n = ::pread(fd_, buf.data(), buf.size() - 1, 0);
            text.assign(buf.data(), n > 0 ? static_cast<std::size_t>(n) : 0);
            if (text.find("since ") != std::string::npos) break;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        ::close(fd_);
        fd_ = -1;
        if (err != EWOULDBLOCK)
            throw IoError(fmt::format("{}: cannot lock the folder ({}): {}", named(option, dir),
                                      file_name, std::strerror(err)));
        auto field = [&](std::string_view key) {
            const auto at = text.find(std::string(key) + " ");
            if (at == std::string::npos) return std::string("?");
            const auto end = text.find('\n', at);
            return text.substr(at + key.size() + 1, end == std::string::npos
                                                        ? std::string::npos
                                                        : end - at - key.size() - 1);
        };
        throw IoError(fmt::format(
            "{} is in use by manta {} (pid {}) since {}; wait for it to end or choose another {}",
            dir.string(), field("command"), field("pid"), field("since"),
            option.empty() ? "folder" : option));
    }
    std::array<char, 32> when{};
    const std::time_t now = std::time(nullptr);
    std::tm tm{};
    ::gmtime_r(&now, &tm);
    std::strftime(when.data(), when.size(), "%Y-%m-%dT%H:%M:%SZ", &tm);
    const std::string record = fmt::format("pid {}\ncommand {}\nsince {}\n",
                                           static_cast<long>(::getpid()), command, when.data());
    if (::ftruncate(fd_, 0) != 0 ||
        ::pwrite(fd_, record.data(), record.size(), 0) != static_cast<ssize_t>(record.size())) {
        const int err = errno;
        ::close(fd_);
        fd_ = -1;
        throw IoError(fmt::format("{}: cannot write the lock file {}: {}", named(option, dir),
                                  file_name, std::strerror(err)));
    }
    (void)remove_stale_temporaries(dir, true);
}

RunFolderLock::~RunFolderLock() {
    if (fd_ >= 0) ::close(fd_);
}

RunFolderLock::RunFolderLock(RunFolderLock&& other) noexcept
    : dir_(std::move(other.dir_)), fd_(std::exchange(other.fd_, -1)) {}

RunFolderLock& RunFolderLock::operator=(RunFolderLock&& other) noexcept {
    if (this != &other) {
        if (fd_ >= 0) ::close(fd_);
        dir_ = std::move(other.dir_);
        fd_ = std::exchange(other.fd_, -1);
    }
    return *this;
}

// ------------------------------------------------------------------------------- atomic writes

AtomicFileWriter::AtomicFileWriter(const std::filesystem::path& file) : file_(file) {
    std::error_code ec;
    if (file.has_parent_path()) fs::create_directories(file.parent_path(), ec);
    if (ec)
        throw IoError(fmt::format("{}: cannot create directory: {}", file.parent_path().string(),
                                  ec.message()));
    clean_folder_once(file.parent_path());
    tmp_ = file.string() + fmt::format(".tmp{}", static_cast<long>(::getpid()));
    out_ = std::make_unique<std::ofstream>(tmp_, std::ios::binary | std::ios::trunc);
    if (!*out_) throw IoError(fmt::format("{}: cannot open for writing", tmp_.string()));
}

AtomicFileWriter::~AtomicFileWriter() {
    if (committed_) return;
    out_.reset();
    std::error_code ec;
    std::filesystem::remove(tmp_, ec);
}

void AtomicFileWriter::write(std::string_view text) {
    out_->write(text.data(), static_cast<std::streamsize>(text.size()));
    if (!*out_) throw IoError(fmt::format("{}: write failed", tmp_.string()));
}

void AtomicFileWriter::spill(std::string& buffer, std::size_t threshold) {
    if (buffer.size() < threshold) return;
    write(buffer);
    buffer.clear();
}

void AtomicFileWriter::commit() {
    out_->flush();
    if (!*out_) throw IoError(fmt::format("{}: write failed", tmp_.string()));
    out_.reset();
    std::error_code ec;
    std::filesystem::rename(tmp_, file_, ec);
    if (ec) {
        std::filesystem::remove(tmp_);
        throw IoError(fmt::format("{}: cannot replace file: {}", file_.string(), ec.message()));
    }
    committed_ = true;
}

void write_file_atomic(const std::filesystem::path& file, std::string_view content) {
    AtomicFileWriter w(file);
    w.write(content);
    w.commit();
}

std::string read_file(const std::filesystem::path& file) {
    // An ifstream opens a directory on Linux and reads nothing: say what is wrong instead.
    std::error_code ec;
    if (std::filesystem::is_directory(file, ec))
        throw IoError(fmt::format("{}: is a directory; expected a file", file.string()));
    std::ifstream in(file, std::ios::binary);
    if (!in) throw IoError(fmt::format("{}: cannot open file for reading", file.string()));
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string format_exact(double v) {
    std::array<char, 64> buf{};
    const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
    return std::string(buf.data(), r.ptr);
}

int CsvTable::find(std::string_view name) const {
    const auto it = std::find(columns.begin(), columns.end(), name);
    return it == columns.end() ? -1 : static_cast<int>(it - columns.begin());
}

std::size_t CsvTable::require(std::string_view name) const {
    const int i = find(name);
    if (i < 0) {
        throw InputError(fmt::format("{}: missing column '{}'; columns present: {}", source, name,
                                     fmt::join(columns, ", ")));
    }
    return static_cast<std::size_t>(i);
}

std::vector<double> CsvTable::column(std::size_t index) const {
    std::vector<double> out;
    out.reserve(rows.size());
    for (const auto& r : rows) out.push_back(r.at(index));
    return out;
}

CsvTable parse_csv(std::string_view text, std::string source) {
    CsvTable t;
    t.source = std::move(source);
    int line_no = 0;
    std::size_t pos = 0;
    bool have_header = false;
    while (pos <= text.size()) {
        const std::size_t nl = text.find('\n', pos);
        std::string_view line =
            text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
        pos = nl == std::string_view::npos ? text.size() + 1 : nl + 1;
        ++line_no;
        line = core::trim_blanks(line);
        if (line.empty()) continue;
        if (line.front() == '#') {
            t.comments.emplace_back(core::trim_blanks(line.substr(1)));
            continue;
        }
        const auto fields = core::split_fields(line);
        if (!have_header) {
            for (std::size_t i = 0; i < fields.size(); ++i) {
                if (fields[i].empty())
                    throw InputError(fmt::format("{}:{}: column {} of the header is empty",
                                                 t.source, line_no, i + 1));
                if (std::find(t.columns.begin(), t.columns.end(), fields[i]) != t.columns.end())
                    throw InputError(fmt::format("{}:{}: column '{}' appears twice in the header",
                                                 t.source, line_no, fields[i]));
                t.columns.emplace_back(fields[i]);
            }
            have_header = true;
            continue;
        }
        if (fields.size() != t.columns.size()) {
            throw InputError(fmt::format("{}:{}: row has {} fields; expected {} as in the header",
                                         t.source, line_no, fields.size(), t.columns.size()));
        }
        std::vector<double> row(fields.size());
        for (std::size_t i = 0; i < fields.size(); ++i) {
            const std::string_view f = fields[i];
            // from_chars rejects an explicit leading '+', which other tools write ("+1.5e+00").
            const std::string_view digits =
                f.size() > 1 && f.front() == '+' && f[1] != '-' && f[1] != '+' ? f.substr(1) : f;
            double v = 0.0;
            const auto r = std::from_chars(digits.data(), digits.data() + digits.size(), v);
            if (f.empty() || r.ec != std::errc() || r.ptr != digits.data() + digits.size()) {
                throw InputError(fmt::format("{}:{}: column '{}' value '{}' is not a number",
                                             t.source, line_no, t.columns[i], f));
            }
            if (!std::isfinite(v)) {
                throw InputError(fmt::format(
                    "{}:{}: column '{}' value '{}' is not finite; expected a finite number",
                    t.source, line_no, t.columns[i], f));
            }
            row[i] = v;
        }
        t.rows.push_back(std::move(row));
        t.row_lines.push_back(line_no);
    }
    if (!have_header)
        throw InputError(fmt::format(
            "{}: no header line found; expected comma-separated column names", t.source));
    return t;
}

CsvTable read_csv(const std::filesystem::path& file) {
    return parse_csv(read_file(file), file.string());
}

std::string to_csv(const std::vector<std::string>& columns,
                   const std::vector<std::vector<double>>& rows,
                   const std::vector<std::string>& comments) {
    std::string out;
    for (const auto& c : comments) out += fmt::format("# {}\n", c);
    out += fmt::format("{}\n", fmt::join(columns, ","));
    for (const auto& r : rows) {
        for (std::size_t i = 0; i < r.size(); ++i) {
            if (i) out += ',';
            out += format_exact(r[i]);
        }
        out += '\n';
    }
    return out;
}

}  // namespace manta::core
