/// @file motion.cpp
/// Motion histories: validation, the motion file (docs/formats.md, "Motion file"), C1 cubic
/// Hermite interpolation with body rates, and forced-oscillation histories.
/// Numbers are written with core::format_exact and read back by core::parse_csv (std::from_chars),
/// so a written motion reads back bit for bit.

#include "manta/aero/motion.hpp"
#include "manta/core/text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "manta/core/error.hpp"
#include "manta/core/frames.hpp"
#include "manta/core/io.hpp"
#include "manta/core/utf8.hpp"

namespace manta::aero {

namespace {

constexpr std::array<std::string_view, 3> position_columns{"x_ref", "y_ref", "z_ref"};
constexpr std::array<std::string_view, 3> angle_columns{"phi", "theta", "psi"};
constexpr std::array<std::string_view, 3> required_modes{"elevator", "aileron", "rudder"};
constexpr std::string_view mode_prefix = "mode_";

/// The metadata keys with a meaning.
enum class MetaKey { v0, mach, altitude };
constexpr std::array<std::pair<std::string_view, MetaKey>, 3> meta_keys{
    {{"v0", MetaKey::v0}, {"mach", MetaKey::mach}, {"altitude", MetaKey::altitude}}};

/// If `comment` (text after '#') is `key: value` with a known key, that key and the value text.
std::optional<std::pair<MetaKey, std::string_view>> split_metadata(std::string_view comment) {
    const std::size_t colon = comment.find(':');
    if (colon == std::string_view::npos) return std::nullopt;
    const std::string_view key = core::trim_blanks(comment.substr(0, colon));
    for (const auto& [name, k] : meta_keys) {
        if (key == name) return std::pair{k, core::trim_blanks(comment.substr(colon + 1))};
    }
    return std::nullopt;
}

std::string_view meta_name(MetaKey k) {
    for (const auto& [name, key] : meta_keys) {
        if (key == k) return name;
    }
    return "?";
}

/// The field of `m` holding key `k` (`M` is MotionMetadata, const or not).
template <class M>
auto& meta_slot(M& m, MetaKey k) {
    switch (k) {
        case MetaKey::v0:
            return m.v0;
        case MetaKey::mach:
            return m.mach;
        case MetaKey::altitude:
            break;
    }
    return m.altitude;
}

/// Why a metadata value is out of range, or empty.
std::string meta_range_problem(MetaKey k, double v) {
    if (!std::isfinite(v)) return "is not finite; expected a finite number";
    if (k == MetaKey::v0 && !(v > 0.0)) return "must be positive (free-stream speed in m/s)";
    if (k == MetaKey::mach && !(v >= 0.0)) return "must not be negative";
    return {};
}

bool is_valid_mode_name(std::string_view name) {
    if (name.empty()) return false;
    return std::all_of(name.begin(), name.end(), [](char ch) {
        const auto c = static_cast<unsigned char>(ch);
        return std::isalnum(c) != 0 || ch == '_';
    });
}

/// Where row `i` is, for messages: `source:line` for a file, `source: row i` otherwise.
struct RowLocator {
    std::string_view source;
    const std::vector<int>* lines = nullptr;
    [[nodiscard]] std::string operator()(std::size_t i) const {
        if (lines != nullptr && i < lines->size()) return fmt::format("{}:{}", source, (*lines)[i]);
        return fmt::format("{}: row {}", source, i + 1);
    }
};

// Plausible ranges of the motion columns (issue 16, defect 5): a value beyond them is a unit slip
// or a broken file, never a motion to fly. Attitude angles may accumulate (an unwrapped heading in
// a sustained turn passes 2 pi), so their bound is 100 rad, about 16 turns; a control deflection
// beyond 90 deg is no deflection of a hinged surface; the reference point moves in a frame that
// travels with the entry flight, so it stays within 100 km of its origin; times within 10^6 s.
constexpr double max_abs_attitude = 100.0;
constexpr double max_abs_deflection = std::numbers::pi / 2.0;
constexpr double max_abs_position = 1e5;
constexpr double max_abs_time = 1e6;

/// " (degrees typed as radians? 5 rad would be 286.5 deg)" when `v` reads as a plausible
/// number of degrees, else "".
std::string degree_slip(double v) {
    if (std::abs(v) > 360.0) return {};
    return fmt::format(
        " (degrees typed as radians? {} rad would be {:.1f} deg; {} deg is {:.4f} rad)",
        core::format_exact(v), v * 180.0 / std::numbers::pi, core::format_exact(v),
        v * std::numbers::pi / 180.0);
}

template <class Locator>
void check_range(const std::vector<double>& v, std::string_view name, double limit,
                 std::string_view unit, const Locator& at_row, std::string_view note) {
    for (std::size_t i = 0; i < v.size(); ++i) {
        if (std::abs(v[i]) <= limit) continue;
        throw InputError(fmt::format(
            "{}: column '{}' value {} {} is outside the plausible range [-{:g}, {:g}] {}{}{}",
            at_row(i), name, core::format_exact(v[i]), unit, limit, limit, unit, note,
            unit == "rad" ? degree_slip(v[i]) : std::string()));
    }
}

/// The invariants of a motion; `header` is where whole-column problems are reported.
void check_motion(const Motion& m, const RowLocator& at_row, const std::string& header) {
    const std::size_t n = m.t.size();
    if (n < 2) {
        throw InputError(
            fmt::format("{}: column 't' has {} row{}; a motion needs at least 2 samples", header, n,
                        n == 1 ? "" : "s"));
    }
    const auto check_column = [&](const std::vector<double>& v, std::string_view name) {
        if (v.size() != n) {
            throw InputError(fmt::format("{}: column '{}' has {} values; expected {} as column 't'",
                                         header, name, v.size(), n));
        }
        for (std::size_t i = 0; i < n; ++i) {
            if (!std::isfinite(v[i])) {
                throw InputError(
                    fmt::format("{}: column '{}' value {} is not finite; expected a finite number",
                                at_row(i), name, v[i]));
            }
        }
    };
    check_column(m.t, "t");
    for (std::size_t i = 1; i < n; ++i) {
        if (!(m.t[i] > m.t[i - 1])) {
            throw InputError(fmt::format(
                "{}: column 't' value {} is not greater than the previous time {}; times must "
                "increase strictly",
                at_row(i), core::format_exact(m.t[i]), core::format_exact(m.t[i - 1])));
        }
    }
    check_range(m.t, "t", max_abs_time, "s", at_row, "");
    for (std::size_t k = 0; k < 3; ++k) {
        check_column(m.position[k], position_columns[k]);
        check_range(m.position[k], position_columns[k], max_abs_position, "m", at_row, "");
    }
    for (std::size_t k = 0; k < 3; ++k) {
        check_column(m.angles[k], angle_columns[k]);
        check_range(m.angles[k], angle_columns[k], max_abs_attitude, "rad", at_row,
                    " (about 16 turns, unwrapped)");
    }
    if (m.modes.size() != m.mode_names.size()) {
        throw InputError(fmt::format("{}: {} mode names but {} mode columns", header,
                                     m.mode_names.size(), m.modes.size()));
    }
    for (std::size_t k = 0; k < m.modes.size(); ++k) {
        const std::string& name = m.mode_names[k];
        if (!is_valid_mode_name(name)) {
            throw InputError(fmt::format(
                "{}: mode name '{}' is not valid; expected letters, digits and '_' (column "
                "'mode_<name>')",
                header, name));
        }
        for (std::size_t j = 0; j < k; ++j) {
            if (m.mode_names[j] == name)
                throw InputError(fmt::format("{}: mode '{}' appears twice", header, name));
        }
        const std::string column = fmt::format("{}{}", mode_prefix, name);
        check_column(m.modes[k], column);
        for (std::size_t i = 0; i < n; ++i) {
            const double v = m.modes[k][i];
            if (std::abs(v) > max_abs_deflection) {
                throw InputError(fmt::format(
                    "{}: column '{}' value {} rad is outside the plausible range of a control "
                    "deflection [-{:.4f}, {:.4f}] rad (+-90 deg){}; expected radians",
                    at_row(i), column, core::format_exact(v), max_abs_deflection,
                    max_abs_deflection, degree_slip(v)));
            }
        }
    }
    std::vector<std::string> missing;
    for (const std::string_view name : required_modes) {
        if (m.find_mode(name) < 0) missing.push_back(fmt::format("'{}{}'", mode_prefix, name));
    }
    if (!missing.empty()) {
        throw InputError(
            fmt::format("{}: missing mode column{} {}; a motion needs mode_elevator, "
                        "mode_aileron and mode_rudder",
                        header, missing.size() == 1 ? "" : "s", fmt::join(missing, ", ")));
    }
}

void check_metadata(const MotionMetadata& meta, std::string_view source) {
    for (const auto& [name, key] : meta_keys) {
        const std::optional<double>& v = meta_slot(meta, key);
        if (!v) continue;
        const std::string problem = meta_range_problem(key, *v);
        if (!problem.empty()) {
            throw InputError(
                fmt::format("{}: metadata '{}' value {} {}", source, name, *v, problem));
        }
    }
    for (const std::string& c : meta.comments) {
        if (c.find_first_of("\r\n") != std::string::npos) {
            throw InputError(
                fmt::format("{}: comment starting '{}' holds a line break; expected one line",
                            source, std::string_view(c).substr(0, c.find_first_of("\r\n"))));
        }
        if (core::trim_blanks(c) != c) {
            throw InputError(fmt::format(
                "{}: comment '{}' has leading or trailing blanks; they would not survive a "
                "round trip",
                source, c));
        }
        if (const auto kv = split_metadata(c)) {
            throw InputError(fmt::format(
                "{}: comment '{}' would read back as metadata '{}'; set the metadata field instead",
                source, c, meta_name(kv->first)));
        }
    }
}

/// Comment lines of a CSV text with their line numbers, and the header line, found with the
/// same rules as core::parse_csv (lines trimmed; blank lines skipped; '#' starts a comment).
struct TextLayout {
    int header_line = 0;
    std::vector<std::pair<int, std::string_view>> comments;  ///< text after '#', trimmed
};

TextLayout scan_layout(std::string_view text) {
    TextLayout out;
    int line_no = 0;
    std::size_t pos = 0;
    while (pos <= text.size()) {
        const std::size_t nl = text.find('\n', pos);
        std::string_view line =
            text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
        pos = nl == std::string_view::npos ? text.size() + 1 : nl + 1;
        ++line_no;
        line = core::trim_blanks(line);
        if (line.empty()) continue;
        if (line.front() == '#') {
            out.comments.emplace_back(line_no, core::trim_blanks(line.substr(1)));
        } else if (out.header_line == 0) {
            out.header_line = line_no;
        }
    }
    return out;
}

double parse_meta_number(std::string_view value, std::string_view where, MetaKey key) {
    const std::string_view digits =
        value.size() > 1 && value.front() == '+' && value[1] != '-' && value[1] != '+'
            ? value.substr(1)
            : value;
    double v = 0.0;
    const auto r = std::from_chars(digits.data(), digits.data() + digits.size(), v);
    if (value.empty() || r.ec != std::errc() || r.ptr != digits.data() + digits.size()) {
        throw InputError(
            fmt::format("{}: metadata '{}' value '{}' is not a number; expected "
                        "'# {}: <number>'",
                        where, meta_name(key), value, meta_name(key)));
    }
    const std::string problem = meta_range_problem(key, v);
    if (!problem.empty()) {
        throw InputError(
            fmt::format("{}: metadata '{}' value '{}' {}", where, meta_name(key), value, problem));
    }
    return v;
}

std::string motion_text(const Motion& m, std::string_view source) {
    m.validate(source);
    std::vector<std::string> columns{"t"};
    for (const auto c : position_columns) columns.emplace_back(c);
    for (const auto c : angle_columns) columns.emplace_back(c);
    for (const auto& name : m.mode_names) columns.push_back(fmt::format("{}{}", mode_prefix, name));
    std::vector<std::string> comments;
    for (const auto& [name, key] : meta_keys) {
        const std::optional<double>& v = meta_slot(m.metadata, key);
        if (v) comments.push_back(fmt::format("{}: {}", name, core::format_exact(*v)));
    }
    comments.insert(comments.end(), m.metadata.comments.begin(), m.metadata.comments.end());
    std::vector<std::vector<double>> rows(m.t.size());
    for (std::size_t i = 0; i < m.t.size(); ++i) {
        auto& r = rows[i];
        r.reserve(columns.size());
        r.push_back(m.t[i]);
        for (const auto& c : m.position) r.push_back(c[i]);
        for (const auto& c : m.angles) r.push_back(c[i]);
        for (const auto& c : m.modes) r.push_back(c[i]);
    }
    return core::to_csv(columns, rows, comments);
}

/// Weights of the finite-difference slope at node i: f'(t_i) ~ sum_j w[j] f[start + j], the
/// derivative at t_i of the Lagrange polynomial through the (up to) five nearest nodes.
struct SlopeStencil {
    std::size_t start = 0;
    std::size_t count = 0;
    std::array<double, 5> w{};
    [[nodiscard]] double apply(const std::vector<double>& f) const {
        double s = 0.0;
        for (std::size_t j = 0; j < count; ++j) s += w[j] * f[start + j];
        return s;
    }
};

SlopeStencil slope_stencil(const std::vector<double>& t, std::size_t i) {
    const std::size_t n = t.size();
    SlopeStencil s;
    s.count = std::min<std::size_t>(n, 5);
    s.start = std::min(i >= 2 ? i - 2 : 0, n - s.count);
    const double ti = t[i];
    for (std::size_t a = 0; a < s.count; ++a) {
        const std::size_t j = s.start + a;
        if (j == i) {
            // L_i'(t_i) = sum_{k != i} 1 / (t_i - t_k)
            double sum = 0.0;
            for (std::size_t b = 0; b < s.count; ++b) {
                const std::size_t k = s.start + b;
                if (k != i) sum += 1.0 / (ti - t[k]);
            }
            s.w[a] = sum;
        } else {
            // L_j'(t_i) = prod_{k != i, j} (t_i - t_k) / prod_{k != j} (t_j - t_k)
            double num = 1.0;
            double den = 1.0;
            for (std::size_t b = 0; b < s.count; ++b) {
                const std::size_t k = s.start + b;
                if (k == j) continue;
                den *= t[j] - t[k];
                if (k != i) num *= ti - t[k];
            }
            s.w[a] = num / den;
        }
    }
    return s;
}

}  // namespace

// ---------------------------------------------------------------- Motion

int Motion::find_mode(std::string_view name) const {
    const auto it = std::find(mode_names.begin(), mode_names.end(), name);
    return it == mode_names.end() ? -1 : static_cast<int>(it - mode_names.begin());
}

void Motion::add_mode(std::string name, std::vector<double> values) {
    mode_names.push_back(std::move(name));
    modes.push_back(std::move(values));
}

void Motion::validate(std::string_view source) const {
    check_motion(*this, RowLocator{source, nullptr}, std::string(source));
    check_metadata(metadata, source);
}

double Motion::default_clamp_tolerance() const {
    return t.size() < 2 ? 0.0 : 1e-6 * (t.back() - t.front());
}

MotionState Motion::at(double time) const {
    return at(time, default_clamp_tolerance());
}

MotionState Motion::at(double time, double clamp_tolerance) const {
    const std::size_t n = t.size();
    MANTA_REQUIRE(n >= 2, "Motion::at needs a motion of at least 2 samples");
    // Cheap guard against out-of-bounds reads; the full check is validate().
    const auto sized = [n](const std::vector<double>& c) { return c.size() == n; };
    MANTA_REQUIRE(std::all_of(position.begin(), position.end(), sized) &&
                      std::all_of(angles.begin(), angles.end(), sized) &&
                      std::all_of(modes.begin(), modes.end(), sized),
                  "Motion::at needs columns as long as t (see Motion::validate)");
    if (!std::isfinite(time))
        throw InputError(fmt::format("Motion::at: time {} is not finite", time));
    if (!(clamp_tolerance >= 0.0) || !std::isfinite(clamp_tolerance))
        throw InputError(fmt::format("Motion::at: clamping tolerance {} s must be finite and >= 0",
                                     clamp_tolerance));
    MotionState s;
    s.t = time;
    if (time < t.front() || time > t.back()) {
        const double excess = time < t.front() ? t.front() - time : time - t.back();
        if (excess > clamp_tolerance) {
            throw InputError(fmt::format(
                "Motion::at: t = {} s lies {} s outside the motion's time range [{}, {}] s; at "
                "most {} s is clamped",
                time, excess, t.front(), t.back(), clamp_tolerance));
        }
        s.t = std::clamp(time, t.front(), t.back());
        s.clamped = true;
    }

    // Interval [t_i, t_i+1] holding s.t (the last interval for s.t == tN).
    const auto it = std::upper_bound(t.begin(), t.end(), s.t);
    const std::size_t i =
        std::min(static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - t.begin(), 1)) - 1, n - 2);
    const double h = t[i + 1] - t[i];
    const double u = (s.t - t[i]) / h;
    const double u2 = u * u, u3 = u2 * u;
    // Cubic Hermite basis and its derivative with respect to u.
    const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2,
                 h11 = u3 - u2;
    const double d00 = 6 * u2 - 6 * u, d10 = 3 * u2 - 4 * u + 1, d01 = -d00, d11 = 3 * u2 - 2 * u;
    const SlopeStencil left = slope_stencil(t, i);
    const SlopeStencil right = slope_stencil(t, i + 1);
    const auto eval = [&](const std::vector<double>& f, double& value, double& rate) {
        const double m0 = left.apply(f), m1 = right.apply(f);
        value = h00 * f[i] + h10 * h * m0 + h01 * f[i + 1] + h11 * h * m1;
        rate = (d00 * f[i] + d01 * f[i + 1]) / h + d10 * m0 + d11 * m1;
    };
    for (std::size_t k = 0; k < 3; ++k) {
        eval(position[k], s.position[k], s.velocity[k]);
        eval(angles[k], s.euler[k], s.euler_rates[k]);
    }
    s.modes.resize(modes.size());
    s.mode_rates.resize(modes.size());
    for (std::size_t k = 0; k < modes.size(); ++k) eval(modes[k], s.modes[k], s.mode_rates[k]);
    s.omega_body = core::body_rates_from_euler_rates(s.euler, s.euler_rates);
    return s;
}

