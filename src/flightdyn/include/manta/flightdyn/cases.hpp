#pragma once
/// @file cases.hpp
/// The cases CSV of an ensemble (`manta simulate --cases`, docs/formats.md#cases-csv): one
/// header line naming columns `name`, `speed`, `altitude` (required), `inputs` and
/// `climb_angle_deg` (optional), then one row per case. Every check names file:line[:column].

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace manta::flightdyn {

/// The most cases one file may hold (a plausible ensemble is tens to thousands of cases; more
/// is refused rather than read and flown for hours).
inline constexpr std::size_t max_cases = 100000;

/// One row of a cases file.
struct CaseRow {
    std::string name;                   ///< case name, the output file's name
    int line = 0;                       ///< line in the cases file
    double speed = 0.0;                 ///< true airspeed [m/s]
    double altitude = 0.0;              ///< [m]
    double climb_angle_deg = 0.0;       ///< flight-path angle [deg] (column climb_angle_deg)
    std::string inputs;                 ///< as written ("" = trim controls held)
    std::filesystem::path inputs_path;  ///< resolved against the cases file's folder
    int inputs_column = 0;              ///< 1-based column of `inputs` (for messages)
    std::string inputs_text;            ///< the inputs file's content ("" if not read)
};

/// The columns of a cases file and what each holds, in their canonical order.
[[nodiscard]] const std::vector<std::pair<std::string, std::string>>& case_columns();

/// Why `name` cannot name a file DIR/<name>.csv, or "" if it can: letters, digits, '_', '-'
/// and '.', not first, not empty.
[[nodiscard]] std::string unsafe_case_name_reason(std::string_view name);

/// Reads the content of a row's inputs file (given its resolved path); IoError if it cannot.
using InputsFileReader = std::function<std::string(const std::filesystem::path&)>;

/// Parse cases-file text; `source` names it in messages and its folder resolves relative
/// `inputs` paths. With `read_inputs`, each row's inputs file is read as the row is parsed (into
/// `CaseRow::inputs_text`; an IoError names the row); without, no file is touched. InputError
/// "source:line[:column]: ..." for an empty or unknown header column (suggesting the closest),
/// a repeated or missing column, a row of the wrong length, an empty, unsafe or repeated name
/// (ignoring case; naming the line of the first), a value that is not a finite number or out of
/// range, an `inputs` path that is not UTF-8, more than `max_cases` rows, no header, no rows.
[[nodiscard]] std::vector<CaseRow> parse_cases(std::string_view text, const std::string& source,
                                               const InputsFileReader& read_inputs = {});

/// Read a cases file and every inputs file it names (so a missing one fails before any aircraft
/// is loaded). IoError if a file cannot be read; InputError as `parse_cases`.
[[nodiscard]] std::vector<CaseRow> read_cases(const std::string& file);

}  // namespace manta::flightdyn
