/// @file trajectory.cpp
/// Trajectory CSV reader with located validation (trajectory.hpp).

#include "manta/replay/trajectory.hpp"
#include "manta/core/text.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <numbers>
#include <optional>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/core/utf8.hpp"

namespace manta::replay {

namespace {

constexpr double deg = std::numbers::pi / 180.0;

/// A column the reader knows: its name, whether required, and its physical range.
struct Known {
    const char* name;
    bool required;
    double lo, hi;       ///< allowed closed range
    const char* expect;  ///< the range in words
};

constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double tiny = 1e-9;  // rounding slack on the angle limits

const std::array<Known, 20> known{{
    {"t", true, -inf, inf, "a finite time"},
    {"x", true, -inf, inf, "a finite position"},
    {"y", true, -inf, inf, "a finite position"},
    {"z", true, -inf, inf, "a finite position"},
    {"phi", true, -inf, inf, "a finite angle"},
    {"theta", true, -90 * deg - tiny, 90 * deg + tiny, "|theta| <= pi/2 (90 deg)"},
    {"psi", true, -inf, inf, "a finite angle"},
    {"V", true, 1e-9, 1000.0, "0 < V <= 1000 m/s"},
    {"alpha", true, -90 * deg - tiny, 90 * deg + tiny, "|alpha| <= pi/2 (90 deg)"},
    {"beta", true, -90 * deg - tiny, 90 * deg + tiny, "|beta| <= pi/2 (90 deg)"},
    {"p", true, -20.0, 20.0, "|p| <= 20 rad/s"},
    {"q", true, -20.0, 20.0, "|q| <= 20 rad/s"},
    {"r", true, -20.0, 20.0, "|r| <= 20 rad/s"},
    {"elevator", true, -90 * deg - tiny, 90 * deg + tiny, "|elevator| <= pi/2 rad (90 deg)"},
    {"aileron", true, -90 * deg - tiny, 90 * deg + tiny, "|aileron| <= pi/2 rad (90 deg)"},
    {"rudder", true, -90 * deg - tiny, 90 * deg + tiny, "|rudder| <= pi/2 rad (90 deg)"},
    // Throttle is not used by a replay; interpolated files overshoot [0, 1] slightly.
    {"throttle", false, -0.05, 1.05, "a throttle setting in [0, 1] (+- 0.05)"},
    {"mach", false, 0.0, 5.0, "0 <= mach <= 5"},
    {"phase", false, 0.0, 1e6, "a phase index >= 0"},
    {"", false, 0, 0, ""},
}};

}  // namespace

std::string Trajectory::meta(const std::string& key, const std::string& fallback) const {
    const auto it = metadata.find(key);
    return it == metadata.end() ? fallback : it->second;
}

Trajectory parse_trajectory(std::string_view text, std::string source) {
    core::require_utf8_text(text, source);
    Trajectory tr;
    tr.source = source;
    std::vector<std::string_view> header;
    int header_line = 0;
    std::vector<int> col(known.size(), -1);  // known column -> field index
    std::vector<std::vector<double>> values(known.size());
    int line_no = 0;
    std::size_t pos = 0;
    while (pos <= text.size()) {
        const std::size_t e = text.find('\n', pos);
        std::string_view line =
            text.substr(pos, e == std::string_view::npos ? std::string_view::npos : e - pos);
        pos = e == std::string_view::npos ? text.size() + 1 : e + 1;
        ++line_no;
        line = core::trim_blanks(line);
        if (line.empty()) continue;
        if (line.front() == '#') {
            const std::string_view body = core::trim_blanks(line.substr(1));
            const std::size_t c = body.find(':');
            if (c != std::string_view::npos && c > 0 &&
                body.substr(0, c).find(' ') == std::string_view::npos)
                tr.metadata[std::string(body.substr(0, c))] =
                    std::string(core::trim_blanks(body.substr(c + 1)));
            continue;
        }
        if (header.empty()) {
            header = core::split_fields(line);
            header_line = line_no;
            std::string missing;
            for (std::size_t k = 0; k + 1 < known.size(); ++k) {
                for (std::size_t f = 0; f < header.size(); ++f)
                    if (header[f] == known[k].name) {
                        if (col[k] >= 0)
                            throw InputError(fmt::format(
                                "{}:{}: column '{}' appears twice (columns {} and {}); expected "
                                "each column once",
                                source, line_no, known[k].name, col[k] + 1, f + 1));
                        col[k] = static_cast<int>(f);
                    }
                if (known[k].required && col[k] < 0) {
                    if (!missing.empty()) missing += ", ";
                    missing += known[k].name;
                }
            }
            if (!missing.empty())
                throw InputError(fmt::format(
                    "{}:{}: missing column(s) {}; expected t, x, y, z, phi, theta, psi, V, alpha, "
                    "beta, p, q, r, elevator, aileron, rudder (docs/formats.md#trajectory-csv)",
                    source, line_no, missing));
            continue;
        }
        const std::vector<std::string_view> f = core::split_fields(line);
        for (std::size_t k = 0; k + 1 < known.size(); ++k) {
            if (col[k] < 0) continue;
            const auto c = static_cast<std::size_t>(col[k]);
            if (c >= f.size())
                throw InputError(fmt::format(
                    "{}:{}: row of {} fields has no column {} '{}'; expected {} fields as the "
                    "header",
                    source, line_no, f.size(), c + 1, known[k].name, header.size()));
            const std::string_view s = f[c];
            double v = 0.0;
            const char* b = s.data();
            if (!s.empty() && *b == '+') ++b;
            const auto [ptr, ec] = std::from_chars(b, s.data() + s.size(), v);
            if (s.empty() || ec != std::errc() || ptr != s.data() + s.size())
                throw InputError(fmt::format("{}:{}, column {} '{}': '{}' is not a number", source,
                                             line_no, c + 1, known[k].name, s));
            if (!std::isfinite(v))
                throw InputError(fmt::format("{}:{}, column {} '{}': {}; expected a finite number",
                                             source, line_no, c + 1, known[k].name, s));
            if (!(v >= known[k].lo && v <= known[k].hi))
                throw InputError(fmt::format("{}:{}, column {} '{}': {} out of range; expected {}",
                                             source, line_no, c + 1, known[k].name, s,
                                             known[k].expect));
            if (std::string_view(known[k].name) == "phase" && v != std::floor(v))
                throw InputError(
                    fmt::format("{}:{}, column {} 'phase': {}; expected an integer phase index",
                                source, line_no, c + 1, s));
            if (k == 0 && !values[0].empty() && !(v > values[0].back()))
                throw InputError(fmt::format(
                    "{}:{}, column {} 't': time {} s {} the {} s of line {}; expected strictly "
                    "increasing times",
                    source, line_no, c + 1, s, v == values[0].back() ? "repeats" : "goes back from",
                    values[0].back(), tr.line.back()));
            values[k].push_back(v);
        }
        tr.line.push_back(line_no);
    }
    if (header.empty())
        throw InputError(
            fmt::format("{}: no header line; expected a trajectory CSV "
                        "(docs/formats.md#trajectory-csv)",
                        source));
    if (tr.line.size() < 2)
        throw InputError(fmt::format("{}:{}: {} data row(s); expected at least 2", source,
                                     header_line, tr.line.size()));
    auto take = [&](const char* name) {
        for (std::size_t k = 0; k < known.size(); ++k)
            if (std::string_view(known[k].name) == name) return std::move(values[k]);
        return std::vector<double>{};
    };
    tr.t = take("t");
    tr.position = {take("x"), take("y"), take("z")};
    tr.euler = {take("phi"), take("theta"), take("psi")};
    tr.V = take("V");
    tr.alpha = take("alpha");
    tr.beta = take("beta");
    tr.rates = {take("p"), take("q"), take("r")};
    tr.controls = {take("elevator"), take("aileron"), take("rudder")};
    tr.throttle = take("throttle");
    tr.mach = take("mach");
    for (const double v : take("phase")) tr.phase.push_back(static_cast<int>(v));
    if (const auto it = tr.metadata.find("phases"); it != tr.metadata.end()) {
        std::string_view s = it->second;
        while (true) {
            const std::size_t c = s.find(',');
            const std::string_view n = core::trim_blanks(s.substr(0, c));
            if (!n.empty()) tr.phase_names.emplace_back(n);
            if (c == std::string_view::npos) break;
            s.remove_prefix(c + 1);
        }
    }
    return tr;
}

Trajectory read_trajectory(const std::filesystem::path& file) {
    return parse_trajectory(core::read_file(file), file.string());
}

}  // namespace manta::replay