// ---------------------------------------------------------------- file

Motion parse_motion(std::string_view text, std::string source) {
    core::require_utf8_text(text, source);
    const core::CsvTable table = core::parse_csv(text, source);
    const TextLayout layout = scan_layout(text);
    const std::string header = fmt::format("{}:{}", source, layout.header_line);

    // Columns: the required ones, any number of mode_<name>, nothing else.
    std::vector<std::string> required{"t"};
    for (const auto c : position_columns) required.emplace_back(c);
    for (const auto c : angle_columns) required.emplace_back(c);
    for (const auto c : required_modes) required.push_back(fmt::format("{}{}", mode_prefix, c));
    for (const std::string& c : table.columns) {
        const bool is_mode = c.size() > mode_prefix.size() && c.starts_with(mode_prefix);
        if (std::find(required.begin(), required.end(), c) == required.end() && !is_mode) {
            throw InputError(
                fmt::format("{}: column '{}' is not a motion column; expected {} and optional "
                            "mode_<name> columns",
                            header, c, fmt::join(required, ", ")));
        }
        if (is_mode && !is_valid_mode_name(std::string_view(c).substr(mode_prefix.size()))) {
            throw InputError(fmt::format(
                "{}: column '{}' is not a valid mode name; expected mode_<name> with letters, "
                "digits and '_'",
                header, c));
        }
    }
    std::vector<std::string> missing;
    for (const std::string& c : required) {
        if (table.find(c) < 0) missing.push_back(fmt::format("'{}'", c));
    }
    if (!missing.empty()) {
        throw InputError(fmt::format("{}: missing column{} {}; columns present: {}", header,
                                     missing.size() == 1 ? "" : "s", fmt::join(missing, ", "),
                                     fmt::join(table.columns, ", ")));
    }

    Motion m;
    m.t = table.column(table.require("t"));
    for (std::size_t k = 0; k < 3; ++k) {
        m.position[k] = table.column(table.require(position_columns[k]));
        m.angles[k] = table.column(table.require(angle_columns[k]));
    }
    for (std::size_t c = 0; c < table.columns.size(); ++c) {
        const std::string& name = table.columns[c];
        if (name.starts_with(mode_prefix))
            m.add_mode(name.substr(mode_prefix.size()), table.column(c));
    }

    // Metadata lines, with their line numbers for messages.
    std::array<int, meta_keys.size()> seen_on{};
    for (const auto& [line, comment] : layout.comments) {
        const auto kv = split_metadata(comment);
        if (!kv) {
            // A carriage return inside the line would be a line break once written back
            // (issue 16, found by fuzz_motion): refused here rather than by the writer.
            if (comment.find('\r') != std::string_view::npos) {
                throw InputError(fmt::format(
                    "{}:{}: comment '{}' holds a carriage return inside the line; expected one "
                    "line ending in LF or CR LF",
                    source, line, comment));
            }
            m.metadata.comments.emplace_back(comment);
            continue;
        }
        const auto [key, value] = *kv;
        const std::string where = fmt::format("{}:{}", source, line);
        int& seen = seen_on[static_cast<std::size_t>(key)];
        if (seen != 0) {
            throw InputError(fmt::format("{}: metadata '{}' given twice (first on line {})", where,
                                         meta_name(key), seen));
        }
        seen = line;
        meta_slot(m.metadata, key) = parse_meta_number(value, where, key);
    }

    check_motion(m, RowLocator{source, &table.row_lines}, header);
    return m;
}

