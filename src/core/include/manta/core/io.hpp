#pragma once
/// @file io.hpp
/// File helpers: atomic writes (write to a temporary beside the target, then rename, so a reader
/// never sees half a file), output folders checked before any work and locked while a command
/// writes them, and numeric CSV tables with located errors.

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace manta::core {

/// Write `content` to `file` atomically; creates parent directories. IoError on failure.
void write_file_atomic(const std::filesystem::path& file, std::string_view content);

/// A file written piece by piece and made visible at once: the pieces go to a temporary beside
/// `file`, which `commit` renames over it; destroyed without `commit`, the temporary is removed
/// and `file` is unchanged. For outputs too large to assemble in memory first. IoError on
/// failure, naming the file. The temporary is named `file` + ".tmp" + the process id; a process
/// killed while writing leaves it behind, and the first writer of this process in that folder
/// removes such leftovers of processes that are no longer alive (remove_stale_temporaries).
class AtomicFileWriter {
public:
    explicit AtomicFileWriter(const std::filesystem::path& file);
    ~AtomicFileWriter();
    AtomicFileWriter(const AtomicFileWriter&) = delete;
    AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;
    /// Append `text`.
    void write(std::string_view text);
    /// Append `buffer` and clear it when it holds at least `threshold` bytes.
    void spill(std::string& buffer, std::size_t threshold = std::size_t{1} << 22);
    /// Flush, close and rename over the target.
    void commit();

private:
    std::filesystem::path file_;
    std::filesystem::path tmp_;
    std::unique_ptr<std::ofstream> out_;
    bool committed_ = false;
};

/// Remove the temporaries AtomicFileWriter left in `dir` when its process was killed: files
/// named NAME.tmpPID whose process PID is not alive (a live process may still be writing its
/// own). With `recursive`, in every folder below `dir` too. Returns how many were removed;
/// never throws (a file it cannot remove stays).
std::size_t remove_stale_temporaries(const std::filesystem::path& dir, bool recursive = false);

/// Make `dir` ready for a command's output before any work is done: created with its parents
/// when missing, and a file can be created in it. IoError (exit code 2), one line naming
/// `option`, the path and the system's reason ("--out /a/b: cannot create the folder: Not a
/// directory"); also for an empty path.
void prepare_output_folder(const std::filesystem::path& dir, std::string_view option);

/// The same for an output file: its folder prepared as by prepare_output_folder, and `file`
/// itself not a folder. IoError naming `option`, the path and the reason.
void prepare_output_file(const std::filesystem::path& file, std::string_view option);

/// An exclusive lock on a run folder, held while a command writes it, so that two commands
/// never write one folder at once. The lock is flock(2) on the file `.manta.lock` in the folder,
/// which holds the holder's process id, command and start time; the kernel releases it when the
/// holder ends, however it ends, so a lock left by a killed process is simply taken. Taking it
/// prepares the folder (prepare_output_folder) and then removes the temporaries that killed
/// processes left anywhere in it (remove_stale_temporaries). Child processes started with exec
/// do not inherit it (close-on-exec).
class RunFolderLock {
public:
    /// Lock `dir` for `command` ("tables", "cfd", ...). IoError (exit code 2) when another
    /// process holds it: "DIR is in use by manta COMMAND (pid N) since TIME; ...", or when the
    /// folder cannot be prepared (naming `option`).
    RunFolderLock(const std::filesystem::path& dir, std::string_view command,
                  std::string_view option = "--out");
    ~RunFolderLock();
    RunFolderLock(const RunFolderLock&) = delete;
    RunFolderLock& operator=(const RunFolderLock&) = delete;
    RunFolderLock(RunFolderLock&& other) noexcept;
    RunFolderLock& operator=(RunFolderLock&& other) noexcept;
    /// The locked folder.
    [[nodiscard]] const std::filesystem::path& folder() const { return dir_; }
    /// The lock file's name in a run folder.
    static constexpr const char* file_name = ".manta.lock";

private:
    std::filesystem::path dir_;
    int fd_ = -1;
};

/// Read a whole text file. IoError on failure.
[[nodiscard]] std::string read_file(const std::filesystem::path& file);

/// Shortest decimal text that reads back to exactly the same double.
[[nodiscard]] std::string format_exact(double v);

/// A numeric CSV table: header of column names, rows of finite numbers. Lines starting with '#'
/// are comments (kept in `comments`). Whitespace around fields is ignored.
struct CsvTable {
    std::string source;                     ///< file name, for messages
    std::vector<std::string> columns;       ///< header names
    std::vector<std::vector<double>> rows;  ///< rows.size() x columns.size()
    std::vector<int> row_lines;             ///< 1-based file line of each row
    std::vector<std::string> comments;      ///< comment lines without the leading '#'

    /// Index of column `name`, or -1.
    [[nodiscard]] int find(std::string_view name) const;
    /// Index of a column that must exist; InputError naming the file and the columns present.
    [[nodiscard]] std::size_t require(std::string_view name) const;
    /// One column's values.
    [[nodiscard]] std::vector<double> column(std::size_t index) const;
};

/// Parse CSV text; InputError naming source, line and column for a non-numeric or non-finite
/// field, a row of the wrong length, an empty header or duplicated column names.
[[nodiscard]] CsvTable parse_csv(std::string_view text, std::string source);
/// Read and parse a CSV file.
[[nodiscard]] CsvTable read_csv(const std::filesystem::path& file);

/// Build CSV text: optional '#' comment lines, a header and rows (values written exactly).
[[nodiscard]] std::string to_csv(const std::vector<std::string>& columns,
                                 const std::vector<std::vector<double>>& rows,
                                 const std::vector<std::string>& comments = {});

}  // namespace manta::core
