/// @file html.cpp
/// The report page: sections for the run overview, aircraft, tables, manoeuvres, replays and
/// provenance; numbers in HTML tables; plots as placeholders that the inline script draws from
/// the embedded JSON.

#include "manta/report/html.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>

#include "detail/assets.hpp"
#include "manta/core/version.hpp"
#include "manta/report/report.hpp"

namespace manta::report {

namespace {

constexpr double rad2deg = 180.0 / 3.14159265358979323846;

std::string num(double v) {
    if (!std::isfinite(v)) return fmt::format("{}", v);
    return fmt::format("{:.6g}", v);
}

/// A JSON scalar (or short array of scalars) as text; "" for objects.
std::string json_text(const nlohmann::json& v) {
    if (v.is_null()) return "null";
    if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
    if (v.is_number_integer()) return std::to_string(v.get<long long>());
    if (v.is_number()) return num(v.get<double>());
    if (v.is_string()) return v.get<std::string>();
    if (v.is_array()) {
        std::string s;
        for (const auto& e : v) {
            if (e.is_structured())
                return v.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
            s += (s.empty() ? "" : ", ") + json_text(e);
        }
        return "[" + s + "]";
    }
    return v.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

/// Rows (key path, value) of a JSON object, nested objects flattened with '.'.
void flatten(const nlohmann::json& j, const std::string& prefix,
             std::vector<std::pair<std::string, std::string>>& rows) {
    if (j.is_object()) {
        for (auto it = j.begin(); it != j.end(); ++it)
            flatten(it.value(), prefix.empty() ? it.key() : prefix + "." + it.key(), rows);
    } else if (j.is_array() &&
               std::any_of(j.begin(), j.end(), [](const auto& e) { return e.is_object(); })) {
        for (std::size_t i = 0; i < j.size(); ++i)
            flatten(j[i], fmt::format("{}[{}]", prefix, i), rows);
    } else {
        rows.emplace_back(prefix, json_text(j));
    }
}

std::string key_value_table(const nlohmann::json& j) {
    std::vector<std::pair<std::string, std::string>> rows;
    flatten(j, "", rows);
    std::string s =
        "<table class=\"num\"><tr><th class=\"k\">key</th><th class=\"k\">value</th></tr>\n";
    for (const auto& [k, v] : rows)
        s += fmt::format("<tr><td class=\"k\">{}</td><td class=\"k\">{}</td></tr>\n",
                         escape_html(k), escape_html(v));
    return s + "</table>\n";
}

/// A number from a JSON object by key path, as text ("–" if absent or not a number).
std::string jnum(const nlohmann::json& j, std::initializer_list<const char*> path) {
    const nlohmann::json* p = &j;
    for (const char* k : path) {
        if (!p->is_object() || !p->contains(k)) return "&ndash;";
        p = &(*p)[k];
    }
    if (p->is_number()) return num(p->get<double>());
    if (p->is_string() || p->is_boolean()) return escape_html(json_text(*p));
    return "&ndash;";
}

std::string missing_note(const std::vector<std::string>& missing, const std::string& what) {
    if (missing.empty()) return {};
    std::string list;
    for (const auto& m : missing) list += (list.empty() ? "" : ", ") + escape_html(m);
    return fmt::format("<p class=\"note missing\">Not in {}: {} (not shown).</p>\n",
                       escape_html(what), list);
}

std::string plot(const std::string& id) {
    return fmt::format("<div class=\"plot\" data-figure=\"{}\"></div>\n", escape_html(id));
}

std::string group_html(const FigureGroup& g) {
    std::string s = fmt::format("<div class=\"tools\"><label>{} <select data-group=\"{}\">",
                                escape_html(g.label), escape_html(g.id));
    for (std::size_t i = 0; i < g.figure_ids.size(); ++i)
        s += fmt::format("<option value=\"{}\"{}>{}</option>", escape_html(g.figure_ids[i]),
                         i == g.initial ? " selected" : "", escape_html(g.labels[i]));
    s += "</select></label></div>\n";
    s += fmt::format("<div class=\"plot\" id=\"{}\" data-figure=\"{}\"></div>\n", escape_html(g.id),
                     escape_html(g.figure_ids[g.initial]));
    return s;
}

std::string aircraft_section(const AircraftInfo& a) {
    std::string s = "<section id=\"aircraft\"><h2>Aircraft</h2>\n";
    s += fmt::format("<p><b>{}</b> ({})<br><span class=\"note\">{}</span></p>\n",
                     escape_html(a.name), escape_html(a.file), escape_html(a.description));
    s += "<table class=\"num\"><tr><th class=\"k\">reference</th><th>value</th></tr>\n";
    s += fmt::format("<tr><td class=\"k\">area S [m²]</td><td>{}</td></tr>", num(a.area));
    s += fmt::format("<tr><td class=\"k\">span b [m]</td><td>{}</td></tr>", num(a.span));
    s += fmt::format("<tr><td class=\"k\">mean aerodynamic chord c̄ [m]</td><td>{}</td></tr>",
                     num(a.chord));
    s += fmt::format(
        "<tr><td class=\"k\">moment reference point x, y, z [m] (geometry axes)</td><td>{}, {}, "
        "{}</td></tr>",
        num(a.moment_reference[0]), num(a.moment_reference[1]), num(a.moment_reference[2]));
    s += fmt::format("<tr><td class=\"k\">length [m]</td><td>{}</td></tr>", num(a.length));
    s += fmt::format("<tr><td class=\"k\">aerodynamic model</td><td>{}</td></tr></table>\n",
                     escape_html(a.aero_label));
    s += "<h3>Mass cases</h3><table class=\"num\"><tr><th class=\"k\">case</th><th>mass [kg]</th>"
         "<th>CG x, y, z [m]</th><th>Ixx [kg m²]</th><th>Iyy</th><th>Izz</th><th>Ixz</th></tr>\n";
    for (const auto& m : a.mass_cases)
        s += fmt::format(
            "<tr><td class=\"k\">{}{}</td><td>{}</td><td>{}, {}, "
            "{}</td><td>{}</td><td>{}</td><td>{}"
            "</td><td>{}</td></tr>\n",
            escape_html(m.name), m.name == a.default_mass_case ? " (default)" : "", num(m.mass),
            num(m.cg[0]), num(m.cg[1]), num(m.cg[2]), num(m.inertia[0]), num(m.inertia[1]),
            num(m.inertia[2]), num(m.inertia[3]));
    s += "</table>\n<h3>Control limits</h3><table class=\"num\"><tr><th class=\"k\">control</th>"
         "<th>min [deg]</th><th>max [deg]</th></tr>\n";
    const char* names[3] = {"elevator", "aileron", "rudder"};
    for (int i = 0; i < 3; ++i)
        s += fmt::format("<tr><td class=\"k\">{}</td><td>{}</td><td>{}</td></tr>\n", names[i],
                         num(a.control_limits[i][0] * rad2deg),
                         num(a.control_limits[i][1] * rad2deg));
    s += "</table>\n";
    if (!a.top.empty())
        s += "<h3>Three-view</h3><div class=\"drawing\">" + three_view_svg(a) + "</div>\n";
    return s + "</section>\n";
}

/// The campaign of a tables directory: source, samples, times, scenarios, table entries.
std::string campaign_html(const nlohmann::json& j) {
    std::string s = "<table class=\"num\">";
    s += fmt::format("<tr><td class=\"k\">campaign</td><td class=\"k\">{}</td></tr>",
                     jnum(j, {"campaign"}));
    s += fmt::format("<tr><td class=\"k\">source</td><td class=\"k\">{} ({})</td></tr>",
                     jnum(j, {"source", "name"}), jnum(j, {"source", "fingerprint"}));
    s += fmt::format(
        "<tr><td class=\"k\">samples evaluated / reused / failed / total</td><td>{} / {} / {} "
        "/ "
        "{}</td></tr>",
        jnum(j, {"samples", "evaluated"}), jnum(j, {"samples", "reused"}),
        jnum(j, {"samples", "failed"}), jnum(j, {"samples", "total"}));
    s += fmt::format("<tr><td class=\"k\">wall time [s]</td><td>{}</td></tr>",
                     jnum(j, {"wall_time_s"}));
    s += fmt::format("<tr><td class=\"k\">sample wall time [s]</td><td>{}</td></tr></table>\n",
                     jnum(j, {"sample_wall_time_s"}));
    if (j.contains("scenarios") && j["scenarios"].is_array()) {
        s += "<h3>Scenarios (leave-one-out RMSE relative to the coefficient's range)</h3>"
             "<table class=\"num\"><tr><th class=\"k\">scenario</th><th>samples</th>"
             "<th>failed</th><th class=\"k\">stop</th>";
        for (const char* k : coefficient_names) s += fmt::format("<th>{}</th>", k);
        s += "</tr>\n";
        for (const auto& sc : j["scenarios"]) {
            if (!sc.is_object()) continue;
            s += fmt::format(
                "<tr><td class=\"k\">{}</td><td>{}</td><td>{}</td><td class=\"k\">{}</td>",
                jnum(sc, {"scenario"}), jnum(sc, {"samples_done"}), jnum(sc, {"samples_failed"}),
                jnum(sc, {"stop_reason"}));
            for (const char* k : coefficient_names)
                s += fmt::format("<td>{}</td>", jnum(sc, {"loo", k, "relative"}));
            s += "</tr>\n";
        }
        s += "</table>\n";
    }
    if (j.contains("table_entries") && j["table_entries"].is_object()) {
        s += "<p class=\"note\">Table entries: ";
        for (auto it = j["table_entries"].begin(); it != j["table_entries"].end(); ++it)
            s += fmt::format("{} {}; ", escape_html(it.key()), escape_html(json_text(it.value())));
        s += "</p>\n";
    }
    return s;
}

/// A number of the comparison ("–" for NaN: a table that does not reach the point).
std::string cnum(double v) {
    return std::isfinite(v) ? num(v) : std::string("&ndash;");
}

std::string degrees_list(const std::vector<double>& v) {
    std::string s;
    for (const double x : v) s += (s.empty() ? "" : ", ") + num(x * rad2deg);
    return s.empty() ? std::string("&ndash;") : s;
}

/// The comparison's summary: per Mach the slopes and zero-incidence coefficients of both tables
/// and their ratio, the control powers, the slices drawn from interpolation or left out.
std::string comparison_html(const Comparison& cmp, const ReportContent& c) {
    const std::string a = escape_html(cmp.main_label), b = escape_html(cmp.other_label);
    std::string s = fmt::format("<h3 id=\"tables-compare\">Comparison: {} and {}</h3>\n", a, b);
    s += fmt::format(
        "<p class=\"note\">Per Mach number of the {0} table at its sideslip nearest 0: "
        "CL<sub>α</sub> and Cm<sub>α</sub> [1/rad] by least squares over the α points given "
        "(the {0} table's breakpoints in [−2°, 4°], or the three nearest 1° inside both "
        "tables), CL, Cm and CD at α = 0; each table evaluated through its own entries "
        "(multilinear between breakpoints, no Kriging refit). Ratio = {1} / {0}; "
        "&ndash; where a table does not reach the point.</p>\n",
        a, b);
    static const std::array<const char*, 5> heads{
        "CL<sub>α</sub> [1/rad]", "Cm<sub>α</sub> [1/rad]", "CL(α=0)", "Cm(α=0)", "CD(α=0)"};
    s += "<div class=\"wide\"><table class=\"num\" id=\"compare-summary\"><tr><th "
         "rowspan=\"2\">Mach</th><th rowspan=\"2\">β [deg]</th><th rowspan=\"2\" "
         "class=\"k\">α points [deg]</th>";
    for (const char* h : heads) s += fmt::format("<th colspan=\"3\">{}</th>", h);
    s += "</tr>\n<tr>";
    for (std::size_t k = 0; k < heads.size(); ++k)
        s += fmt::format("<th>{}</th><th>{}</th><th>ratio</th>", a, b);
    s += "</tr>\n";
    for (const auto& m : cmp.machs) {
        s += fmt::format("<tr><td>{}</td><td>{}</td><td class=\"k\">{}</td>", num(m.mach),
                         num(m.beta * rad2deg), degrees_list(m.fit_alpha));
        for (std::size_t k = 0; k < summary_names.size(); ++k)
            s += fmt::format("<td>{}</td><td>{}</td><td>{}</td>", cnum(m.main[k]), cnum(m.other[k]),
                             cnum(m.ratio(k)));
        s += "</tr>\n";
    }
    s += "</table></div>\n";
    if (!cmp.controls.empty()) {
        s += fmt::format(
            "<h3>Control power</h3><p class=\"note\">dC/dδ [1/rad] at α = 0, β = 0 and the {0} "
            "control table's middle Mach number: least squares of the increments over the "
            "deflections given (the {0} table's in [−10°, 10°] inside both tables, or the "
            "three nearest 0). Every coefficient is in the JSON output (--json).</p>\n",
            a);
        s += fmt::format(
            "<table class=\"num\" id=\"compare-controls\"><tr><th class=\"k\">control</th><th "
            "class=\"k\">coefficient</th><th>Mach</th><th class=\"k\">δ points "
            "[deg]</th><th>{}</th><th>{}</th><th>ratio</th></tr>\n",
            a, b);
        for (const auto& cs : cmp.controls) {
            // The coefficients a control mainly moves.
            std::vector<std::size_t> ks{0, 1, 4};  // elevator: CL CD Cm
            if (cs.control == "aileron") ks = {3, 5};
            if (cs.control == "rudder") ks = {2, 3, 5};
            for (const std::size_t k : ks)
                s += fmt::format(
                    "<tr><td class=\"k\">{}</td><td class=\"k\">d{}/dδ</td><td>{}</td><td "
                    "class=\"k\">{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                    escape_html(cs.control), coefficient_names[k], num(cs.mach),
                    degrees_list(cs.fit_delta), cnum(cs.main[k]), cnum(cs.other[k]),
                    cnum(cs.ratio(k)));
        }
        s += "</table>\n";
    }
    if (!cmp.controls_only_main.empty()) {
        std::string list;
        for (const auto& n : cmp.controls_only_main)
            list += (list.empty() ? "" : ", ") + escape_html(n);
        s += fmt::format("<p class=\"note\">Control tables only in {}: {}.</p>\n", a, list);
    }
    std::string interpolated, outside;
    for (const auto& [mb, mode] : cmp.slices) {
        const std::string label = fmt::format("M {} β {}°", num(mb[0]), num(mb[1] * rad2deg));
        if (mode == SliceMode::interpolated)
            interpolated += (interpolated.empty() ? "" : ", ") + label;
        else if (mode == SliceMode::outside)
            outside += (outside.empty() ? "" : ", ") + label;
    }
    if (!interpolated.empty())
        s += fmt::format(
            "<p class=\"note\">Static slices where {} is interpolated (it lacks that Mach number "
            "or sideslip): {}.</p>\n",
            b, interpolated);
    if (!outside.empty())
        s += fmt::format(
            "<p class=\"note missing\">Static slices outside the Mach or sideslip range of {} "
            "(only {} drawn): {}.</p>\n",
            b, a, outside);
    if (std::any_of(c.figures.begin(), c.figures.end(),
                    [](const Figure& f) { return f.id == "tables-compare-summary"; }))
        s += plot("tables-compare-summary");
    return s;
}

std::string tables_section(const RunData& run, const ReportContent& c) {
    const TablesData& t = *run.tables;
    std::string s = "<section id=\"tables\"><h2>Aerodynamic tables</h2>\n";
    s += fmt::format("<p class=\"note\">From <code>{}</code>{}.</p>\n", escape_html(t.dir.string()),
                     run.compare ? " (" + escape_html(t.label) + ")" : std::string());
    s += missing_note(t.missing, "the tables directory");
    if (run.compare)
        s += fmt::format(
            "<p class=\"note\">Compared with <b>{}</b> from <code>{}</code>: drawn on the same "
            "axes in its own colour, with a lighter ±2σ band and its samples as squares.</p>\n",
            escape_html(run.compare->label), escape_html(run.compare->dir.string()));
    if (t.summary.is_object()) s += "<h3>Campaign</h3>" + campaign_html(t.summary);
    if (run.compare) {
        s += missing_note(run.compare->missing, "the compared tables directory");
        if (run.compare->summary.is_object())
            s += fmt::format(
                "<details><summary class=\"note\">campaign of {}</summary>\n{}</details>\n",
                escape_html(run.compare->label), campaign_html(run.compare->summary));
    }
    if (c.comparison) s += comparison_html(*c.comparison, c);
    const std::string both =
        run.compare ? fmt::format(
                          " Beside them the {} table (its own entries where it has the "
                          "Mach number and sideslip, else interpolated at these α "
                          "breakpoints inside its range).",
                          escape_html(run.compare->label))
                    : std::string();
    for (const auto& g : c.groups) {
        if (g.id == "tables-static") {
            s += "<h3>Static table</h3><p class=\"note\">Each coefficient against α at the chosen "
                 "Mach number and sideslip: the table (Kriging mean at the entries), its ±2σ band "
                 "and the flow-solver samples at that Mach number and sideslip." +
                 both + "</p>\n";
            s += group_html(g);
        }
    }
    for (const auto& g : c.groups) {
        if (g.id == "tables-static" || g.id == "tables-dynamic-compare" ||
            g.id.rfind("tables-", 0) != 0)
            continue;
        s += fmt::format(
            "<h3>Control table: {}</h3><p class=\"note\">Increments ΔC against α at "
            "β = 0 for the smallest and largest deflection, with ±2σ bands.{}</p>\n",
            escape_html(g.id.substr(7)),
            run.compare ? fmt::format(" Dashed: {} at the same deflections.",
                                      escape_html(run.compare->label))
                        : std::string());
        s += group_html(g);
    }
    if (std::any_of(c.figures.begin(), c.figures.end(),
                    [](const Figure& f) { return f.id == "tables-dynamic"; })) {
        s += "<h3>Dynamic derivatives</h3>\n" + plot("tables-dynamic");
    }
    for (const auto& g : c.groups)
        if (g.id == "tables-dynamic-compare")
            s += fmt::format("<h3>Dynamic derivatives of {} and {}</h3>\n", escape_html(t.label),
                             escape_html(run.compare->label)) +
                 group_html(g);
    return s + "</section>\n";
}

std::string manoeuvre_section(const ManoeuvreData& m, std::size_t k, const ReportContent& c) {
    std::string s = fmt::format("<section id=\"manoeuvre-{}\"><h2>Manoeuvre: {}</h2>\n", k,
                                escape_html(m.name));
    s +=
        fmt::format("<p class=\"note\">From <code>{}</code>{}.</p>\n", escape_html(m.dir.string()),
                    m.phases.empty()
                        ? std::string()
                        : "; phases: " + escape_html(fmt::format("{}", fmt::join(m.phases, ", "))));
    s += missing_note(m.missing, "the manoeuvre directory");
    if (m.summary.is_object()) {
        // The main numbers first (those present), then every key in a collapsed table.
        static const std::array<std::pair<const char*, const char*>, 12> main_keys{{
            {"status", "status"},
            {"ipopt_status", "IPOPT status"},
            {"final_time", "final time [s]"},
            {"iterations", "IPOPT iterations"},
            {"nodes", "nodes"},
            {"segments", "segments"},
            {"max_constraint_violation", "largest constraint violation"},
            {"resimulation_error", "re-simulation error"},
            {"cpu_time", "CPU time [s]"},
            {"wall_time", "wall time [s]"},
            {"mass_kg", "mass [kg]"},
            {"hessian", "Hessian"},
        }};
        s += "<h3>Summary</h3><table class=\"num\">";
        for (const auto& [key, label] : main_keys)
            if (m.summary.contains(key))
                s += fmt::format("<tr><td class=\"k\">{}</td><td>{}</td></tr>", label,
                                 jnum(m.summary, {key}));
        s += "</table>\n<details><summary class=\"note\">every value of summary.json</summary>\n" +
             key_value_table(m.summary) + "</details>\n";
    }
    const std::string hid = fmt::format("manoeuvre-{}-histories", k);
    if (std::any_of(c.figures.begin(), c.figures.end(),
                    [&](const Figure& f) { return f.id == hid; })) {
        s += fmt::format(
            "<h3>Time histories</h3><p class=\"note\">Lines: {}, one colour per quantity in "
            "every figure; circles: the LGL nodes (trajectory.csv).</p>\n",
            m.dense ? "the solution's interpolant (trajectory_dense.csv)"
                    : "the nodes joined (trajectory.csv)");
        s += plot(hid);
        s += "<h3>Flight path</h3>\n";
        s += fmt::format("<div class=\"plot path3d\" data-path=\"manoeuvre-{}-path\"></div>\n", k);
    }
    return s + "</section>\n";
}

/// RMS and max of |a - b| for coefficient column `col` of two comparisons, b interpolated
/// linearly at a's times inside b's range; nullopt when they do not overlap.
std::optional<std::array<double, 2>> replay_gap(const Columns& a, const Columns& b,
                                                const std::string& col) {
    const auto& ta = a.at("t");
    const auto& tb = b.at("t");
    const auto& ya = a.at(col);
    const auto& yb = b.at(col);
    double sum = 0.0, mx = 0.0;
    std::size_t n = 0, j = 0;
    for (std::size_t i = 0; i < ta.size(); ++i) {
        if (ta[i] < tb.front() - 1e-9 || ta[i] > tb.back() + 1e-9) continue;
        while (j + 2 < tb.size() && tb[j + 1] < ta[i]) ++j;
        const double w = tb.size() > 1 && tb[j + 1] > tb[j]
                             ? std::clamp((ta[i] - tb[j]) / (tb[j + 1] - tb[j]), 0.0, 1.0)
                             : 0.0;
        const double v = tb.size() == 1 ? yb[0]
                         : w <= 0.0     ? yb[j]
                         : w >= 1.0     ? yb[j + 1]
                                        : yb[j] + w * (yb[j + 1] - yb[j]);
        const double d = ya[i] - v;
        sum += d * d;
        mx = std::max(mx, std::abs(d));
        ++n;
    }
    if (n == 0) return std::nullopt;
    return std::array<double, 2>{std::sqrt(sum / static_cast<double>(n)), mx};
}

/// The replays of other sources beside this one: the differences of each against the table and
/// against this replay, and the figure with all of them on the same axes.
std::string sources_part(const ReplayData& r, std::size_t k, const ReportContent& c) {
    const std::string id = fmt::format("replay-{}-sources", k);
    if (std::none_of(c.figures.begin(), c.figures.end(),
                     [&](const Figure& f) { return f.id == id; }))
        return "";
    std::string s =
        fmt::format("<h3 id=\"replay-{}-sources-h\">Sources on the same axes: {} replay, table, ",
                    k, escape_html(r.label));
    for (std::size_t i = 0; i < r.others.size(); ++i)
        s += (i ? ", " : "") + escape_html(r.others[i].label) + " replay";
    s += "</h3>\n<table class=\"num sources\"><tr><th class=\"k\">RMS / max |Δ|</th>";
    for (const char* ck : coefficient_names) s += fmt::format("<th>{}</th>", ck);
    s += "</tr>\n";
    auto row = [&](const std::string& label, const ReplayData& x) {
        s += fmt::format("<tr><td class=\"k\">{} replay − table</td>", escape_html(label));
        for (const char* ck : coefficient_names)
            s += fmt::format("<td>{} / {}</td>", jnum(x.summary, {"coefficients", ck, "rms"}),
                             jnum(x.summary, {"coefficients", ck, "max_abs"}));
        s += "</tr>\n";
    };
    row(r.label, r);
    for (const auto& o : r.others) row(o.label, o);
    for (const auto& o : r.others) {
        if (!o.comparison || !r.comparison) continue;
        s += fmt::format("<tr><td class=\"k\">{} replay − {} replay</td>", escape_html(r.label),
                         escape_html(o.label));
        for (const char* ck : coefficient_names) {
            const auto g = replay_gap(*r.comparison, *o.comparison, std::string(ck) + "_replay");
            s += g ? fmt::format("<td>{} / {}</td>", num((*g)[0]), num((*g)[1]))
                   : std::string("<td>&ndash;</td>");
        }
        s += "</tr>\n";
    }
    s += "</table>\n";
    for (const auto& o : r.others)
        s += fmt::format(
            "<p class=\"note\">{} replay from <code>{}</code>: time step {} s, {} "
            "steps, wall time {} s.</p>\n",
            escape_html(o.label), escape_html(o.dir.string()), jnum(o.summary, {"dt"}),
            jnum(o.summary, {"steps"}), jnum(o.summary, {"wall_time_s"}));
    s += plot(id);
    s += fmt::format(
        "<p class=\"note\">Solid: the table (blue) and the {} replay (red); dashed: the other "
        "sources' replays against the same table at their own time steps (the differences "
        "between replays are the second part of the table above, the {} replay's times, the "
        "other interpolated linearly). Shaded: the {} replay's flagged intervals.</p>\n",
        escape_html(r.label), escape_html(r.label), escape_html(r.label));
    return s;
}

/// The surface Cp pictures of the replay's snapshots.
std::string surface_part(const ReplayData& r, std::size_t k, const ReportContent& c) {
    std::string pics;
    std::size_t n = 0;
    for (const auto& p : c.pictures) {
        if (p.replay != k) continue;
        ++n;
        pics +=
            fmt::format("<figure class=\"cp\" id=\"{}\">{}<figcaption>{}</figcaption></figure>\n",
                        p.id, p.svg, escape_html(p.caption));
    }
    if (r.snapshot_index.empty()) return "";
    std::string s = fmt::format(
        "<h3>Surface Cp</h3>\n<p class=\"note\">{} snapshot(s) of the wall in "
        "<code>surface/</code> (every {} s of flight); shown: the one nearest each flagged "
        "interval's largest |replay − table| / tolerance, and a reference outside them. Plan "
        "views of the mesh at rest (geometry axes, control surfaces undeflected), nose up; Cp on "
        "the instantaneous airspeed's dynamic pressure, one colour range for the pictures of this "
        "replay.</p>\n",
        r.snapshot_index.size(), jnum(r.summary, {"snapshots", "every_s"}));
    if (n == 0) s += "<p class=\"note\">No snapshot picked.</p>\n";
    return s + pics;
}

std::string replay_section(const ReplayData& r, std::size_t k, const ReportContent& c) {
    std::string s = fmt::format("<section id=\"replay-{}\"><h2>Replay against table: {}</h2>\n", k,
                                escape_html(r.name));
    s += fmt::format("<p class=\"note\">From <code>{}</code>.</p>\n", escape_html(r.dir.string()));
    s += missing_note(r.missing, "the replay directory");
    const auto& j = r.summary;
    if (j.is_object()) {
        s += fmt::format(
            "<table class=\"num\"><tr><td class=\"k\">source</td><td "
            "class=\"k\">{}</td></tr><tr><td "
            "class=\"k\">trajectory</td><td class=\"k\">{}</td></tr><tr><td class=\"k\">time step "
            "[s] / steps</td><td>{} / {}</td></tr><tr><td class=\"k\">wall / CPU time "
            "[s]</td><td>{} / "
            "{}</td></tr><tr><td class=\"k\">resumed from step</td><td>{}</td></tr></table>\n",
            jnum(j, {"source"}), jnum(j, {"trajectory"}), jnum(j, {"dt"}), jnum(j, {"steps"}),
            jnum(j, {"wall_time_s"}), jnum(j, {"cpu_time_s"}), jnum(j, {"resumed_from_step"}));
        s += "<h3>Replay − table, whole manoeuvre</h3><table class=\"num\"><tr><th "
             "class=\"k\">coefficient</th><th>RMS</th><th>max |Δ|</th><th>at t [s]</th><th>mean "
             "replay</th><th>mean table</th><th>tolerance</th></tr>\n";
        for (const char* ck : coefficient_names)
            s += fmt::format(
                "<tr><td class=\"k\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
                "<td>{}</td></tr>\n",
                ck, jnum(j, {"coefficients", ck, "rms"}), jnum(j, {"coefficients", ck, "max_abs"}),
                jnum(j, {"coefficients", ck, "t_max"}),
                jnum(j, {"coefficients", ck, "mean_replay"}),
                jnum(j, {"coefficients", ck, "mean_table"}), jnum(j, {"tolerances", ck}));
        s += "</table>\n";
        if (j.contains("phases") && j["phases"].is_array() && !j["phases"].empty()) {
            s += "<h3>Per phase: RMS / max |Δ|</h3><table class=\"num\"><tr><th "
                 "class=\"k\">phase</th><th>t start [s]</th><th>t end [s]</th>";
            for (const char* ck : coefficient_names) s += fmt::format("<th>{}</th>", ck);
            s += "</tr>\n";
            for (const auto& ph : j["phases"]) {
                if (!ph.is_object()) continue;
                s += fmt::format("<tr><td class=\"k\">{}</td><td>{}</td><td>{}</td>",
                                 jnum(ph, {"name"}), jnum(ph, {"t_start"}), jnum(ph, {"t_end"}));
                for (const char* ck : coefficient_names)
                    s += fmt::format("<td>{} / {}</td>", jnum(ph, {"coefficients", ck, "rms"}),
                                     jnum(ph, {"coefficients", ck, "max_abs"}));
                s += "</tr>\n";
            }
            s += "</table>\n";
        }
        if (j.contains("flags") && j["flags"].is_array()) {
            s += fmt::format("<h3>Flagged intervals ({})</h3>\n", j["flags"].size());
            if (j["flags"].empty()) {
                s += "<p class=\"note\">No difference above its tolerance.</p>\n";
            } else {
                s += "<table class=\"num\"><tr><th>t start [s]</th><th>t end [s]</th><th "
                     "class=\"k\">coefficients (max |Δ|)</th><th>α max [deg]</th><th>rate max "
                     "[deg/s]</th><th>control rate max [deg/s]</th><th>Mach max</th><th "
                     "class=\"k\">reasons</th></tr>\n";
                for (const auto& fl : j["flags"]) {
                    if (!fl.is_object()) continue;
                    std::string coeffs;
                    if (fl.contains("coefficients") && fl["coefficients"].is_array())
                        for (const auto& ck : fl["coefficients"]) {
                            const std::string name =
                                ck.is_string() ? ck.get<std::string>() : json_text(ck);
                            coeffs += (coeffs.empty() ? "" : ", ") + escape_html(name);
                            if (fl.contains("max_diff") && fl["max_diff"].is_object() &&
                                fl["max_diff"].contains(name) && fl["max_diff"][name].is_number())
                                coeffs += " (" + num(fl["max_diff"][name].get<double>()) + ")";
                        }
                    auto deg_of = [&](const char* key) {
                        if (fl.contains("state") && fl["state"].is_object() &&
                            fl["state"].contains(key) && fl["state"][key].is_number())
                            return num(fl["state"][key].get<double>() * rad2deg);
                        return std::string("&ndash;");
                    };
                    std::string reasons;
                    if (fl.contains("reasons") && fl["reasons"].is_array())
                        for (const auto& rs : fl["reasons"])
                            reasons += (reasons.empty() ? "" : "; ") + escape_html(json_text(rs));
                    s += fmt::format(
                        "<tr><td>{}</td><td>{}</td><td class=\"k\">{}</td><td>{}</td><td>{}</td>"
                        "<td>{}</td><td>{}</td><td class=\"k\">{}</td></tr>\n",
                        jnum(fl, {"t_start"}), jnum(fl, {"t_end"}), coeffs, deg_of("alpha_max"),
                        deg_of("rate_max"), deg_of("control_rate_max"),
                        jnum(fl, {"state", "mach_max"}), reasons);
                }
                s += "</table>\n";
            }
        }
    }
    for (const char* part : {"coefficients", "differences", "state"}) {
        const std::string id = fmt::format("replay-{}-{}", k, part);
        if (std::any_of(c.figures.begin(), c.figures.end(),
                        [&](const Figure& f) { return f.id == id; }))
            s += plot(id);
    }
    if (r.comparison)
        s += "<p class=\"note\">Shaded: flagged intervals (some |replay − table| above its "
             "tolerance); hover a shade for the reasons.</p>\n";
    s += sources_part(r, k, c);
    s += surface_part(r, k, c);
    return s + "</section>\n";
}

std::string overview_section(const RunData& run) {
    std::string s = "<section id=\"overview\"><h2>Overview</h2>\n";
    s += fmt::format("<p>Run directory <code>{}</code> ({} layout).</p>\n",
                     escape_html(run.dir.string()), escape_html(run.layout));
    s += missing_note(run.missing, "the run directory");
    if (!run.manoeuvres.empty()) {
        s += "<h3>Manoeuvres</h3><table class=\"num\"><tr><th class=\"k\">manoeuvre</th><th>final "
             "time [s]</th><th>IPOPT iterations</th><th "
             "class=\"k\">status</th><th>nodes</th></tr>\n";
        for (std::size_t k = 0; k < run.manoeuvres.size(); ++k) {
            const auto& m = run.manoeuvres[k];
            s += fmt::format(
                "<tr><td class=\"k\"><a "
                "href=\"#manoeuvre-{}\">{}</a></td><td>{}</td><td>{}</td><td "
                "class=\"k\">{}</td><td>{}</td></tr>\n",
                k, escape_html(m.name), jnum(m.summary, {"final_time"}),
                jnum(m.summary, {"iterations"}), jnum(m.summary, {"status"}),
                jnum(m.summary, {"nodes"}));
        }
        s += "</table>\n";
    }
    if (!run.replays.empty()) {
        s += "<h3>Replays: max |replay − table|</h3><table class=\"num\"><tr><th "
             "class=\"k\">manoeuvre</th>";
        for (const char* ck : coefficient_names) s += fmt::format("<th>{}</th>", ck);
        s += "<th>flagged intervals</th></tr>\n";
        for (std::size_t k = 0; k < run.replays.size(); ++k) {
            const auto& r = run.replays[k];
            s += fmt::format("<tr><td class=\"k\"><a href=\"#replay-{}\">{}</a></td>", k,
                             escape_html(r.name));
            for (const char* ck : coefficient_names)
                s += fmt::format("<td>{}</td>", jnum(r.summary, {"coefficients", ck, "max_abs"}));
            s += fmt::format("<td>{}</td></tr>\n", r.summary.is_object() &&
                                                           r.summary.contains("flags") &&
                                                           r.summary["flags"].is_array()
                                                       ? std::to_string(r.summary["flags"].size())
                                                       : std::string("&ndash;"));
        }
        s += "</table>\n";
    }
    return s + "</section>\n";
}

std::string provenance_section(const RunData& run) {
    std::string s = "<section id=\"provenance\"><h2>Provenance</h2>\n";
    if (run.run.is_object()) {
        s += "<p class=\"note\">From run.json: versions, command, settings and timings.</p>\n";
        s += key_value_table(run.run);
    } else {
        s += "<p class=\"note missing\">No run.json in the directory: versions, settings and "
             "timings of the run are unknown.</p>\n";
    }
    s += fmt::format("<p class=\"note\">Report written by MANTA {}.</p>\n",
                     escape_html(core::version()));
    return s + "</section>\n";
}

}  // namespace

std::string escape_html(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            case '\'':
                out += "&#39;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

std::string script_json(const nlohmann::json& j) {
    const std::string raw = j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    std::string out;
    out.reserve(raw.size() + raw.size() / 50);
    for (std::size_t i = 0; i < raw.size(); ++i) {
        const char c = raw[i];
        if (c == '<')
            out += "\\u003c";
        else if (c == '>')
            out += "\\u003e";
        else if (c == '&')
            out += "\\u0026";
        else if (c == '\xE2' && i + 2 < raw.size() && raw[i + 1] == '\x80' &&
                 (raw[i + 2] == '\xA8' || raw[i + 2] == '\xA9')) {
            out += raw[i + 2] == '\xA8' ? "\\u2028" : "\\u2029";
            i += 2;
        } else
            out += c;
    }
    return out;
}

std::string render_html(const RunData& run, const ReportContent& content) {
    const std::string title =
        run.aircraft ? "MANTA report: " + run.aircraft->name : std::string("MANTA report");
    std::string nav = "<a href=\"#overview\">Overview</a>";
    std::string body = overview_section(run);
    if (run.aircraft) {
        nav += "<a href=\"#aircraft\">Aircraft</a>";
        body += aircraft_section(*run.aircraft);
    }
    if (run.tables) {
        nav += "<a href=\"#tables\">Tables</a>";
        body += tables_section(run, content);
    }
    for (std::size_t k = 0; k < run.manoeuvres.size(); ++k) {
        nav +=
            fmt::format("<a href=\"#manoeuvre-{}\">{}</a>", k, escape_html(run.manoeuvres[k].name));
        body += manoeuvre_section(run.manoeuvres[k], k, content);
    }
    for (std::size_t k = 0; k < run.replays.size(); ++k) {
        nav += fmt::format("<a href=\"#replay-{}\">Replay {}</a>", k,
                           escape_html(run.replays[k].name));
        body += replay_section(run.replays[k], k, content);
    }
    nav += "<a href=\"#provenance\">Provenance</a>";
    body += provenance_section(run);

    nlohmann::json data{{"figures", nlohmann::json::object()}, {"paths", nlohmann::json::object()}};
    for (const auto& f : content.figures) data["figures"][f.id] = to_json(f);
    for (const auto& p : content.paths) data["paths"][p.id] = to_json(p);

    const auto now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    std::tm tm{};
    gmtime_r(&now, &tm);
    char stamp[32];
    std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%SZ", &tm);

    std::string s = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
    s += fmt::format("<title>{}</title>\n<style>{}</style>\n</head>\n", escape_html(title),
                     detail::report_css);
    s += "<body data-errors=\"0\">\n";
    s += fmt::format("<header><h1>{}</h1><p>{} · written {} by MANTA {}</p></header>\n",
                     escape_html(title), escape_html(run.dir.string()), stamp,
                     escape_html(core::version()));
    s += "<div id=\"errors\" hidden></div>\n<noscript><p>The plots need JavaScript; the tables "
         "below do not.</p></noscript>\n";
    s += "<nav>" + nav + "</nav>\n<main>\n" + body + "</main>\n";
    s += "<script type=\"application/json\" id=\"manta-data\">" + script_json(data) + "</script>\n";
    s += fmt::format("<script>{}</script>\n</body>\n</html>\n", detail::report_js);
    return s;
}

}  // namespace manta::report
