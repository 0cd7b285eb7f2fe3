/// @file compare.cpp
/// A second table set beside the first: its tables as aero databases (multilinear
/// interpolation of the tables.csv entries), and the summary numbers of the comparison.

#include "manta/report/compare.hpp"
#include "detail/values.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "manta/aero/database.hpp"
#include "manta/core/error.hpp"

namespace manta::report {

namespace fs = std::filesystem;

using detail::distinct;
using detail::near;

namespace {

constexpr double deg = 3.14159265358979323846 / 180.0;
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

/// Index of `v` among the sorted distinct breakpoints `b` (they were built from the same values).
std::size_t index_of(const std::vector<double>& b, double v) {
    for (std::size_t i = 0; i < b.size(); ++i)
        if (near(v, b[i])) return i;
    return b.size();
}

bool within(const std::vector<double>& b, double v) {
    if (b.empty()) return false;
    const double tol = 1e-9 * std::max(1.0, std::abs(v));
    return v >= b.front() - tol && v <= b.back() + tol;
}

std::optional<aero::Axis> control_axis(const std::string& name) {
    if (name == "elevator") return aero::Axis::elevator;
    if (name == "aileron") return aero::Axis::aileron;
    if (name == "rudder") return aero::Axis::rudder;
    return std::nullopt;
}

std::vector<std::string> six_columns() {
    return {coefficient_names.begin(), coefficient_names.end()};
}

/// A static table that is zero everywhere (one alpha breakpoint): the base of the databases
/// that hold a control or the dynamic table alone.
aero::Table zero_static() {
    return {"zero",
            aero::TableKind::static_table,
            {{aero::Axis::alpha, {0.0}}},
            six_columns(),
            std::vector<double>(6, 0.0)};
}

std::shared_ptr<const aero::AeroDatabase> database(std::vector<aero::Table> tables,
                                                   const std::string& file) {
    try {
        return std::make_shared<const aero::AeroDatabase>(
            aero::DatabaseInfo{"report", "tables of " + file, "report"}, aero::ForceAxes::wind,
            aero::Extrapolation::clamp, std::move(tables));
    } catch (const InputError& e) {
        throw InputError(fmt::format("{}: {}", file, e.what()));
    }
}

/// Wind-axis forces and body moments of `db` at a point (the database works in body axes).
std::array<double, 6> evaluate(const aero::AeroDatabase& db, const aero::AeroQuery<double>& q) {
    const aero::BodyCoefficients<double> b = db.evaluate(q, aero::Interpolation::multilinear);
    const auto w = aero::wind_from_body(b.CX, b.CY, b.CZ, q.alpha, q.beta);
    return {w.CL, w.CD, w.CY, b.Cl, b.Cm, b.Cn};
}

nlohmann::json number_or_null(double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

std::vector<double> in_degrees(const std::vector<double>& v) {
    std::vector<double> out;
    for (const double x : v) out.push_back(std::round(x / deg * 1e9) / 1e9);  // 15, not 14.99..
    return out;
}

}  // namespace

TablesInterpolant::TablesInterpolant(const TablesData& t) {
    const std::string file = (t.dir / "tables.csv").string();
    for (const auto& [name, entries] : t.tables) {
        Part p;
        std::optional<aero::Axis> axis;
        if (name != "static") {
            axis = control_axis(name);
            if (!axis) continue;  // a table the aero database has no axis for: not compared
            p.control = name;
        }
        std::vector<double> a, m, b, d;
        for (const auto& e : entries) {
            a.push_back(e.alpha);
            m.push_back(e.mach);
            b.push_back(e.beta);
            d.push_back(e.delta);
        }
        p.grid = {distinct(a), distinct(m), distinct(b), distinct(d)};
        if (!axis && p.grid.delta.size() > 1)
            throw InputError(fmt::format(
                "{}: table 'static' has {} deflections (delta_deg); expected 0 in every static row",
                file, p.grid.delta.size()));
        const std::size_t na = p.grid.alpha.size(), nm = p.grid.mach.size(),
                          nb = p.grid.beta.size(), nd = p.grid.delta.size();
        const std::size_t n = na * nm * nb * nd;
        std::vector<double> values(n * 6), sigma(n * 6);
        std::vector<char> seen(n, 0);
        for (const auto& e : entries) {
            const std::size_t k =
                ((index_of(p.grid.alpha, e.alpha) * nm + index_of(p.grid.mach, e.mach)) * nb +
                 index_of(p.grid.beta, e.beta)) *
                    nd +
                index_of(p.grid.delta, e.delta);
            if (seen[k])
                throw InputError(fmt::format(
                    "{}: table '{}' has two rows at alpha {} deg, Mach {}, beta {} deg, delta {} "
                    "deg; expected one row per grid point",
                    file, name, e.alpha / deg, e.mach, e.beta / deg, e.delta / deg));
            seen[k] = 1;
            for (std::size_t c = 0; c < 6; ++c) {
                values[k * 6 + c] = e.c[c];
                sigma[k * 6 + c] = e.sigma[c];
            }
        }
        if (entries.size() != n)
            throw InputError(fmt::format(
                "{}: table '{}' is not a full grid: {} rows for {} alpha x {} Mach x {} beta x {} "
                "deflection breakpoints; expected one row per grid point",
                file, name, entries.size(), na, nm, nb, nd));
        std::vector<aero::GridAxis> axes{{aero::Axis::alpha, p.grid.alpha},
                                         {aero::Axis::mach, p.grid.mach},
                                         {aero::Axis::beta, p.grid.beta}};
        if (axis) axes.push_back({*axis, p.grid.delta});
        const auto kind = axis ? aero::TableKind::control : aero::TableKind::static_table;
        auto tables_of = [&](std::vector<double> v) {
            std::vector<aero::Table> out;
            if (axis) out.push_back(zero_static());
            out.push_back({name, kind, axes, six_columns(), std::move(v)});
            return out;
        };
        p.values = database(tables_of(std::move(values)), file);
        p.sigma = database(tables_of(std::move(sigma)), file);
        parts_.emplace(name, std::move(p));
    }
    if (t.dynamic) {
        const Columns& c = *t.dynamic;
        const std::string dfile = (t.dir / "dynamic.csv").string();
        static const std::set<std::string> rates{"p", "q", "r", "alphadot", "betadot"};
        for (const auto& col : c.names) {
            const auto u = col.find('_');
            if (u == std::string::npos) continue;
            const std::string coef = col.substr(0, u), rate = col.substr(u + 1);
            if (std::find(coefficient_names.begin(), coefficient_names.end(), coef) !=
                    coefficient_names.end() &&
                rates.count(rate))
                dyn_columns_.push_back(col);
        }
        if (!dyn_columns_.empty() && c.n_rows() > 0) {
            Part p;
            std::vector<double> a = c.at("alpha_deg");
            for (double& x : a) x *= deg;
            const std::vector<double>& m = c.at("mach");
            p.grid.alpha = distinct(a);
            p.grid.mach = distinct(m);
            const std::size_t na = p.grid.alpha.size(), nm = p.grid.mach.size(),
                              nc = dyn_columns_.size();
            std::vector<double> values(na * nm * nc);
            std::vector<char> seen(na * nm, 0);
            for (std::size_t i = 0; i < c.n_rows(); ++i) {
                const std::size_t k =
                    index_of(p.grid.alpha, a[i]) * nm + index_of(p.grid.mach, m[i]);
                if (seen[k])
                    throw InputError(fmt::format(
                        "{}: two rows at alpha {} deg, Mach {}; expected one row per grid point",
                        dfile, a[i] / deg, m[i]));
                seen[k] = 1;
                for (std::size_t j = 0; j < nc; ++j) values[k * nc + j] = c.at(dyn_columns_[j])[i];
            }
            if (c.n_rows() != na * nm)
                throw InputError(fmt::format(
                    "{}: not a full grid: {} rows for {} alpha x {} Mach breakpoints; expected "
                    "one row per grid point",
                    dfile, c.n_rows(), na, nm));
            p.values =
                database({zero_static(),
                          {"dynamic",
                           aero::TableKind::dynamic,
                           {{aero::Axis::alpha, p.grid.alpha}, {aero::Axis::mach, p.grid.mach}},
                           dyn_columns_,
                           std::move(values)}},
                         dfile);
            dynamic_ = std::move(p);
        } else {
            dyn_columns_.clear();
        }
    }
}

const TablesInterpolant::Part& TablesInterpolant::part(const std::string& name) const {
    const auto it = parts_.find(name);
    if (it == parts_.end())
        throw InputError(fmt::format("report: no table '{}' to evaluate", name));
    return it->second;
}

const TableGrid* TablesInterpolant::grid(const std::string& name) const {
    const auto it = parts_.find(name);
    return it == parts_.end() ? nullptr : &it->second.grid;
}

bool TablesInterpolant::inside(const std::string& name, double alpha, double mach, double beta,
                               double delta) const {
    const TableGrid* g = grid(name);
    if (!g) return false;
    return within(g->alpha, alpha) && within(g->mach, mach) && within(g->beta, beta) &&
           (name == "static" || within(g->delta, delta));
}

namespace {

aero::AeroQuery<double> query(const std::string& control, double alpha, double mach, double beta,
                              double delta) {
    aero::AeroQuery<double> q;
    q.alpha = alpha;
    q.mach = mach;
    q.beta = beta;
    if (control == "elevator") q.elevator = delta;
    if (control == "aileron") q.aileron = delta;
    if (control == "rudder") q.rudder = delta;
    return q;
}

}  // namespace

std::array<double, 6> TablesInterpolant::value(const std::string& name, double alpha, double mach,
                                               double beta, double delta) const {
    const Part& p = part(name);
    return evaluate(*p.values, query(p.control, alpha, mach, beta, delta));
}

std::array<double, 6> TablesInterpolant::sigma(const std::string& name, double alpha, double mach,
                                               double beta, double delta) const {
    const Part& p = part(name);
    return evaluate(*p.sigma, query(p.control, alpha, mach, beta, delta));
}

const TableGrid* TablesInterpolant::dynamic_grid() const {
    return dynamic_ ? &dynamic_->grid : nullptr;
}

std::optional<double> TablesInterpolant::dynamic(const std::string& column, double alpha,
                                                 double mach) const {
    if (!dynamic_ ||
        std::find(dyn_columns_.begin(), dyn_columns_.end(), column) == dyn_columns_.end())
        return std::nullopt;
    const auto u = column.find('_');
    const std::string coef = column.substr(0, u), rate = column.substr(u + 1);
    aero::AeroQuery<double> q;
    q.alpha = alpha;
    q.mach = mach;
    (rate == "p"          ? q.p_hat
     : rate == "q"        ? q.q_hat
     : rate == "r"        ? q.r_hat
     : rate == "alphadot" ? q.alpha_dot_hat
                          : q.beta_dot_hat) = 1.0;
    const auto c = evaluate(*dynamic_->values, q);  // the static part is zero: C_rate * 1
    const auto k = static_cast<std::size_t>(
        std::find(coefficient_names.begin(), coefficient_names.end(), coef) -
        coefficient_names.begin());
    return c[k];
}

const char* to_string(SliceMode m) {
    switch (m) {
        case SliceMode::exact:
            return "exact";
        case SliceMode::interpolated:
            return "interpolated";
        case SliceMode::outside:
            return "outside";
    }
    return "outside";
}

SliceMode slice_mode(const TablesInterpolant& oi, double mach, double beta) {
    const TableGrid* g = oi.grid("static");
    if (!g) return SliceMode::outside;
    if (index_of(g->mach, mach) < g->mach.size() && index_of(g->beta, beta) < g->beta.size())
        return SliceMode::exact;
    if (within(g->mach, mach) && within(g->beta, beta)) return SliceMode::interpolated;
    return SliceMode::outside;
}

double least_squares_slope(const std::vector<double>& x, const std::vector<double>& y) {
    const std::size_t n = std::min(x.size(), y.size());
    if (n < 2) return nan;
    double mx = 0, my = 0;
    for (std::size_t i = 0; i < n; ++i) {
        mx += x[i];
        my += y[i];
    }
    mx /= static_cast<double>(n);
    my /= static_cast<double>(n);
    double sxx = 0, sxy = 0;
    for (std::size_t i = 0; i < n; ++i) {
        sxx += (x[i] - mx) * (x[i] - mx);
        sxy += (x[i] - mx) * (y[i] - my);
    }
    return sxx > 0 ? sxy / sxx : nan;
}

std::vector<double> fit_points(const std::vector<double>& points, double lo, double hi,
                               std::array<double, 2> common, std::size_t min_points) {
    auto in = [](double v, double a, double b) {
        const double tol = 1e-9 * std::max(1.0, std::abs(v));
        return v >= a - tol && v <= b + tol;
    };
    std::vector<double> out, candidates;
    for (const double p : points) {
        if (!in(p, common[0], common[1])) continue;
        candidates.push_back(p);
        if (in(p, lo, hi)) out.push_back(p);
    }
    if (out.size() >= min_points) return out;
    const double centre = (lo + hi) / 2;
    std::stable_sort(candidates.begin(), candidates.end(), [&](double a, double b) {
        return std::abs(a - centre) < std::abs(b - centre);
    });
    candidates.resize(std::min(candidates.size(), std::max(min_points, out.size())));
    std::sort(candidates.begin(), candidates.end());
    return candidates;
}

Comparison compare_tables(const TablesData& main, const TablesInterpolant& mi,
                          const TablesData& other, const TablesInterpolant& oi) {
    Comparison c;
    c.main_label = main.label;
    c.other_label = other.label;
    c.main_dir = main.dir;
    c.other_dir = other.dir;
    const TableGrid* gm = mi.grid("static");
    const TableGrid* go = oi.grid("static");
    if (!gm || !go) return c;
    const double b0 = *std::min_element(gm->beta.begin(), gm->beta.end(), [](double p, double q) {
        return std::abs(p) < std::abs(q);
    });
    const std::array<double, 2> common{std::max(gm->alpha.front(), go->alpha.front()),
                                       std::min(gm->alpha.back(), go->alpha.back())};
    const std::vector<double> fit = common[0] <= common[1]
                                        ? fit_points(gm->alpha, -2 * deg, 4 * deg, common, 3)
                                        : std::vector<double>{};
    // CL_alpha, Cm_alpha, CL_0, Cm_0, CD_0 of one table at (mach, b0).
    auto summary = [&](const TablesInterpolant& t, double mach) {
        std::array<double, 5> s{nan, nan, nan, nan, nan};
        if (!t.inside("static", common[0], mach, b0) && !t.inside("static", 0.0, mach, b0))
            return s;
        std::vector<double> cl, cm;
        for (const double a : fit) {
            const auto v = t.value("static", a, mach, b0);
            cl.push_back(v[0]);
            cm.push_back(v[4]);
        }
        if (t.inside("static", common[0], mach, b0)) {
            s[0] = least_squares_slope(fit, cl);
            s[1] = least_squares_slope(fit, cm);
        }
        if (t.inside("static", 0.0, mach, b0)) {
            const auto v = t.value("static", 0.0, mach, b0);
            s[2] = v[0];
            s[3] = v[4];
            s[4] = v[1];
        }
        return s;
    };
    for (const double m : gm->mach) {
        MachSummary s;
        s.mach = m;
        s.beta = b0;
        s.fit_alpha = fit;
        s.main = summary(mi, m);
        s.other = summary(oi, m);
        c.machs.push_back(s);
    }
    for (const auto& [name, entries] : main.tables) {
        if (name == "static") continue;
        const TableGrid* cm = mi.grid(name);
        const TableGrid* co = oi.grid(name);
        if (!cm) continue;
        if (!co) {
            c.controls_only_main.push_back(name);
            continue;
        }
        ControlSummary s;
        s.control = name;
        s.mach = cm->mach[cm->mach.size() / 2];
        const double cb =
            *std::min_element(cm->beta.begin(), cm->beta.end(),
                              [](double p, double q) { return std::abs(p) < std::abs(q); });
        const std::array<double, 2> dcommon{std::max(cm->delta.front(), co->delta.front()),
                                            std::min(cm->delta.back(), co->delta.back())};
        if (dcommon[0] <= dcommon[1])
            s.fit_delta = fit_points(cm->delta, -10 * deg, 10 * deg, dcommon, 3);
        auto power = [&](const TablesInterpolant& t) {
            std::array<double, 6> p{nan, nan, nan, nan, nan, nan};
            for (const double d : s.fit_delta)
                if (!t.inside(name, 0.0, s.mach, cb, d)) return p;
            std::array<std::vector<double>, 6> y;
            for (const double d : s.fit_delta) {
                const auto v = t.value(name, 0.0, s.mach, cb, d);
                for (std::size_t k = 0; k < 6; ++k) y[k].push_back(v[k]);
            }
            for (std::size_t k = 0; k < 6; ++k) p[k] = least_squares_slope(s.fit_delta, y[k]);
            return p;
        };
        s.main = power(mi);
        s.other = power(oi);
        c.controls.push_back(s);
    }
    for (const double m : gm->mach)
        for (const double b : gm->beta) c.slices.push_back({{m, b}, slice_mode(oi, m, b)});
    for (const auto& col : mi.dynamic_columns())
        if (std::find(oi.dynamic_columns().begin(), oi.dynamic_columns().end(), col) !=
            oi.dynamic_columns().end())
            c.dynamic_columns.push_back(col);
    return c;
}

nlohmann::json Comparison::to_json() const {
    nlohmann::json j;
    j["main"] = {{"label", main_label}, {"dir", main_dir.string()}};
    j["compare"] = {{"label", other_label}, {"dir", other_dir.string()}};
    j["summary"] = nlohmann::json::array();
    for (const auto& s : machs) {
        nlohmann::json e{{"mach", s.mach},
                         {"beta_deg", std::round(s.beta / deg * 1e9) / 1e9},
                         {"fit_alpha_deg", in_degrees(s.fit_alpha)}};
        for (std::size_t k = 0; k < summary_names.size(); ++k) {
            e["main"][summary_names[k]] = number_or_null(s.main[k]);
            e["compare"][summary_names[k]] = number_or_null(s.other[k]);
            e["ratio"][summary_names[k]] = number_or_null(s.ratio(k));
        }
        j["summary"].push_back(std::move(e));
    }
    j["controls"] = nlohmann::json::array();
    for (const auto& s : controls) {
        nlohmann::json e{{"control", s.control},
                         {"mach", s.mach},
                         {"alpha_deg", 0.0},
                         {"fit_delta_deg", in_degrees(s.fit_delta)}};
        for (std::size_t k = 0; k < 6; ++k) {
            const std::string n = std::string("d") + coefficient_names[k] + "_d" + s.control;
            e["main"][n] = number_or_null(s.main[k]);
            e["compare"][n] = number_or_null(s.other[k]);
            e["ratio"][n] = number_or_null(s.ratio(k));
        }
        j["controls"].push_back(std::move(e));
    }
    j["controls_only_main"] = controls_only_main;
    j["dynamic_columns"] = dynamic_columns;
    nlohmann::json sl{{"exact", 0},
                      {"interpolated", nlohmann::json::array()},
                      {"outside", nlohmann::json::array()}};
    for (const auto& [mb, mode] : slices) {
        if (mode == SliceMode::exact)
            sl["exact"] = sl["exact"].get<int>() + 1;
        else
            sl[to_string(mode)].push_back(
                {{"mach", mb[0]}, {"beta_deg", std::round(mb[1] / deg * 1e9) / 1e9}});
    }
    j["slices"] = sl;
    return j;
}

TablesData read_compare_tables(const fs::path& dir) {
    if (!fs::is_directory(dir))
        throw IoError(fmt::format(
            "{}: not a directory; --compare-tables expects a `manta tables --out` directory",
            dir.string()));
    if (!fs::exists(dir / "tables.csv"))
        throw IoError(fmt::format(
            "{}: no tables.csv; --compare-tables expects a `manta tables --out` directory{}",
            dir.string(),
            fs::exists(dir / "tables" / "tables.csv")
                ? fmt::format(" (such as {})", (dir / "tables").string())
                : std::string()));
    TablesData t = read_tables(dir);
    if (!t.tables.count("static"))
        throw InputError(fmt::format(
            "{}: no static table (no row with table 'static'); --compare-tables expects the "
            "tables of `manta tables`",
            (dir / "tables.csv").string()));
    return t;
}

void check_same_coefficients(const TablesData& main, const TablesData& other) {
    std::vector<std::string> a = main.coefficient_columns, b = other.coefficient_columns;
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    if (a != b)
        throw InputError(fmt::format(
            "{}: coefficient columns {} differ from those of {} ({}); expected the same "
            "coefficients in both table sets",
            (other.dir / "tables.csv").string(), fmt::join(other.coefficient_columns, ","),
            (main.dir / "tables.csv").string(), fmt::join(main.coefficient_columns, ",")));
}

}  // namespace manta::report
