/// @file text_csv.cpp
/// Text CSV and JSON readers with located errors.

#include "manta/report/text_csv.hpp"
#include "manta/core/text.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <charconv>
#include <cmath>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"

namespace manta::report {

namespace {

/// Split one record starting at `pos` (which may span lines inside quotes); advances `pos` past
/// the record's newline and `line` by the newlines consumed.
std::vector<std::string> split_record(std::string_view text, std::size_t& pos, int& line,
                                      const std::string& source) {
    std::vector<std::string> fields;
    std::string field;
    bool quoted = false;      // inside a quoted section
    bool was_quoted = false;  // this field had quotes (keep its spaces)
    const int start_line = line;
    while (pos < text.size()) {
        const char c = text[pos++];
        if (quoted) {
            if (c == '"') {
                if (pos < text.size() && text[pos] == '"') {
                    field += '"';
                    ++pos;
                } else {
                    quoted = false;
                }
            } else {
                if (c == '\n') ++line;
                field += c;
            }
            continue;
        }
        if (c == '"') {
            quoted = true;
            was_quoted = true;
        } else if (c == ',') {
            fields.emplace_back(was_quoted ? field : std::string(core::trim_blanks(field)));
            field.clear();
            was_quoted = false;
        } else if (c == '\n') {
            ++line;
            break;
        } else if (c != '\r') {  // CRLF files: the CR is not part of the last field
            field += c;
        }
    }
    if (quoted)
        throw InputError(fmt::format("{}:{}: column {}: quoted field is not closed", source,
                                     start_line, fields.size() + 1));
    fields.emplace_back(was_quoted ? field : std::string(core::trim_blanks(field)));
    return fields;
}

}  // namespace

int TextCsv::find(std::string_view name) const {
    const auto it = std::find(columns.begin(), columns.end(), name);
    return it == columns.end() ? -1 : static_cast<int>(it - columns.begin());
}

std::size_t TextCsv::require(std::string_view name) const {
    const int i = find(name);
    if (i < 0)
        throw InputError(fmt::format("{}: missing column '{}'; columns present: {}", source, name,
                                     fmt::join(columns, ",")));
    return static_cast<std::size_t>(i);
}

double TextCsv::number(std::size_t row, std::size_t column) const {
    const std::string& f = rows.at(row).at(column);
    const std::string_view digits =
        f.size() > 1 && f.front() == '+' ? std::string_view(f).substr(1) : std::string_view(f);
    double v = 0.0;
    const auto r = std::from_chars(digits.data(), digits.data() + digits.size(), v);
    if (f.empty() || r.ec != std::errc() || r.ptr != digits.data() + digits.size())
        throw InputError(fmt::format("{}:{}: column {} '{}' value '{}' is not a number", source,
                                     row_lines[row], column + 1, columns[column], f));
    if (!std::isfinite(v))
        throw InputError(fmt::format("{}:{}: column {} '{}' value '{}' is not finite", source,
                                     row_lines[row], column + 1, columns[column], f));
    return v;
}

TextCsv parse_text_csv(std::string_view text, std::string source) {
    TextCsv t;
    t.source = std::move(source);
    std::size_t pos = 0;
    int line = 1;
    bool have_header = false;
    while (pos < text.size()) {
        // Comment and blank lines are recognised at the start of a record only.
        const std::size_t nl = text.find('\n', pos);
        const std::string_view raw = core::trim_blanks(
            text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos));
        if (raw.empty() || (!have_header && raw.front() == '#')) {
            if (!raw.empty()) t.comments.emplace_back(core::trim_blanks(raw.substr(1)));
            pos = nl == std::string_view::npos ? text.size() : nl + 1;
            ++line;
            continue;
        }
        const int record_line = line;
        auto fields = split_record(text, pos, line, t.source);
        if (!have_header) {
            for (std::size_t i = 0; i < fields.size(); ++i) {
                if (fields[i].empty())
                    throw InputError(fmt::format("{}:{}: column {} of the header is empty",
                                                 t.source, record_line, i + 1));
                if (std::find(fields.begin(), fields.begin() + static_cast<std::ptrdiff_t>(i),
                              fields[i]) != fields.begin() + static_cast<std::ptrdiff_t>(i))
                    throw InputError(
                        fmt::format("{}:{}: column {} '{}' appears twice in the header", t.source,
                                    record_line, i + 1, fields[i]));
            }
            t.columns = std::move(fields);
            have_header = true;
            continue;
        }
        if (fields.size() != t.columns.size())
            throw InputError(fmt::format("{}:{}: row has {} fields; expected {} as in the header",
                                         t.source, record_line, fields.size(), t.columns.size()));
        t.rows.push_back(std::move(fields));
        t.row_lines.push_back(record_line);
    }
    if (!have_header)
        throw InputError(fmt::format(
            "{}: no header line found; expected comma-separated column names", t.source));
    return t;
}

TextCsv read_text_csv(const std::filesystem::path& file) {
    return parse_text_csv(core::read_file(file), file.string());
}

nlohmann::json parse_json(std::string_view text, const std::string& source) {
    try {
        return nlohmann::json::parse(text.begin(), text.end());
    } catch (const nlohmann::json::parse_error& e) {
        // Locate the byte nlohmann stopped at (1-based line and column).
        const std::size_t at = std::min<std::size_t>(e.byte > 0 ? e.byte - 1 : 0, text.size());
        int line = 1;
        std::size_t line_start = 0;
        for (std::size_t i = 0; i < at; ++i)
            if (text[i] == '\n') {
                ++line;
                line_start = i + 1;
            }
        std::string reason = e.what();
        // Drop nlohmann's "[json.exception.parse_error.101] parse error at line L, column C: ".
        if (const auto k = reason.find(": "); k != std::string::npos) reason = reason.substr(k + 2);
        if (const auto k = reason.find("; last read"); k != std::string::npos)
            reason = reason.substr(0, k);
        throw InputError(
            fmt::format("{}:{}:{}: invalid JSON: {}", source, line, at - line_start + 1, reason));
    }
}

nlohmann::json read_json(const std::filesystem::path& file) {
    return parse_json(core::read_file(file), file.string());
}

}  // namespace manta::report
