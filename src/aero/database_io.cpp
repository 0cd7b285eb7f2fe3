/// @file database_io.cpp
/// The native text format of AeroDatabase (YAML; docs/aero-database.md): writer and reader.
/// Numbers are written with core::format_exact and read with std::from_chars, so every double,
/// subnormals and the sign of zero included, survives a round trip bit for bit.

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "database_validate.hpp"
#include "manta/aero/database.hpp"
#include "manta/core/config.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"

namespace manta::aero {

namespace {

constexpr long format_version = 1;

// ---------------------------------------------------------------- writer

/// True if `s` reads back from YAML as the same plain scalar (conservative).
bool is_plain_safe(const std::string& s) {
    if (s.empty() || s.back() == ' ') return false;
    const auto first = static_cast<unsigned char>(s.front());
    if (!std::isalpha(first) && s.front() != '_') return false;
    for (const char ch : s) {
        const auto c = static_cast<unsigned char>(ch);
        if (!(std::isalnum(c) || ch == ' ' || ch == '_' || ch == '.' || ch == '-' || ch == '(' ||
              ch == ')' || ch == '/' || ch == '+' || ch == ',')) {
            return false;
        }
    }
    for (const char* word :
         {"null", "Null", "NULL", "true", "True", "TRUE", "false", "False", "FALSE", "yes", "Yes",
          "YES",  "no",   "No",   "NO",   "on",   "On",   "ON",    "off",   "Off",   "OFF"}) {
        if (s == word) return false;
    }
    return true;
}

/// `s` as a YAML scalar: plain when safe, else double-quoted with escapes.
std::string yaml_string(const std::string& s) {
    if (is_plain_safe(s)) return s;
    std::string out = "\"";
    for (const char ch : s) {
        const auto c = static_cast<unsigned char>(ch);
        switch (ch) {
            case '"':
                out += "\\\"";
                break;
            case '\\':
                out += "\\\\";
                break;
            case '\n':
                out += "\\n";
                break;
            case '\t':
                out += "\\t";
                break;
            case '\r':
                out += "\\r";
                break;
            default:
                if (c < 0x20 || c == 0x7f) {
                    out += fmt::format("\\x{:02x}", c);
                } else {
                    out += ch;  // UTF-8 bytes pass through
                }
        }
    }
    out += '"';
    return out;
}

std::string number_list(const std::vector<double>& v, std::size_t begin, std::size_t end) {
    std::string s = "[";
    for (std::size_t k = begin; k < end; ++k) {
        if (k > begin) s += ", ";
        s += core::format_exact(v[k]);
    }
    s += ']';
    return s;
}

// ---------------------------------------------------------------- reader

/// Exact decimal-to-double conversion of a scalar node (std::from_chars is correctly rounded and
/// accepts subnormals, which std::stod rejects); a leading '+' is allowed.
double read_number(const core::ConfigNode& n, std::string_view expected) {
    if (!n.is_scalar()) n.fail("is not a number", expected);
    const std::string text = n.value_text();
    const char* begin = text.data();
    const char* end = text.data() + text.size();
    if (begin != end && *begin == '+') ++begin;
    double v = 0.0;
    const auto r = std::from_chars(begin, end, v);
    if (r.ec == std::errc::result_out_of_range) n.fail("is out of the range of a double", expected);
    if (r.ec != std::errc() || r.ptr != end || begin == end) n.fail("is not a number", expected);
    if (!std::isfinite(v)) n.fail("is not finite", expected);
    return v;
}

// Plausible ranges (issue 16, defect 12): a value outside them is refused with the range named,
// rather than tabulated and flown. Mach numbers lie in [0, 10]. A coefficient of a static or
// control table beyond 100 in magnitude, or a dynamic derivative beyond 1000, is no aerodynamic
// coefficient (measured ones stay below 10 in magnitude; e.g. Stevens, Lewis and Johnson,
// "Aircraft Control and Simulation", 3rd ed., table 3.5-1, the F-16 data).
constexpr double max_static_coefficient = 100.0;
constexpr double max_dynamic_coefficient = 1000.0;

// Angles beyond 2 pi rad are refused by detail::validate_table ("looks like degrees").
void check_breakpoint(const core::ConfigNode& n, Axis axis, double v) {
    if (axis == Axis::mach && !(v <= 10.0))
        n.fail("is outside the plausible range of a Mach number", "a Mach number in [0, 10]");
}

void check_coefficient(const core::ConfigNode& n, const Table& t, std::size_t column, double v) {
    const double limit =
        t.kind == TableKind::dynamic ? max_dynamic_coefficient : max_static_coefficient;
    if (std::abs(v) <= limit) return;
    n.fail(fmt::format("of table '{}' column '{}' is implausible for an aerodynamic {}", t.name,
                       column < t.columns.size() ? t.columns[column] : std::string("?"),
                       t.kind == TableKind::dynamic ? "derivative" : "coefficient"),
           fmt::format("a number in [-{:g}, {:g}]", limit, limit));
}

std::vector<std::string> axis_names() {
    std::vector<std::string> v;
    for (const Axis a :
         {Axis::alpha, Axis::beta, Axis::mach, Axis::elevator, Axis::aileron, Axis::rudder})
        v.emplace_back(to_string(a));
    return v;
}

/// Located nodes of one table, for messages about it after it has been read.
struct TableNodes {
    core::ConfigNode table;
    core::ConfigNode name;
    std::vector<core::ConfigNode> axes;    ///< the axis mappings
    std::vector<core::ConfigNode> values;  ///< each axis's values / values_deg list
    core::ConfigNode columns;
    core::ConfigNode data;
};

[[noreturn]] void fail_at(const core::ConfigNode& node, const std::string& message) {
    // Validation messages start "aero database: "; the location says which file instead.
    constexpr std::string_view prefix = "aero database: ";
    std::string_view m = message;
    if (m.starts_with(prefix)) m.remove_prefix(prefix.size());
    throw InputError(fmt::format("{}: {}", node.where(), m));
}

[[noreturn]] void fail_issue(const detail::Issue& issue, const core::ConfigNode& tables_node,
                             const std::vector<TableNodes>& nodes,
                             const std::vector<Table>& tables) {
    using detail::IssuePart;
    if (issue.table < 0 || static_cast<std::size_t>(issue.table) >= nodes.size())
        fail_at(tables_node, issue.message);
    const auto ti = static_cast<std::size_t>(issue.table);
    const TableNodes& tn = nodes[ti];
    const auto index = static_cast<std::size_t>(std::max(issue.index, 0));
    switch (issue.part) {
        case IssuePart::database:
            fail_at(tables_node, issue.message);
        case IssuePart::table:
            fail_at(tn.table, issue.message);
        case IssuePart::table_name:
            fail_at(tn.name, issue.message);
        case IssuePart::axis:
            fail_at(tn.axes.at(index), issue.message);
        case IssuePart::breakpoint:
            fail_at(tn.values.at(index).element(static_cast<std::size_t>(issue.sub)),
                    issue.message);
        case IssuePart::column:
            fail_at(tn.columns.element(index), issue.message);
        case IssuePart::values:
            fail_at(tn.data, issue.message);
        case IssuePart::value: {
            const std::size_t nc = tables[ti].columns.size();
            fail_at(tn.data.element(index / nc).element(index % nc), issue.message);
        }
    }
    fail_at(tables_node, issue.message);
}

GridAxis read_axis(core::ConfigMap& am, core::ConfigNode& values_node) {
    const std::string name = am.string("name");
    const auto axis = detail::axis_from_string(name);
    if (!axis) {
        const auto names = axis_names();
        std::string expected = fmt::format("one of {}", fmt::join(names, ", "));
        const std::string guess = core::closest_match(name, names);
        if (!guess.empty()) expected += fmt::format(" (did you mean '{}'?)", guess);
        am.node().child("name").fail("is not an axis name", expected);
    }
    const bool rad = am.has("values");
    const bool deg = am.has("values_deg");
    if (rad && deg) {
        am.fail("values_deg", "duplicates 'values'", "either 'values' or 'values_deg', not both");
    }
    if (!rad && !deg) {
        throw InputError(fmt::format("{}: axis '{}' has no breakpoints; expected key 'values'{}",
                                     am.node().where(), name,
                                     is_angle(*axis) ? " (radians) or 'values_deg'" : ""));
    }
    if (deg && !is_angle(*axis)) {
        am.fail("values_deg", fmt::format("is given for '{}', which is not an angle", name),
                "'values' (Mach numbers are dimensionless)");
    }
    values_node = am.child(deg ? "values_deg" : "values");
    const std::string expected = fmt::format("a list of strictly increasing numbers [{}]",
                                             !is_angle(*axis) ? "-" : (deg ? "deg" : "rad"));
    if (!values_node.is_sequence()) values_node.fail("is not a list", expected);
    if (values_node.size() == 0) values_node.fail("is empty", expected);
    GridAxis a;
    a.axis = *axis;
    double previous = 0.0;
    for (std::size_t j = 0; j < values_node.size(); ++j) {
        const double v = read_number(values_node.element(j), expected);
        if (j > 0 && !(v > previous)) {
            // Checked here, in the units of the file (degrees for values_deg).
            const char* unit = deg ? " deg" : "";
            throw InputError(fmt::format(
                "{}: axis '{}' breakpoint [{}] = {}{} is not greater than breakpoint "
                "[{}] = {}{}; breakpoints must be strictly increasing",
                values_node.element(j).where(), name, j, v, unit, j - 1, previous, unit));
        }
        previous = v;
        check_breakpoint(values_node.element(j), *axis, v);
        a.breakpoints.push_back(deg ? v * (std::numbers::pi / 180.0) : v);
    }
    am.finish();
    return a;
}

std::string grid_shape(const Table& t) {
    std::string s;
    for (const auto& a : t.axes) {
        s +=
            fmt::format("{}{} {}", s.empty() ? "" : " x ", a.breakpoints.size(), to_string(a.axis));
    }
    return s.empty() ? "no axes" : s;
}

Table read_table(const core::ConfigNode& node, ForceAxes force_axes, TableNodes& nodes) {
    core::ConfigMap tm(node);
    nodes.table = node;
    Table t;
    t.name = tm.string("name");
    nodes.name = node.child("name");
    const std::string kind = tm.choice("kind", {"static", "control", "dynamic"});
    t.kind = *detail::kind_from_string(kind);
    const core::ConfigNode axes = tm.sequence("axes", /*allow_empty=*/true);
    for (std::size_t k = 0; k < axes.size(); ++k) {
        core::ConfigMap am(axes.element(k));
        core::ConfigNode values;
        t.axes.push_back(read_axis(am, values));
        nodes.axes.push_back(axes.element(k));
        nodes.values.push_back(values);
    }
    nodes.columns = tm.sequence("columns");
    for (std::size_t c = 0; c < nodes.columns.size(); ++c)
        t.columns.push_back(nodes.columns.element(c).to_string());
    // Axes and columns first, so a row count is only checked against a valid grid.
    if (auto issue = detail::validate_table(t, 0, force_axes, false)) {
        fail_issue(*issue, node, {nodes}, {t});
    }
    nodes.data = tm.sequence("data");
    const std::size_t n_points = t.n_points();
    const std::size_t nc = t.columns.size();
    if (nodes.data.size() != n_points) {
        fail_at(nodes.data,
                fmt::format("table '{}' has {} data rows; expected {} = {} (one row per grid "
                            "point, last axis fastest)",
                            t.name, nodes.data.size(), n_points, grid_shape(t)));
    }
    t.values.reserve(n_points * nc);
    const std::string expected =
        fmt::format("a finite number (column of {})", fmt::join(t.columns, ", "));
    for (std::size_t r = 0; r < n_points; ++r) {
        const core::ConfigNode row = nodes.data.element(r);
        if (!row.is_sequence() || row.size() != nc) {
            fail_at(
                row,
                fmt::format("table '{}' data row {} has {}; expected a list of {} numbers, one per "
                            "column ({})",
                            t.name, r,
                            row.is_sequence() ? fmt::format("{} entries", row.size()) : "no list",
                            nc, fmt::join(t.columns, ", ")));
        }
        for (std::size_t c = 0; c < nc; ++c) {
            const core::ConfigNode cell = row.element(c);
            t.values.push_back(read_number(cell, expected));
            check_coefficient(cell, t, c, t.values.back());
        }
    }
    tm.finish();
    return t;
}

AeroDatabase parse(std::string_view text, const std::string& source) {
    const core::ConfigNode root = core::ConfigNode::parse_string(text, source);
    if (!root.is_map()) {
        root.fail("is not an aero database", "a YAML mapping starting 'manta_aero_database: 1'");
    }
    core::ConfigMap m(root);
    if (!m.has("manta_aero_database")) {
        throw InputError(
            fmt::format("{}: not an aero database: missing key 'manta_aero_database' "
                        "(the format version, 1)",
                        root.where()));
    }
    const long version = m.integer("manta_aero_database", core::NumberSpec::any("-"));
    if (version != format_version) {
        m.fail("manta_aero_database", "is an unsupported format version",
               fmt::format("{} (this MANTA reads version {})", format_version, format_version));
    }
    DatabaseInfo info;
    if (auto node = m.optional_child("info")) {
        core::ConfigMap im(*node);
        info.name = im.string_or("name", "");
        info.source = im.string_or("source", "");
        info.description = im.string_or("description", "");
        im.finish();
    }
    const ForceAxes force_axes =
        m.choice("force_axes", {"wind", "body"}) == "wind" ? ForceAxes::wind : ForceAxes::body;
    const Extrapolation extrapolation =
        m.choice_or("extrapolation", "clamp", {"clamp", "linear"}) == "clamp"
            ? Extrapolation::clamp
            : Extrapolation::linear;
    const core::ConfigNode tables_node = m.sequence("tables");
    std::vector<Table> tables;
    std::vector<TableNodes> nodes(tables_node.size());
    for (std::size_t k = 0; k < tables_node.size(); ++k)
        tables.push_back(read_table(tables_node.element(k), force_axes, nodes[k]));
    m.finish();
    if (auto issue = detail::validate(tables, force_axes))
        fail_issue(*issue, tables_node, nodes, tables);
    return AeroDatabase(std::move(info), force_axes, extrapolation, std::move(tables));
}

}  // namespace

std::string AeroDatabase::to_text() const {
    std::string s;
    s += "# MANTA aerodynamic database (format: docs/aero-database.md).\n";
    s += "# Angles (alpha, beta, elevator, aileron, rudder) in radians; numbers in the shortest\n";
    s += "# decimal form that reads back to the same double.\n";
    s += fmt::format("manta_aero_database: {}\n", format_version);
    s += "info:\n";
    s += fmt::format("  name: {}\n", yaml_string(info().name));
    s += fmt::format("  source: {}\n", yaml_string(info().source));
    s += fmt::format("  description: {}\n", yaml_string(info().description));
    s += fmt::format("force_axes: {}\n", to_string(force_axes()));
    s += fmt::format("extrapolation: {}\n", to_string(extrapolation()));
    s += "tables:\n";
    for (const Table& t : tables()) {
        s += fmt::format("  - name: {}\n", yaml_string(t.name));
        s += fmt::format("    kind: {}\n", to_string(t.kind));
        if (t.axes.empty()) {
            s += "    axes: []\n";
        } else {
            s += "    axes:\n";
            for (const auto& a : t.axes) {
                s += fmt::format("      - {{name: {}, values: {}}}\n", to_string(a.axis),
                                 number_list(a.breakpoints, 0, a.breakpoints.size()));
            }
        }
        s += fmt::format("    columns: [{}]\n", fmt::join(t.columns, ", "));
        s += fmt::format("    # {} rows = {}, last axis fastest\n", t.n_points(), grid_shape(t));
        s += "    data:\n";
        const std::size_t nc = t.columns.size();
        for (std::size_t p = 0; p < t.n_points(); ++p)
            s += "      - " + number_list(t.values, p * nc, (p + 1) * nc) + "\n";
    }
    return s;
}

AeroDatabase AeroDatabase::from_text(std::string_view text, const std::string& source) {
    try {
        return parse(text, source);
    } catch (const ConfigError& e) {
        // A database file is input data, not configuration: one error type for all its problems.
        throw InputError(e.what());
    }
}

void AeroDatabase::write(const std::filesystem::path& file) const {
    core::write_file_atomic(file, to_text());
}

AeroDatabase AeroDatabase::read(const std::filesystem::path& file) {
    return from_text(core::read_file(file), file.string());
}

}  // namespace manta::aero
