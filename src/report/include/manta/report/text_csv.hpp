#pragma once
/// @file text_csv.hpp
/// CSV tables with text fields (RFC 4180 quoting), such as `tables.csv` and `samples.csv`, and
/// JSON files, read with errors that name the file, line and column.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace manta::report {

/// A CSV table whose fields are kept as text. Lines starting with '#' before the header are
/// comments; blank lines are skipped.
struct TextCsv {
    std::string source;                          ///< file name, for messages
    std::vector<std::string> columns;            ///< header names
    std::vector<std::vector<std::string>> rows;  ///< rows.size() x columns.size()
    std::vector<int> row_lines;                  ///< 1-based file line of each row
    std::vector<std::string> comments;           ///< comment lines without the leading '#'

    /// Index of column `name`, or -1.
    [[nodiscard]] int find(std::string_view name) const;
    /// Index of a column that must exist; InputError naming the file and the columns present.
    [[nodiscard]] std::size_t require(std::string_view name) const;
    /// Field (row, column) as a finite number; InputError "file:line: column N 'name' value 'v'
    /// is not a number" otherwise.
    [[nodiscard]] double number(std::size_t row, std::size_t column) const;
};

/// Parse CSV text with quoted fields ("a ""b"", c" is one field). InputError naming source, line
/// and column for an unterminated quote, a row of the wrong length, an empty or duplicated header
/// name, or no header.
[[nodiscard]] TextCsv parse_text_csv(std::string_view text, std::string source);
/// Read and parse a CSV file (IoError if it cannot be read).
[[nodiscard]] TextCsv read_text_csv(const std::filesystem::path& file);

/// Parse JSON text; InputError "source:line:column: invalid JSON: reason" on a syntax error.
[[nodiscard]] nlohmann::json parse_json(std::string_view text, const std::string& source);
/// Read and parse a JSON file (IoError if it cannot be read).
[[nodiscard]] nlohmann::json read_json(const std::filesystem::path& file);

}  // namespace manta::report
