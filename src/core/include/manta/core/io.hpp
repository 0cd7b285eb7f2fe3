#pragma once
/// @file io.hpp
/// File helpers: atomic writes (write to a temporary beside the target, then rename, so a reader
/// never sees half a file) and numeric CSV tables with located errors.

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
/// failure, naming the file.
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
