/// @file content.cpp
/// The report's figures, built from the run data: table slices with +-2 sigma bands and samples,
/// manoeuvre time histories (the paper's Figs. 10-12) and flight paths (Fig. 9), replay against
/// table (Figs. 13-15).

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "detail/values.hpp"
#include "manta/report/report.hpp"

namespace manta::report {

using detail::distinct;
using detail::near;

namespace {

constexpr double rad2deg = 180.0 / 3.14159265358979323846;

std::string num(double v) {
    return fmt::format("{:g}", v);
}

std::vector<double> scaled(const std::vector<double>& v, double f) {
    std::vector<double> out(v.size());
    std::transform(v.begin(), v.end(), out.begin(), [f](double x) { return x * f; });
    return out;
}

const std::array<const char*, 6> coefficient_labels{"CL", "CD", "CY", "Cl", "Cm", "Cn"};

/// The second table set of a comparison (--compare-tables).
struct Second {
    const TablesData& tables;
    const TablesInterpolant& interp;
};

std::vector<TableEntry> rows_at(const std::vector<TableEntry>& entries, double mach,
                                std::optional<double> beta, std::optional<double> delta) {
    std::vector<TableEntry> rows;
    for (const auto& e : entries)
        if (near(e.mach, mach) && (!beta || near(e.beta, *beta)) &&
            (!delta || near(e.delta, *delta)))
            rows.push_back(e);
    std::sort(rows.begin(), rows.end(),
              [](const TableEntry& a, const TableEntry& b) { return a.alpha < b.alpha; });
    return rows;
}

bool has_breakpoint(const std::vector<double>& b, double v) {
    return std::any_of(b.begin(), b.end(), [&](double x) { return near(x, v); });
}

/// A table's curve of coefficient k: mean and band (display units) and the name and colour. A
/// second table's band (lighter, opacity < 0.2) goes under every line already in the panel.
void add_curve(Panel& p, const std::vector<TableEntry>& rows, std::size_t k,
               const std::string& name, const std::string& colour, SeriesStyle line,
               double opacity) {
    Series band{name + " +-2 sigma", colour, SeriesStyle::band, {}, {}, {}};
    band.opacity = opacity;
    Series mean{name, colour, line, {}, {}, {}};
    for (const auto& e : rows) {
        band.x.push_back(e.alpha * rad2deg);
        band.y.push_back(e.c[k] - 2 * e.sigma[k]);
        band.y_upper.push_back(e.c[k] + 2 * e.sigma[k]);
        mean.x.push_back(e.alpha * rad2deg);
        mean.y.push_back(e.c[k]);
    }
    auto at = p.series.end();
    if (opacity < 0.2)
        at = std::find_if(p.series.begin(), p.series.end(),
                          [](const Series& s) { return s.style != SeriesStyle::band; });
    p.series.insert(at, std::move(band));
    p.series.push_back(std::move(mean));
}

/// The second table's entries at a slice: its own where it has the slice's breakpoints, else
/// interpolated through its database at the main table's alphas inside its alpha range; empty
/// outside its range. `interpolated` says which.
std::vector<TableEntry> second_rows(const Second& s, const std::string& table,
                                    const std::vector<TableEntry>& main_rows, double mach,
                                    double beta, double delta, bool& interpolated) {
    interpolated = false;
    const TableGrid* g = s.interp.grid(table);
    if (!g || main_rows.empty()) return {};
    const bool is_static = table == "static";
    if (has_breakpoint(g->mach, mach) && has_breakpoint(g->beta, beta) &&
        (is_static || has_breakpoint(g->delta, delta)))
        return rows_at(s.tables.tables.at(table), mach, beta,
                       is_static ? std::nullopt : std::optional<double>(delta));
    std::vector<TableEntry> out;
    for (const auto& m : main_rows) {
        if (!s.interp.inside(table, m.alpha, mach, beta, delta)) continue;
        TableEntry e;
        e.alpha = m.alpha;
        e.mach = mach;
        e.beta = beta;
        e.delta = delta;
        e.c = s.interp.value(table, m.alpha, mach, beta, delta);
        e.sigma = s.interp.sigma(table, m.alpha, mach, beta, delta);
        out.push_back(e);
    }
    interpolated = !out.empty();
    return out;
}

/// Static slice at (mach, beta): the six coefficients against alpha, +-2 sigma, samples; with a
/// second table set, its curves on the same axes (its own colour, lighter band, squares).
Figure static_slice(const TablesData& t, double mach, double beta, const std::string& id,
                    const std::optional<Second>& second) {
    Figure f;
    f.id = id;
    f.title = fmt::format("Static table at M = {}, beta = {} deg", num(mach), num(beta * rad2deg));
    const std::vector<TableEntry> rows = rows_at(t.tables.at("static"), mach, beta, std::nullopt);
    bool interpolated = false;
    const std::vector<TableEntry> rows2 =
        second ? second_rows(*second, "static", rows, mach, beta, 0.0, interpolated)
               : std::vector<TableEntry>{};
    const std::string name1 = second ? t.label : std::string("table (Kriging)");
    const std::string samples1 = second ? t.label + " samples" : std::string("samples");
    for (std::size_t k = 0; k < 6; ++k) {
        Panel p;
        p.title = coefficient_labels[k];
        p.x_label = "alpha [deg]";
        p.y_label = std::string(coefficient_labels[k]) + " [-]";
        add_curve(p, rows, k, name1, colour_of("table"), SeriesStyle::line, 0.2);
        if (!second) p.series.front().name = "table +-2 sigma";
        auto samples_of = [&](const TablesData& d, const std::string& name,
                              const std::string& colour, SeriesStyle style) {
            Series s{name, colour, style, {}, {}, {}};
            for (const auto& x : d.samples)
                if (x.scenario == "static" && !x.has_rates && near(x.mach, mach) &&
                    near(x.beta, beta)) {
                    s.x.push_back(x.alpha * rad2deg);
                    s.y.push_back(x.c[k]);
                }
            if (!s.x.empty()) p.series.push_back(std::move(s));
        };
        if (!rows2.empty())
            add_curve(p, rows2, k, second->tables.label + (interpolated ? " (interpolated)" : ""),
                      colour_of("compare"), SeriesStyle::line, 0.1);
        samples_of(t, samples1, colour_of("samples"), SeriesStyle::markers);
        if (!rows2.empty() && !interpolated)
            samples_of(second->tables, second->tables.label + " samples", colour_of("compare"),
                       SeriesStyle::squares);
        f.panels.push_back(std::move(p));
    }
    return f;
}

/// Control increments at one Mach: the extreme deflections with +-2 sigma (the paper's Fig. 8);
/// with a second table set, its increments at the same deflections (dashed, its own colours).
Figure control_slice(const std::string& control, const TablesData& t, double mach,
                     const std::string& id, const std::optional<Second>& second) {
    const std::vector<TableEntry>& entries = t.tables.at(control);
    Figure f;
    f.id = id;
    f.title = fmt::format("{} increments at M = {}, beta = 0", control, num(mach));
    std::vector<double> deltas;
    for (const auto& e : entries) deltas.push_back(e.delta);
    deltas = distinct(deltas);
    std::vector<std::pair<double, std::string>> shown;
    if (!deltas.empty()) shown.emplace_back(deltas.front(), "delta_min");
    if (deltas.size() > 1) shown.emplace_back(deltas.back(), "delta_max");
    for (std::size_t k = 0; k < 6; ++k) {
        Panel p;
        p.title = std::string("d") + coefficient_labels[k];
        p.x_label = "alpha [deg]";
        p.y_label = fmt::format("d{} [-]", coefficient_labels[k]);
        for (const auto& [delta, key] : shown) {
            const std::vector<TableEntry> rows = rows_at(entries, mach, std::nullopt, delta);
            const std::string name = fmt::format("{} {} deg", control, num(delta * rad2deg));
            add_curve(p, rows, k, second ? t.label + " " + name : name, colour_of(key),
                      SeriesStyle::line, 0.2);
            if (!second || rows.empty()) continue;
            bool interpolated = false;
            const auto rows2 =
                second_rows(*second, control, rows, mach, rows.front().beta, delta, interpolated);
            if (!rows2.empty())
                add_curve(
                    p, rows2, k,
                    second->tables.label + " " + name + (interpolated ? " (interpolated)" : ""),
                    colour_of(key == "delta_min" ? "compare_min" : "compare_max"),
                    SeriesStyle::dashed, 0.1);
        }
        f.panels.push_back(std::move(p));
    }
    return f;
}

/// The dynamic derivatives the report draws.
const std::array<const char*, 9> dynamic_names{"CL_q", "Cm_q", "CY_p", "Cl_p", "Cn_p",
                                               "CY_r", "Cl_r", "Cn_r", "CD_q"};

/// Dynamic derivatives against alpha, one curve per Mach.
std::optional<Figure> dynamic_figure(const Columns& d) {
    static const std::array<const char*, 6> ramp{"#440154", "#3b528b", "#21918c",
                                                 "#3aa35b", "#8fb21c", "#c7a200"};
    const auto& alpha = d.at("alpha_deg");
    const auto& mach = d.at("mach");
    const std::vector<double> machs = distinct(mach);
    Figure f;
    f.id = "tables-dynamic";
    f.title = "Dynamic derivatives (per non-dimensional rate)";
    for (const char* n : dynamic_names) {
        if (!d.has(n)) continue;
        Panel p;
        p.title = n;
        p.x_label = "alpha [deg]";
        p.y_label = std::string(n) + " [-]";
        for (std::size_t m = 0; m < machs.size(); ++m) {
            Series s{fmt::format("M = {}", num(machs[m])),
                     ramp[m % ramp.size()],
                     SeriesStyle::line,
                     {},
                     {},
                     {}};
            std::vector<std::pair<double, double>> pts;
            for (std::size_t i = 0; i < alpha.size(); ++i)
                if (near(mach[i], machs[m])) pts.emplace_back(alpha[i], d.at(n)[i]);
            std::sort(pts.begin(), pts.end());
            for (const auto& [a, v] : pts) {
                s.x.push_back(a);
                s.y.push_back(v);
            }
            p.series.push_back(std::move(s));
        }
        f.panels.push_back(std::move(p));
    }
    if (f.panels.empty()) return std::nullopt;
    return f;
}

/// (alpha [deg], value) of a dynamic.csv column at one Mach number, sorted by alpha.
std::vector<std::pair<double, double>> dynamic_points(const Columns& d, const std::string& column,
                                                      double mach) {
    std::vector<std::pair<double, double>> pts;
    const auto& alpha = d.at("alpha_deg");
    const auto& m = d.at("mach");
    for (std::size_t i = 0; i < alpha.size(); ++i)
        if (near(m[i], mach)) pts.emplace_back(alpha[i], d.at(column)[i]);
    std::sort(pts.begin(), pts.end());
    return pts;
}

/// The dynamic derivatives of both table sets at one Mach number of the main table: the second's
/// own rows where it has that Mach number, else interpolated at the main table's alphas.
Figure dynamic_compare_figure(const TablesData& t, const Second& second,
                              const std::vector<std::string>& columns, double mach,
                              const std::string& id) {
    Figure f;
    f.id = id;
    f.title = fmt::format("Dynamic derivatives at M = {} (per non-dimensional rate)", num(mach));
    const TableGrid* g2 = second.interp.dynamic_grid();
    const bool exact = g2 && has_breakpoint(g2->mach, mach);
    for (const char* n : dynamic_names) {
        if (std::find(columns.begin(), columns.end(), n) == columns.end()) continue;
        Panel p;
        p.title = n;
        p.x_label = "alpha [deg]";
        p.y_label = std::string(n) + " [-]";
        Series s1{t.label, colour_of("table"), SeriesStyle::line, {}, {}, {}};
        for (const auto& [a, v] : dynamic_points(*t.dynamic, n, mach)) {
            s1.x.push_back(a);
            s1.y.push_back(v);
        }
        Series s2{second.tables.label + (exact ? "" : " (interpolated)"),
                  colour_of("compare"),
                  SeriesStyle::line,
                  {},
                  {},
                  {}};
        if (exact) {
            for (const auto& [a, v] : dynamic_points(*second.tables.dynamic, n, mach)) {
                s2.x.push_back(a);
                s2.y.push_back(v);
            }
        } else if (g2 && mach >= g2->mach.front() - 1e-9 && mach <= g2->mach.back() + 1e-9) {
            for (const double a : s1.x)
                if (a / rad2deg >= g2->alpha.front() - 1e-9 &&
                    a / rad2deg <= g2->alpha.back() + 1e-9)
                    if (const auto v = second.interp.dynamic(n, a / rad2deg, mach)) {
                        s2.x.push_back(a);
                        s2.y.push_back(*v);
                    }
        }
        p.series.push_back(std::move(s1));
        if (!s2.x.empty()) p.series.push_back(std::move(s2));
        f.panels.push_back(std::move(p));
    }
    return f;
}

/// The comparison's summary against Mach: lift and pitching-moment slopes, CL, Cm and CD at
/// alpha = 0, both tables (points where a table reaches them).
Figure summary_figure(const Comparison& c) {
    static const std::array<const char*, 5> labels{"CL_alpha [1/rad]", "Cm_alpha [1/rad]",
                                                   "CL at alpha 0 [-]", "Cm at alpha 0 [-]",
                                                   "CD at alpha 0 [-]"};
    Figure f;
    f.id = "tables-compare-summary";
    f.title = fmt::format("{} and {}: slopes and zero-incidence coefficients", c.main_label,
                          c.other_label);
    for (std::size_t k = 0; k < summary_names.size(); ++k) {
        Panel p;
        p.title = summary_names[k];
        p.x_label = "Mach [-]";
        p.y_label = labels[k];
        Series a{c.main_label, colour_of("table"), SeriesStyle::line, {}, {}, {}};
        Series b{c.other_label, colour_of("compare"), SeriesStyle::line, {}, {}, {}};
        for (const auto& s : c.machs) {
            if (std::isfinite(s.main[k])) {
                a.x.push_back(s.mach);
                a.y.push_back(s.main[k]);
            }
            if (std::isfinite(s.other[k])) {
                b.x.push_back(s.mach);
                b.y.push_back(s.other[k]);
            }
        }
        Series am{c.main_label, colour_of("table"), SeriesStyle::markers, a.x, a.y, {}, false};
        Series bm{c.other_label, colour_of("compare"), SeriesStyle::squares, b.x, b.y, {}, false};
        p.series.push_back(std::move(a));
        p.series.push_back(std::move(b));
        p.series.push_back(std::move(am));
        p.series.push_back(std::move(bm));
        f.panels.push_back(std::move(p));
    }
    return f;
}

/// One time-history panel of a trajectory column (scaled to display units).
void add_history(Figure& f, const ManoeuvreData& m, const std::string& column,
                 const std::string& key, const std::string& label, double factor) {
    const Columns& c = m.curve();
    std::vector<double> y;
    if (c.has(column))
        y = scaled(c.at(column), factor);
    else if (column == "altitude" && c.has("z"))
        y = scaled(c.at("z"), -1.0);
    else
        return;
    Panel p;
    p.title = label.substr(0, label.find(" ["));
    p.x_label = "time [s]";
    p.y_label = label;
    p.series.push_back({key, colour_of(key), SeriesStyle::line, c.at("t"), y, {}, false});
    if (m.dense && m.nodes && (m.nodes->has(column) || column == "altitude")) {
        const Columns& n = *m.nodes;
        const std::vector<double> yn =
            n.has(column) ? scaled(n.at(column), factor) : scaled(n.at("z"), -1.0);
        p.series.push_back(
            {"LGL nodes", colour_of("nodes"), SeriesStyle::markers, n.at("t"), yn, {}});
    }
    f.panels.push_back(std::move(p));
}

Figure manoeuvre_figure(const ManoeuvreData& m, const std::string& id) {
    Figure f;
    f.id = id;
    f.title = m.name + ": states and controls";
    f.columns = 3;
    add_history(f, m, "V", "V", "V [m/s]", 1.0);
    add_history(f, m, "altitude", "altitude", "altitude [m]", 1.0);
    add_history(f, m, "nz", "nz", "load factor nz [-]", 1.0);
    add_history(f, m, "alpha", "alpha", "alpha [deg]", rad2deg);
    add_history(f, m, "beta", "beta", "beta [deg]", rad2deg);
    add_history(f, m, "mach", "mach", "Mach [-]", 1.0);
    add_history(f, m, "phi", "phi", "roll angle phi [deg]", rad2deg);
    add_history(f, m, "theta", "theta", "pitch angle theta [deg]", rad2deg);
    add_history(f, m, "psi", "psi", "yaw angle psi [deg]", rad2deg);
    add_history(f, m, "p", "p", "roll rate p [deg/s]", rad2deg);
    add_history(f, m, "q", "q", "pitch rate q [deg/s]", rad2deg);
    add_history(f, m, "r", "r", "yaw rate r [deg/s]", rad2deg);
    add_history(f, m, "elevator", "elevator", "elevator [deg]", rad2deg);
    add_history(f, m, "aileron", "aileron", "aileron [deg]", rad2deg);
    add_history(f, m, "rudder", "rudder", "rudder [deg]", rad2deg);
    add_history(f, m, "throttle", "throttle", "throttle [-]", 1.0);
    return f;
}

FlightPath flight_path(const ManoeuvreData& m, const AircraftInfo* aircraft,
                       const std::string& id) {
    const Columns& c = m.curve();
    FlightPath p;
    p.id = id;
    p.title = m.name + ": flight path";
    p.t = c.at("t");
    p.north = c.at("x");
    p.east = c.at("y");
    p.altitude = c.has("altitude") ? c.at("altitude") : scaled(c.at("z"), -1.0);
    p.phi = c.at("phi");
    p.theta = c.at("theta");
    p.psi = c.at("psi");
    const std::size_t n = p.t.size();
    const std::size_t n_glyphs = std::min<std::size_t>(n, 14);
    for (std::size_t k = 0; k < n_glyphs; ++k)
        p.glyphs.push_back(n_glyphs > 1 ? k * (n - 1) / (n_glyphs - 1) : 0);
    double length = 10.0;
    if (aircraft && !aircraft->body_segments.empty()) {
        p.body_segments = aircraft->body_segments;
        length = std::max(aircraft->length, 1.0);
    } else {
        // A generic glyph: fuselage, wing, tailplane and fin of a 10 m aircraft (body axes).
        p.body_segments = {{5, 0, 0, -5, 0, 0},     {1, -5, 0, 1, 5, 0},    {1, 5, 0, -1, 5, 0},
                           {-1, 5, 0, -1, -5, 0},   {1, -5, 0, -1, -5, 0},  {-4, -2, 0, -4, 2, 0},
                           {-3, 0, 0, -5, 0, -2.5}, {-5, 0, -2.5, -5, 0, 0}};
    }
    double extent = 1.0;
    for (const auto* v : {&p.north, &p.east, &p.altitude}) {
        const auto [lo, hi] = std::minmax_element(v->begin(), v->end());
        extent = std::max(extent, *hi - *lo);
    }
    // Each glyph about 1/8 of the path's extent, rounded to a whole 10:1 step as the paper
    // states its scale (100:1, 50:1).
    p.glyph_scale = std::max(1.0, std::round(extent / (8.0 * length) / 10.0) * 10.0);
    return p;
}

/// Flagged intervals of a replay: summary.json "flags" (with reasons), else runs of flag = 1.
std::vector<Shade> replay_shades(const ReplayData& r) {
    std::vector<Shade> out;
    if (r.summary.is_object() && r.summary.contains("flags") && r.summary["flags"].is_array()) {
        for (const auto& fl : r.summary["flags"]) {
            if (!fl.is_object()) continue;
            const double t0 = fl.value("t_start", 0.0), t1 = fl.value("t_end", t0);
            std::string label;
            if (fl.contains("reasons") && fl["reasons"].is_array())
                for (const auto& s : fl["reasons"])
                    if (s.is_string()) label += (label.empty() ? "" : ", ") + s.get<std::string>();
            out.push_back({t0, t1, label.empty() ? std::string("flagged") : label});
        }
        return out;
    }
    if (!r.comparison || !r.comparison->has("flag")) return out;
    const auto& t = r.comparison->at("t");
    const auto& flag = r.comparison->at("flag");
    for (std::size_t i = 0; i < t.size(); ++i) {
        if (flag[i] == 0.0) continue;
        std::size_t j = i;
        while (j + 1 < t.size() && flag[j + 1] != 0.0) ++j;
        out.push_back({t[i], t[j], "flagged"});
        i = j;
    }
    return out;
}

Figure replay_coefficients(const ReplayData& r, const std::string& id) {
    const Columns& c = *r.comparison;
    Figure f;
    f.id = id;
    f.title = r.name + ": replay against table";
    const auto shades = replay_shades(r);
    for (const char* k : coefficient_names) {
        Panel p;
        p.title = k;
        p.x_label = "time [s]";
        p.y_label = std::string(k) + " [-]";
        p.series.push_back({"table",
                            colour_of("table"),
                            SeriesStyle::line,
                            c.at("t"),
                            c.at(std::string(k) + "_table"),
                            {}});
        p.series.push_back({"replay",
                            colour_of("replay"),
                            SeriesStyle::line,
                            c.at("t"),
                            c.at(std::string(k) + "_replay"),
                            {}});
        p.shades = shades;
        f.panels.push_back(std::move(p));
    }
    return f;
}

Figure replay_differences(const ReplayData& r, const std::string& id) {
    const Columns& c = *r.comparison;
    Figure f;
    f.id = id;
    f.title = r.name + ": replay - table";
    const auto shades = replay_shades(r);
    const auto& t = c.at("t");
    for (const char* k : coefficient_names) {
        Panel p;
        p.title = std::string(k) + " difference";
        p.x_label = "time [s]";
        p.y_label = fmt::format("{} replay - table [-]", k);
        p.series.push_back({"replay - table",
                            colour_of("difference"),
                            SeriesStyle::line,
                            t,
                            c.at(std::string(k) + "_diff"),
                            {}});
        if (r.summary.is_object() && r.summary.contains("tolerances") &&
            r.summary["tolerances"].is_object() && r.summary["tolerances"].contains(k) &&
            r.summary["tolerances"][k].is_number()) {
            const double tol = r.summary["tolerances"][k].get<double>();
            const std::vector<double> tx{t.front(), t.back()};
            p.series.push_back(
                {"+-tolerance", colour_of("tolerance"), SeriesStyle::dashed, tx, {tol, tol}, {}});
            p.series.push_back(
                {"+-tolerance", colour_of("tolerance"), SeriesStyle::dashed, tx, {-tol, -tol}, {}});
        }
        p.shades = shades;
        f.panels.push_back(std::move(p));
    }
    return f;
}

/// The replay, its table and the replays of the other sources (replay-<source>/) on the same
/// axes, like the paper's Figs. 13-15 (the Euler replay, the Euler table, the lattice replay).
Figure replay_sources(const ReplayData& r, const std::string& id) {
    const Columns& c = *r.comparison;
    Figure f;
    f.id = id;
    std::string names = r.label;
    for (const auto& o : r.others) names += ", " + o.label;
    f.title = fmt::format("{}: table and replays ({})", r.name, names);
    const auto shades = replay_shades(r);
    for (const char* k : coefficient_names) {
        Panel p;
        p.title = k;
        p.x_label = "time [s]";
        p.y_label = std::string(k) + " [-]";
        p.series.push_back({"table",
                            colour_of("table"),
                            SeriesStyle::line,
                            c.at("t"),
                            c.at(std::string(k) + "_table"),
                            {}});
        p.series.push_back({r.label + " replay",
                            colour_of("replay"),
                            SeriesStyle::line,
                            c.at("t"),
                            c.at(std::string(k) + "_replay"),
                            {}});
        for (std::size_t i = 0; i < r.others.size(); ++i) {
            const ReplayData& o = r.others[i];
            if (!o.comparison) continue;
            p.series.push_back({o.label + " replay",
                                colour_of(i == 0 ? "replay_other" : "replay_other2"),
                                SeriesStyle::dashed,
                                o.comparison->at("t"),
                                o.comparison->at(std::string(k) + "_replay"),
                                {}});
        }
        p.shades = shades;
        f.panels.push_back(std::move(p));
    }
    return f;
}

std::optional<Figure> replay_state(const ReplayData& r, const std::string& id) {
    const Columns& c = *r.comparison;
    Figure f;
    f.id = id;
    f.title = r.name + ": replay state";
    const std::vector<std::tuple<const char*, const char*, double>> cols{
        {"alpha", "alpha [deg]", rad2deg},
        {"beta", "beta [deg]", rad2deg},
        {"mach", "Mach [-]", 1.0},
        {"p", "roll rate p [deg/s]", rad2deg},
        {"q", "pitch rate q [deg/s]", rad2deg},
        {"r", "yaw rate r [deg/s]", rad2deg},
        {"elevator", "elevator [deg]", rad2deg},
        {"aileron", "aileron [deg]", rad2deg},
        {"rudder", "rudder [deg]", rad2deg},
        {"elevator_rate", "elevator rate [deg/s]", rad2deg},
        {"aileron_rate", "aileron rate [deg/s]", rad2deg},
        {"rudder_rate", "rudder rate [deg/s]", rad2deg}};
    const auto shades = replay_shades(r);
    for (const auto& [col, label, factor] : cols) {
        if (!c.has(col)) continue;
        std::string key = col;
        if (key.size() > 5 && key.substr(key.size() - 5) == "_rate") key.resize(key.size() - 5);
        Panel p;
        p.title = std::string(label).substr(0, std::string(label).find(" ["));
        p.x_label = "time [s]";
        p.y_label = label;
        p.series.push_back({col,
                            colour_of(key),
                            SeriesStyle::line,
                            c.at("t"),
                            scaled(c.at(col), factor),
                            {},
                            false});
        p.shades = shades;
        f.panels.push_back(std::move(p));
    }
    if (f.panels.empty()) return std::nullopt;
    return f;
}

}  // namespace

ReportContent build_content(const RunData& run) {
    ReportContent out;
    auto add = [&](Figure f, bool exported) {
        if (exported) out.exported.push_back(f.id);
        out.figures.push_back(std::move(f));
    };
    // A second table set (--compare-tables): both as aero databases, and the summary numbers.
    std::optional<TablesInterpolant> main_interp, other_interp;
    std::optional<Second> second;
    if (run.tables && run.compare && run.tables->tables.count("static")) {
        main_interp.emplace(*run.tables);
        other_interp.emplace(*run.compare);
        second.emplace(Second{*run.compare, *other_interp});
        out.comparison = compare_tables(*run.tables, *main_interp, *run.compare, *other_interp);
    }
    if (run.tables && run.tables->tables.count("static")) {
        const TablesData& t = *run.tables;
        std::vector<double> machs, betas;
        for (const auto& e : t.tables.at("static")) {
            machs.push_back(e.mach);
            betas.push_back(e.beta);
        }
        machs = distinct(machs);
        betas = distinct(betas);
        FigureGroup g{"tables-static", "Mach, sideslip", {}, {}, 0};
        for (std::size_t i = 0; i < machs.size(); ++i)
            for (std::size_t j = 0; j < betas.size(); ++j) {
                const std::string id = fmt::format("tables-static-M{}-b{}", i, j);
                bool plotted = false;
                for (const auto& s : t.plot_slices)
                    if (std::abs(s[0] - machs[i]) < 1e-6 && std::abs(s[1] - betas[j]) < 1e-6)
                        plotted = true;
                if (!t.plot_slices.empty() && std::abs(t.plot_slices[0][0] - machs[i]) < 1e-6 &&
                    std::abs(t.plot_slices[0][1] - betas[j]) < 1e-6)
                    g.initial = g.figure_ids.size();
                g.labels.push_back(
                    fmt::format("M = {}, beta = {} deg", num(machs[i]), num(betas[j] * rad2deg)));
                g.figure_ids.push_back(id);
                // With a comparison every slice at the sideslip nearest 0 is written too.
                const bool beta0 = std::none_of(betas.begin(), betas.end(), [&](double b) {
                    return std::abs(b) < std::abs(betas[j]) - 1e-12;
                });
                add(static_slice(t, machs[i], betas[j], id, second), plotted || (second && beta0));
            }
        out.groups.push_back(std::move(g));
    }
    if (run.tables) {
        for (const auto& [name, entries] : run.tables->tables) {
            if (name == "static") continue;
            std::vector<double> machs;
            for (const auto& e : entries) machs.push_back(e.mach);
            machs = distinct(machs);
            FigureGroup g{"tables-" + name, "Mach", {}, {}, machs.size() / 2};
            for (std::size_t i = 0; i < machs.size(); ++i) {
                const std::string id = fmt::format("tables-{}-M{}", name, i);
                g.labels.push_back(fmt::format("M = {}", num(machs[i])));
                g.figure_ids.push_back(id);
                add(control_slice(name, *run.tables, machs[i], id, second), i == machs.size() / 2);
            }
            out.groups.push_back(std::move(g));
        }
        if (run.tables->dynamic)
            if (auto f = dynamic_figure(*run.tables->dynamic)) add(std::move(*f), true);
        if (second && out.comparison && !out.comparison->dynamic_columns.empty()) {
            const std::vector<double> machs = distinct(run.tables->dynamic->at("mach"));
            FigureGroup g{"tables-dynamic-compare", "Mach", {}, {}, machs.size() / 2};
            for (std::size_t i = 0; i < machs.size(); ++i) {
                const std::string id = fmt::format("tables-dynamic-compare-M{}", i);
                g.labels.push_back(fmt::format("M = {}", num(machs[i])));
                g.figure_ids.push_back(id);
                add(dynamic_compare_figure(*run.tables, *second, out.comparison->dynamic_columns,
                                           machs[i], id),
                    true);
            }
            out.groups.push_back(std::move(g));
        }
        if (out.comparison) add(summary_figure(*out.comparison), true);
    }
    for (std::size_t k = 0; k < run.manoeuvres.size(); ++k) {
        const ManoeuvreData& m = run.manoeuvres[k];
        if (!m.nodes && !m.dense) continue;
        add(manoeuvre_figure(m, fmt::format("manoeuvre-{}-histories", k)), true);
        out.paths.push_back(flight_path(m, run.aircraft ? &*run.aircraft : nullptr,
                                        fmt::format("manoeuvre-{}-path", k)));
    }
    for (std::size_t k = 0; k < run.replays.size(); ++k) {
        const ReplayData& r = run.replays[k];
        if (!r.comparison) continue;
        add(replay_coefficients(r, fmt::format("replay-{}-coefficients", k)), true);
        add(replay_differences(r, fmt::format("replay-{}-differences", k)), true);
        if (auto f = replay_state(r, fmt::format("replay-{}-state", k))) add(std::move(*f), true);
        if (std::any_of(r.others.begin(), r.others.end(),
                        [](const ReplayData& o) { return o.comparison.has_value(); }))
            add(replay_sources(r, fmt::format("replay-{}-sources", k)), true);
        // Surface Cp at the picked snapshots, one colour range for the replay's pictures.
        std::vector<const SurfaceSnapshot*> shown;
        for (const auto& p : r.picks) shown.push_back(&r.snapshots[p.snapshot]);
        const CpRange range = cp_range(shown);
        for (std::size_t i = 0; i < r.picks.size(); ++i) {
            const SnapshotPick& p = r.picks[i];
            const SurfaceSnapshot& s = r.snapshots[p.snapshot];
            Picture pic;
            pic.id = fmt::format("replay-{}-cp-{}", k, i);
            pic.replay = k;
            pic.caption = fmt::format("t = {:g} s (step {}, the snapshot nearest {:g} s): {}", s.t,
                                      s.step, p.t_wanted, p.why);
            pic.svg = cp_picture_svg(
                s, range,
                fmt::format("{}: surface Cp at t = {:g} s{}", r.name, s.t,
                            p.flag >= 0 ? fmt::format(" (flagged interval {})", p.flag + 1)
                                        : std::string(" (reference)")));
            out.pictures.push_back(std::move(pic));
        }
    }
    return out;
}

}  // namespace manta::report
