/// @file cases.cpp
/// The cases CSV of an ensemble (docs/formats.md#cases-csv).

#include "manta/flightdyn/cases.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <unordered_map>

#include "manta/core/config.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/core/text.hpp"
#include "manta/core/utf8.hpp"

namespace manta::flightdyn {

namespace {

/// Index of each column in case_columns().
enum Column : std::size_t { c_name, c_speed, c_altitude, c_inputs, c_climb };

/// A finite number from a field, or InputError "file:line:column: ...". `at()` gives the
/// location (formatted only for a message).
template <class At>
double parse_number(std::string_view field, const At& at, const char* column,
                    const char* expected) {
    const std::string_view digits =
        field.size() > 1 && field.front() == '+' && field[1] != '-' && field[1] != '+'
            ? field.substr(1)
            : field;
    double v = 0.0;
    const auto r = std::from_chars(digits.data(), digits.data() + digits.size(), v);
    if (field.empty() || r.ec != std::errc() || r.ptr != digits.data() + digits.size() ||
        !std::isfinite(v))
        throw InputError(
            fmt::format("{}: column '{}' value '{}' is not a finite number; expected {}", at(),
                        column, field, expected));
    return v;
}

/// `s` in lower case (ASCII; names are ASCII once unsafe_case_name_reason accepts them).
std::string lower(std::string_view s) {
    std::string out(s);
    for (char& ch : out) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    return out;
}

}  // namespace

const std::vector<std::pair<std::string, std::string>>& case_columns() {
    static const std::vector<std::pair<std::string, std::string>> c = {
        {"name", "case name, the output file's name"},
        {"speed", "true airspeed [m/s]"},
        {"altitude", "altitude [m]"},
        {"inputs", "control-input CSV, relative to the cases file"},
        {"climb_angle_deg", "flight-path angle of the trim [deg]"}};
    return c;
}

std::string unsafe_case_name_reason(std::string_view name) {
    if (name.empty()) return "is empty";
    for (const char ch : name) {
        const auto u = static_cast<unsigned char>(ch);
        if (std::isalnum(u) || ch == '_' || ch == '-' || ch == '.') continue;
        if (ch == '/' || ch == '\\') return fmt::format("has a path separator '{}'", ch);
        if (std::isprint(u)) return fmt::format("has '{}'", ch);
        return fmt::format("has the byte 0x{:02x}", static_cast<unsigned>(u));
    }
    if (name.front() == '.') return "starts with '.'";
    return {};
}

std::vector<CaseRow> parse_cases(std::string_view text, const std::string& file,
                                 const InputsFileReader& read_inputs) {
    const std::filesystem::path base = std::filesystem::path(file).parent_path();
    std::vector<std::string> valid;
    for (const auto& c : case_columns()) valid.push_back(c.first);
    std::vector<std::string> header;
    std::vector<int> col(valid.size(), -1);  // column of each valid name in the file
    int header_line = 0;
    std::vector<CaseRow> rows;
    // Lower-cased name -> its row in `rows`: names are unique ignoring case.
    std::unordered_map<std::string, std::size_t> seen;
    int line_no = 0;
    std::size_t pos = 0;
    while (pos <= text.size()) {
        const std::size_t nl = text.find('\n', pos);
        const std::string_view raw =
            text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
        pos = nl == std::string_view::npos ? text.size() + 1 : nl + 1;
        ++line_no;
        const std::string_view line = core::trim_blanks(raw);
        if (line.empty() || line.front() == '#') continue;
        const auto fields = core::split_fields(line);
        if (header.empty()) {
            header_line = line_no;
            for (std::size_t i = 0; i < fields.size(); ++i) {
                const std::string name(fields[i]);
                const std::string at = fmt::format("{}:{}:{}", file, line_no, i + 1);
                if (name.empty())
                    throw InputError(
                        fmt::format("{}: column {} of the header is empty", at, i + 1));
                const auto it = std::find(valid.begin(), valid.end(), name);
                if (it == valid.end()) {
                    const std::string guess = core::closest_match(name, valid);
                    throw InputError(fmt::format(
                        "{}: unknown column '{}'{}; valid columns: {}", at, name,
                        guess.empty() ? std::string() : fmt::format(" (did you mean '{}'?)", guess),
                        fmt::join(valid, ", ")));
                }
                const auto k = static_cast<std::size_t>(it - valid.begin());
                if (col[k] >= 0)
                    throw InputError(
                        fmt::format("{}: column '{}' appears twice in the header", at, name));
                col[k] = static_cast<int>(i);
                header.push_back(name);
            }
            for (const std::size_t k : {c_name, c_speed, c_altitude})
                if (col[k] < 0)
                    throw InputError(fmt::format(
                        "{}:{}: missing column '{}' ({}); the header needs name, speed, altitude "
                        "(optional: inputs, climb_angle_deg); columns present: {}",
                        file, line_no, valid[k], case_columns()[k].second,
                        fmt::join(header, ", ")));
            continue;
        }
        if (rows.size() >= max_cases)
            throw InputError(fmt::format(
                "{}:{}: more than {} cases; a cases file holds at most {} (split the ensemble "
                "into several files)",
                file, line_no, max_cases, max_cases));
        if (fields.size() != header.size())
            throw InputError(fmt::format("{}:{}: row has {} fields; expected {} as in the header",
                                         file, line_no, fields.size(), header.size()));
        auto at = [&](std::size_t k) { return fmt::format("{}:{}:{}", file, line_no, col[k] + 1); };
        auto field = [&](std::size_t k) { return fields[static_cast<std::size_t>(col[k])]; };
        CaseRow c;
        c.line = line_no;
        c.name = std::string(field(c_name));
        if (c.name.empty())
            throw InputError(fmt::format(
                "{}: empty case name; every case needs a name (it names its output file)",
                at(c_name)));
        if (const std::string why = unsafe_case_name_reason(c.name); !why.empty())
            throw InputError(fmt::format(
                "{}: case name '{}' {}; names become file names (DIR/<name>.csv): use letters, "
                "digits, '_', '-' and '.' (not first)",
                at(c_name), c.name, why));
        const auto [first, fresh] = seen.try_emplace(lower(c.name), rows.size());
        if (!fresh) {
            const CaseRow& other = rows[first->second];
            throw InputError(fmt::format(
                "{}: case name '{}' repeats '{}' of line {}; names must be unique, ignoring "
                "upper/lower case (each names its output file)",
                at(c_name), c.name, other.name, other.line));
        }
        c.speed = parse_number(
            field(c_speed), [&] { return at(c_speed); }, "speed", "the true airspeed [m/s]");
        if (!(c.speed > 0.0))
            throw InputError(fmt::format("{}: speed {} m/s; expected a true airspeed > 0",
                                         at(c_speed), c.speed));
        c.altitude = parse_number(
            field(c_altitude), [&] { return at(c_altitude); }, "altitude", "the altitude [m]");
        if (col[c_climb] >= 0) {
            c.climb_angle_deg = parse_number(
                field(c_climb), [&] { return at(c_climb); }, "climb_angle_deg",
                "a flight-path angle [deg]");
            if (!(std::abs(c.climb_angle_deg) < 90.0))
                throw InputError(fmt::format(
                    "{}: climb_angle_deg {}; expected a flight-path angle in (-90, 90) deg",
                    at(c_climb), c.climb_angle_deg));
        }
        if (col[c_inputs] >= 0 && !field(c_inputs).empty()) {
            const std::string_view path = field(c_inputs);
            // The path goes into summary.json (JSON text is UTF-8) and names a file.
            if (const std::size_t bad = core::utf8_invalid_offset(path);
                bad != std::string_view::npos)
                throw InputError(fmt::format(
                    "{}: case '{}': inputs path '{}' is not valid UTF-8 ({} of the path); "
                    "expected a UTF-8 file name",
                    at(c_inputs), c.name, core::utf8_escaped(path),
                    core::describe_utf8_error(path, bad)));
            c.inputs = std::string(path);
            c.inputs_column = col[c_inputs] + 1;
            const std::filesystem::path p(c.inputs);
            c.inputs_path = p.is_absolute() ? p : base / p;
            if (read_inputs) {
                try {
                    c.inputs_text = read_inputs(c.inputs_path);
                } catch (const IoError& e) {
                    throw IoError(fmt::format("{}: case '{}': inputs file '{}' cannot be read: {}",
                                              at(c_inputs), c.name, c.inputs, e.what()));
                }
            }
        }
        rows.push_back(std::move(c));
    }
    if (header.empty())
        throw InputError(fmt::format(
            "{}: no header line; expected 'name,speed,altitude' (optional columns inputs, "
            "climb_angle_deg)",
            file));
    if (rows.empty())
        throw InputError(
            fmt::format("{}: no cases after the header (line {}); expected at least one row", file,
                        header_line));
    return rows;
}

std::vector<CaseRow> read_cases(const std::string& file) {
    return parse_cases(core::read_file(file), file,
                       [](const std::filesystem::path& p) { return core::read_file(p); });
}

}  // namespace manta::flightdyn