Motion read_motion(const std::filesystem::path& file) {
    return parse_motion(core::read_file(file), file.string());
}

std::string motion_to_text(const Motion& motion) {
    return motion_text(motion, "motion");
}

void write_motion(const std::filesystem::path& file, const Motion& motion) {
    core::write_file_atomic(file, motion_text(motion, file.string()));
}

void check_mode_limits(const Motion& motion, const std::vector<ModeLimit>& limits,
                       std::string_view source) {
    for (const ModeLimit& l : limits) {
        const int k = motion.find_mode(l.name);
        if (k < 0) continue;
        const std::vector<double>& v = motion.modes[static_cast<std::size_t>(k)];
        for (std::size_t i = 0; i < v.size() && i < motion.t.size(); ++i) {
            if (v[i] >= l.lower && v[i] <= l.upper) continue;
            throw InputError(fmt::format(
                "{}: mode '{}' = {} rad at t = {} s is outside the aircraft's limits [{:.4f}, "
                "{:.4f}] rad ([{:.1f}, {:.1f}] deg){}",
                source, l.name, core::format_exact(v[i]), core::format_exact(motion.t[i]), l.lower,
                l.upper, l.lower * 180.0 / std::numbers::pi, l.upper * 180.0 / std::numbers::pi,
                std::abs(v[i]) > std::max(std::abs(l.lower), std::abs(l.upper)) * 3.0
                    ? degree_slip(v[i])
                    : std::string()));
        }
    }
}

// ---------------------------------------------------------------- forced oscillation

std::string_view to_string(OscillationAxis axis) {
    switch (axis) {
        case OscillationAxis::roll:
            return "roll";
        case OscillationAxis::pitch:
            return "pitch";
        case OscillationAxis::yaw:
            return "yaw";
        case OscillationAxis::plunge:
            break;
    }
    return "plunge";
}

Motion harmonic_motion(OscillationAxis axis, double amplitude, double omega, int n_periods,
                       int samples_per_period, double mean, MotionMetadata metadata) {
    if (!(omega > 0.0) || !std::isfinite(omega))
        throw InputError(fmt::format("harmonic_motion: omega = {} rad/s; expected > 0", omega));
    if (n_periods < 1)
        throw InputError(fmt::format("harmonic_motion: n_periods = {}; expected >= 1", n_periods));
    if (samples_per_period < 4) {
        throw InputError(fmt::format("harmonic_motion: samples_per_period = {}; expected >= 4",
                                     samples_per_period));
    }
    if (!std::isfinite(amplitude) || !std::isfinite(mean)) {
        throw InputError(fmt::format("harmonic_motion: amplitude {} and mean {} must be finite",
                                     amplitude, mean));
    }
    const auto m = static_cast<std::size_t>(samples_per_period);
    const std::size_t n = static_cast<std::size_t>(n_periods) * m + 1;
    const double period = 2.0 * std::numbers::pi / omega;

    Motion mo;
    mo.metadata = std::move(metadata);
    mo.t.resize(n);
    for (auto& c : mo.position) c.assign(n, 0.0);
    for (auto& c : mo.angles) c.assign(n, 0.0);
    for (const auto name : required_modes) mo.add_mode(std::string(name), std::vector<double>(n));
    std::vector<double>& moving = axis == OscillationAxis::roll    ? mo.angles[0]
                                  : axis == OscillationAxis::pitch ? mo.angles[1]
                                  : axis == OscillationAxis::yaw   ? mo.angles[2]
                                                                   : mo.position[2];
    for (std::size_t i = 0; i < n; ++i) {
        mo.t[i] = period * static_cast<double>(i) / static_cast<double>(m);
        const double phase =
            2.0 * std::numbers::pi * static_cast<double>(i % m) / static_cast<double>(m);
        moving[i] = mean + amplitude * std::sin(phase);
    }
    mo.validate("harmonic_motion");
    return mo;
}

}  // namespace manta::aero
