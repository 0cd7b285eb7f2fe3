/// @file database.cpp
/// AeroDatabase: names, validation, compilation of the evaluation plan, counters' report and
/// the linear-derivative builder. Evaluation kernels: database_eval.cpp; file format:
/// database_io.cpp.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <utility>

#include "database_validate.hpp"
#include "manta/aero/database.hpp"
#include "manta/core/config.hpp"
#include "manta/core/error.hpp"

namespace manta::aero {

// ---------------------------------------------------------------- names

std::string_view to_string(ForceAxes v) {
    return v == ForceAxes::wind ? "wind" : "body";
}

std::string_view to_string(Interpolation v) {
    return v == Interpolation::multilinear ? "multilinear" : "c1";
}

std::string_view to_string(Extrapolation v) {
    return v == Extrapolation::clamp ? "clamp" : "linear";
}

std::string_view to_string(Axis v) {
    switch (v) {
        case Axis::alpha:
            return "alpha";
        case Axis::beta:
            return "beta";
        case Axis::mach:
            return "mach";
        case Axis::elevator:
            return "elevator";
        case Axis::aileron:
            return "aileron";
        case Axis::rudder:
            return "rudder";
    }
    return "?";
}

std::string_view to_string(TableKind v) {
    switch (v) {
        case TableKind::static_table:
            return "static";
        case TableKind::control:
            return "control";
        case TableKind::dynamic:
            return "dynamic";
    }
    return "?";
}

bool is_angle(Axis v) {
    return v != Axis::mach;
}

std::size_t Table::n_points() const {
    std::size_t n = 1;
    for (const auto& a : axes) n *= a.breakpoints.size();
    return n;
}

std::uint64_t OutOfRangeReport::total() const {
    std::uint64_t t = 0;
    for (const auto& e : entries) t += e.below + e.above;
    return t;
}

std::string OutOfRangeReport::summary() const {
    std::string s;
    for (const auto& e : entries) {
        if (!s.empty()) s += '\n';
        s += fmt::format("{}/{}:", e.table, to_string(e.axis));
        if (e.below > 0) {
            s += fmt::format(" {} below {:.4g} (min {:.4g})", e.below, e.table_min, e.lowest);
        }
        if (e.above > 0) {
            s += fmt::format("{} {} above {:.4g} (max {:.4g})", e.below > 0 ? "," : "", e.above,
                             e.table_max, e.highest);
        }
    }
    return s;
}

// ---------------------------------------------------------------- validation

namespace detail {

std::vector<std::string> coefficient_names(ForceAxes force_axes) {
    if (force_axes == ForceAxes::wind) return {"CL", "CD", "CY", "Cl", "Cm", "Cn"};
    return {"CX", "CY", "CZ", "Cl", "Cm", "Cn"};
}

std::vector<std::string> rate_names() {
    return {"p", "q", "r", "alphadot", "betadot"};
}

std::optional<Axis> axis_from_string(std::string_view name) {
    for (const Axis a :
         {Axis::alpha, Axis::beta, Axis::mach, Axis::elevator, Axis::aileron, Axis::rudder}) {
        if (to_string(a) == name) return a;
    }
    return std::nullopt;
}

std::optional<TableKind> kind_from_string(std::string_view name) {
    for (const TableKind k : {TableKind::static_table, TableKind::control, TableKind::dynamic}) {
        if (to_string(k) == name) return k;
    }
    return std::nullopt;
}

namespace {

bool is_control_axis(Axis a) {
    return a == Axis::elevator || a == Axis::aileron || a == Axis::rudder;
}

std::string describe_table(const Table& t) {
    return fmt::format("table '{}' ({})", t.name, to_string(t.kind));
}

std::string axis_list(const Table& t) {
    std::string s;
    for (const auto& a : t.axes) s += (s.empty() ? "" : ", ") + std::string(to_string(a.axis));
    return s.empty() ? "none" : s;
}

/// Slot (0..5) of a static/control column, or -1.
int slot_of(std::string_view column, ForceAxes force_axes) {
    const auto names = coefficient_names(force_axes);
    for (std::size_t k = 0; k < names.size(); ++k)
        if (names[k] == column) return static_cast<int>(k);
    return -1;
}

/// (slot, rate) of a dynamic column `<coef>_<rate>`, or (-1, -1).
std::pair<int, int> dynamic_column(std::string_view column, ForceAxes force_axes) {
    const auto us = column.rfind('_');
    if (us == std::string_view::npos) return {-1, -1};
    const int slot = slot_of(column.substr(0, us), force_axes);
    const auto rates = rate_names();
    int rate = -1;
    for (std::size_t k = 0; k < rates.size(); ++k)
        if (rates[k] == column.substr(us + 1)) rate = static_cast<int>(k);
    if (slot < 0 || rate < 0) return {-1, -1};
    return {slot, rate};
}

std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates) {
    const std::string guess = core::closest_match(word, candidates);
    return guess.empty() ? std::string() : fmt::format(" (did you mean '{}'?)", guess);
}

Issue make_issue(IssuePart part, int table, int index, int sub, std::string message) {
    return Issue{part, table, index, sub, "aero database: " + std::move(message)};
}

std::optional<Issue> validate_axes(const Table& t, int ti) {
    const std::string where = describe_table(t);
    for (std::size_t k = 0; k < t.axes.size(); ++k) {
        const GridAxis& a = t.axes[k];
        const int ki = static_cast<int>(k);
        for (std::size_t j = 0; j < k; ++j) {
            if (t.axes[j].axis == a.axis) {
                return make_issue(IssuePart::axis, ti, ki, -1,
                                  fmt::format("{}: axis '{}' appears twice (axes [{}] and [{}]); "
                                              "each axis at most once per table",
                                              where, to_string(a.axis), j, k));
            }
        }
        const auto& x = a.breakpoints;
        if (x.empty()) {
            return make_issue(IssuePart::axis, ti, ki, -1,
                              fmt::format("{}: axis '{}' has no breakpoints; expected at least one",
                                          where, to_string(a.axis)));
        }
        for (std::size_t j = 0; j < x.size(); ++j) {
            const int ji = static_cast<int>(j);
            if (!std::isfinite(x[j])) {
                return make_issue(IssuePart::breakpoint, ti, ki, ji,
                                  fmt::format("{}: axis '{}' breakpoint [{}] = {} is not finite",
                                              where, to_string(a.axis), j, x[j]));
            }
            if (is_angle(a.axis) && std::abs(x[j]) > 2.0 * std::numbers::pi) {
                return make_issue(
                    IssuePart::breakpoint, ti, ki, ji,
                    fmt::format(
                        "{}: axis '{}' breakpoint [{}] = {} rad exceeds 2 pi in magnitude and "
                        "looks like degrees; angles are radians (files may give values_deg)",
                        where, to_string(a.axis), j, x[j]));
            }
            if (a.axis == Axis::mach && x[j] < 0.0) {
                return make_issue(IssuePart::breakpoint, ti, ki, ji,
                                  fmt::format("{}: axis 'mach' breakpoint [{}] = {} is negative; "
                                              "expected a Mach number >= 0",
                                              where, j, x[j]));
            }
            if (j > 0 && !(x[j] > x[j - 1])) {
                return make_issue(IssuePart::breakpoint, ti, ki, ji,
                                  fmt::format("{}: axis '{}' breakpoint [{}] = {} is not greater "
                                              "than breakpoint [{}] = {}; breakpoints must be "
                                              "strictly increasing",
                                              where, to_string(a.axis), j, x[j], j - 1, x[j - 1]));
            }
        }
    }
    return std::nullopt;
}

std::optional<Issue> validate_columns(const Table& t, int ti, ForceAxes force_axes) {
    const std::string where = describe_table(t);
    if (t.columns.empty()) {
        return make_issue(IssuePart::table, ti, -1, -1,
                          fmt::format("{} has no columns; expected at least one", where));
    }
    const auto coefs = coefficient_names(force_axes);
    const auto other =
        coefficient_names(force_axes == ForceAxes::wind ? ForceAxes::body : ForceAxes::wind);
    for (std::size_t c = 0; c < t.columns.size(); ++c) {
        const std::string& name = t.columns[c];
        const int ci = static_cast<int>(c);
        for (std::size_t j = 0; j < c; ++j) {
            if (t.columns[j] == name) {
                return make_issue(
                    IssuePart::column, ti, ci, -1,
                    fmt::format("{}: column '{}' appears twice (columns [{}] and [{}])", where,
                                name, j, c));
            }
        }
        if (t.kind != TableKind::dynamic) {
            if (slot_of(name, force_axes) >= 0) continue;
            std::string hint;
            if (std::find(other.begin(), other.end(), name) != other.end()) {
                hint = fmt::format(" ('{}' is a {}-axis force but force_axes is {})", name,
                                   force_axes == ForceAxes::wind ? "body" : "wind",
                                   to_string(force_axes));
            } else {
                hint = did_you_mean(name, coefs);
            }
            return make_issue(
                IssuePart::column, ti, ci, -1,
                fmt::format("{}: unknown column '{}'{}; expected one of {} ({} force axes)", where,
                            name, hint, fmt::join(coefs, ", "), to_string(force_axes)));
        }
        if (dynamic_column(name, force_axes).first >= 0) continue;
        std::vector<std::string> valid;
        for (const auto& co : coefs)
            for (const auto& r : rate_names()) valid.push_back(co + "_" + r);
        return make_issue(
            IssuePart::column, ti, ci, -1,
            fmt::format("{}: unknown column '{}'{}; dynamic columns are <coef>_<rate> with "
                        "coef in {} ({} force axes) and rate in {}",
                        where, name, did_you_mean(name, valid), fmt::join(coefs, ", "),
                        to_string(force_axes), fmt::join(rate_names(), ", ")));
    }
    return std::nullopt;
}

std::optional<Issue> validate_values(const Table& t, int ti) {
    const std::size_t n = t.n_points();
    const std::size_t nc = t.columns.size();
    if (t.values.size() != n * nc) {
        return make_issue(IssuePart::values, ti, -1, -1,
                          fmt::format("{} has {} values; expected {} = {} grid points x {} columns",
                                      describe_table(t), t.values.size(), n * nc, n, nc));
    }
    for (std::size_t k = 0; k < t.values.size(); ++k) {
        if (!std::isfinite(t.values[k])) {
            return make_issue(
                IssuePart::value, ti, static_cast<int>(k), -1,
                fmt::format("{}: value [{}] (grid point {}, column '{}') = {} is not finite",
                            describe_table(t), k, k / nc, t.columns[k % nc], t.values[k]));
        }
    }
    return std::nullopt;
}

}  // namespace

std::optional<Issue> validate_table(const Table& t, int ti, ForceAxes force_axes,
                                    bool with_values) {
    if (auto issue = validate_axes(t, ti)) return issue;
    if (auto issue = validate_columns(t, ti, force_axes)) return issue;
    if (with_values) return validate_values(t, ti);
    return std::nullopt;
}

std::optional<Issue> validate(const std::vector<Table>& tables, ForceAxes force_axes) {
    int first_static = -1;
    int first_dynamic = -1;
    std::map<Axis, int> control_of;
    for (std::size_t k = 0; k < tables.size(); ++k) {
        const Table& t = tables[k];
        const int ti = static_cast<int>(k);
        if (t.name.empty()) {
            return make_issue(
                IssuePart::table_name, ti, -1, -1,
                fmt::format("table [{}] has an empty name; expected a unique name", k));
        }
        for (std::size_t j = 0; j < k; ++j) {
            if (tables[j].name == t.name) {
                return make_issue(
                    IssuePart::table_name, ti, -1, -1,
                    fmt::format("table [{}] name '{}' repeats table [{}]; table names "
                                "must be unique",
                                k, t.name, j));
            }
        }
        if (auto issue = validate_table(t, ti, force_axes, true)) return issue;
        switch (t.kind) {
            case TableKind::static_table:
                if (first_static >= 0) {
                    return make_issue(
                        IssuePart::table, ti, -1, -1,
                        fmt::format("table '{}' is a second static table (the first is "
                                    "'{}'); exactly one static table is allowed",
                                    t.name, tables[static_cast<std::size_t>(first_static)].name));
                }
                first_static = ti;
                break;
            case TableKind::dynamic:
                if (first_dynamic >= 0) {
                    return make_issue(
                        IssuePart::table, ti, -1, -1,
                        fmt::format("table '{}' is a second dynamic table (the first is "
                                    "'{}'); at most one dynamic table is allowed",
                                    t.name, tables[static_cast<std::size_t>(first_dynamic)].name));
                }
                first_dynamic = ti;
                break;
            case TableKind::control: {
                std::vector<Axis> controls;
                for (const auto& a : t.axes)
                    if (is_control_axis(a.axis)) controls.push_back(a.axis);
                if (controls.size() != 1) {
                    return make_issue(
                        IssuePart::table, ti, -1, -1,
                        fmt::format("control table '{}' has {} control axes (axes: {}); a control "
                                    "table needs exactly one of elevator, aileron, rudder",
                                    t.name, controls.size(), axis_list(t)));
                }
                const auto [it, inserted] = control_of.emplace(controls[0], ti);
                if (!inserted) {
                    return make_issue(
                        IssuePart::table, ti, -1, -1,
                        fmt::format("control table '{}' is a second table for control "
                                    "'{}' (the first is '{}'); at most one per control",
                                    t.name, to_string(controls[0]),
                                    tables[static_cast<std::size_t>(it->second)].name));
                }
                break;
            }
        }
    }
    if (first_static < 0) {
        std::string list;
        for (const auto& t : tables) list += (list.empty() ? "" : ", ") + describe_table(t);
        return make_issue(IssuePart::database, -1, -1, -1,
                          fmt::format("no static table; exactly one table of kind 'static' is "
                                      "required (tables: {})",
                                      list.empty() ? "none" : list));
    }
    return std::nullopt;
}

// ---------------------------------------------------------------- plan

namespace {

/// Derivative at node j of the quadratic through three nodes, as weights on those nodes: the
/// centred non-uniform 3-point rule inside, the one-sided 3-point rule at the ends (exact for
/// quadratics); the secant for a two-point axis.
std::map<int, double> slope_row(const std::vector<double>& x, int j) {
    const int n = static_cast<int>(x.size());
    auto at = [&](int i) { return x[static_cast<std::size_t>(i)]; };
    if (n == 2) {
        const double h = at(1) - at(0);
        return {{0, -1.0 / h}, {1, 1.0 / h}};
    }
    if (j == 0) {
        const double h1 = at(1) - at(0), h2 = at(2) - at(1);
        return {{0, -(2.0 * h1 + h2) / (h1 * (h1 + h2))},
                {1, (h1 + h2) / (h1 * h2)},
                {2, -h1 / (h2 * (h1 + h2))}};
    }
    if (j == n - 1) {
        const double h1 = at(n - 2) - at(n - 3), h2 = at(n - 1) - at(n - 2);
        return {{n - 3, h2 / (h1 * (h1 + h2))},
                {n - 2, -(h1 + h2) / (h1 * h2)},
                {n - 1, (h1 + 2.0 * h2) / (h2 * (h1 + h2))}};
    }
    const double hm = at(j) - at(j - 1), hp = at(j + 1) - at(j);
    return {{j - 1, -hp / (hm * (hm + hp))},
            {j, (hp - hm) / (hm * hp)},
            {j + 1, hm / (hp * (hm + hp))}};
}

detail::GridPlan make_grid(Axis axis, const std::vector<double>& x) {
    detail::GridPlan g;
    g.axis = static_cast<int>(axis);
    g.n = static_cast<int>(x.size());
    g.last = g.n - 2;
    g.last_d = g.last;
    g.x = x;
    g.lo = x.front();
    g.hi = x.back();
    const double h = (g.hi - g.lo) / (g.n - 1);
    g.inv_h = 1.0 / h;
    // Near-uniform spacing (every node within h/4 of its uniform position) keeps the O(1) guess
    // within one cell of the answer, which `locate` then corrects without a branch.
    g.uniform = true;
    for (int i = 0; i < g.n; ++i) {
        if (std::abs(x[static_cast<std::size_t>(i)] - (g.lo + i * h)) > 0.25 * h) g.uniform = false;
    }
    for (int i = 0; i + 1 < g.n; ++i) {
        g.inv_w.push_back(1.0 /
                          (x[static_cast<std::size_t>(i) + 1] - x[static_cast<std::size_t>(i)]));
    }
    g.c1_count = std::min(g.n, detail::max_stencil);
    std::vector<std::map<int, double>> rows;
    for (int j = 0; j < g.n; ++j) rows.push_back(slope_row(x, j));
    auto window = [&](const std::map<int, double>& row, int start, double scale) {
        std::array<double, detail::max_stencil> w{};
        for (const auto& [node, coef] : row) {
            MANTA_ASSERT(node >= start && node < start + g.c1_count);
            w[static_cast<std::size_t>(node - start)] = coef * scale;
        }
        return w;
    };
    for (int i = 0; i + 1 < g.n; ++i) {
        const int start =
            g.n <= detail::max_stencil ? 0 : std::clamp(i - 1, 0, g.n - detail::max_stencil);
        const double hi_ = x[static_cast<std::size_t>(i) + 1] - x[static_cast<std::size_t>(i)];
        g.c1_start.push_back(start);
        g.c1_left.push_back(window(rows[static_cast<std::size_t>(i)], start, hi_));
        g.c1_right.push_back(window(rows[static_cast<std::size_t>(i) + 1], start, hi_));
    }
    g.slope_lo = window(rows.front(), g.c1_start.front(), 1.0);
    g.slope_hi = window(rows.back(), g.c1_start.back(), 1.0);
    return g;
}

detail::Plan compile(const std::vector<Table>& tables, ForceAxes force_axes,
                     Extrapolation extrapolation, std::vector<std::pair<int, int>>& counter_owner) {
    detail::Plan plan;
    plan.wind = force_axes == ForceAxes::wind;
    plan.linear = extrapolation == Extrapolation::linear;
    // Counters: one per (table, axis), in table then axis order.
    std::vector<int> first_counter;
    for (std::size_t t = 0; t < tables.size(); ++t) {
        first_counter.push_back(static_cast<int>(counter_owner.size()));
        for (std::size_t k = 0; k < tables[t].axes.size(); ++k)
            counter_owner.emplace_back(static_cast<int>(t), static_cast<int>(k));
    }
    // Static first, then controls, then the dynamic table.
    std::vector<std::size_t> order;
    for (const TableKind kind : {TableKind::static_table, TableKind::control, TableKind::dynamic})
        for (std::size_t t = 0; t < tables.size(); ++t)
            if (tables[t].kind == kind) order.push_back(t);

    for (const std::size_t t : order) {
        const Table& table = tables[t];
        detail::TablePlan tp;
        const std::size_t nc = table.columns.size();
        tp.n_columns = static_cast<int>(nc);
        tp.n_stored = tp.n_columns + tp.n_columns % 2;
        // Column c of the table goes to stored column order[c]; static and control columns are
        // sorted into slot order (a full static table then adds straight into the slots).
        std::vector<std::pair<int, int>> keyed;  // (slot or dynamic position, table column)
        for (std::size_t c = 0; c < nc; ++c) {
            const int slot = table.kind == TableKind::dynamic
                                 ? static_cast<int>(c)
                                 : detail::slot_of(table.columns[c], force_axes);
            keyed.emplace_back(slot, static_cast<int>(c));
        }
        std::sort(keyed.begin(), keyed.end());
        std::vector<std::size_t> order(nc);
        for (std::size_t k = 0; k < nc; ++k) {
            const auto c = static_cast<std::size_t>(keyed[k].second);
            order[c] = k;
            if (table.kind == TableKind::dynamic) {
                const auto [slot, rate] = detail::dynamic_column(table.columns[c], force_axes);
                tp.slot[k] = static_cast<std::int8_t>(slot);
                tp.factor[k] = static_cast<std::int8_t>(rate);
                tp.rated = true;
            } else {
                tp.slot[k] = static_cast<std::int8_t>(keyed[k].first);
                tp.factor[k] = static_cast<std::int8_t>(detail::unit_factor);
            }
        }
        const std::size_t n_points = table.n_points();
        const auto ns = static_cast<std::size_t>(tp.n_stored);
        tp.values.assign(n_points * ns, 0.0);
        for (std::size_t p = 0; p < n_points; ++p)
            for (std::size_t c = 0; c < nc; ++c)
                tp.values[p * ns + order[c]] = table.values[p * nc + c];
        // Active axes, their grids and strides (last axis fastest).
        std::size_t stride = ns;
        std::vector<std::pair<int, std::size_t>> active;  // (axis index, stride), last axis first
        for (std::size_t k = table.axes.size(); k-- > 0;) {
            const GridAxis& a = table.axes[k];
            if (a.breakpoints.size() >= 2) {
                int g = -1;
                for (std::size_t j = 0; j < plan.grids.size(); ++j) {
                    if (plan.grids[j].axis == static_cast<int>(a.axis) &&
                        plan.grids[j].x == a.breakpoints) {
                        g = static_cast<int>(j);
                    }
                }
                if (g < 0) {
                    plan.grids.push_back(make_grid(a.axis, a.breakpoints));
                    g = static_cast<int>(plan.grids.size()) - 1;
                }
                plan.grids[static_cast<std::size_t>(g)].counters.push_back(first_counter[t] +
                                                                           static_cast<int>(k));
                active.emplace_back(g, stride);
            }
            stride *= a.breakpoints.size();
        }
        std::reverse(active.begin(), active.end());
        tp.n_active = static_cast<int>(active.size());
        for (std::size_t k = 0; k < active.size(); ++k) {
            tp.grid[k] = active[k].first;
            tp.stride[k] = active[k].second;
        }
        tp.multilinear = detail::select_multilinear_kernel(tp);
        plan.tables.push_back(std::move(tp));
    }
    for (auto& g : plan.grids) {
        g.xp = g.x.data();
        g.iwp = g.inv_w.data();
    }
    return plan;
}

static_assert(detail::fast_n_axes == detail::n_axes &&
              detail::fast_max_grids == detail::max_grids &&
              detail::fast_n_slots == detail::n_slots && detail::fast_n_rates == detail::n_rates &&
              detail::fast_first_angle_rate == detail::first_angle_rate);

/// The plain-data copy of a compiled plan (fast_plan.hpp); false if the plan exceeds its fixed
/// limits. The pointers stay valid: the plan's vectors do not change once the Impl is built.
bool make_fast_plan(const detail::Plan& plan, detail::FastPlan& fast) {
    if (plan.grids.size() > static_cast<std::size_t>(detail::fast_max_grids) ||
        plan.tables.size() > static_cast<std::size_t>(detail::fast_max_tables))
        return false;
    fast.wind = plan.wind ? 1 : 0;
    fast.n_grids = static_cast<int>(plan.grids.size());
    fast.n_tables = static_cast<int>(plan.tables.size());
    for (std::size_t g = 0; g < plan.grids.size(); ++g) {
        const detail::GridPlan& gp = plan.grids[g];
        int uniform = gp.uniform ? 1 : 0;
        if (gp.uniform) {
            const double h = (gp.hi - gp.lo) / (gp.n - 1);
            bool exact = true;
            for (int i = 0; i < gp.n; ++i) {
                if (std::abs(gp.x[static_cast<std::size_t>(i)] - (gp.lo + i * h)) > 1e-14 * h)
                    exact = false;
            }
            if (exact) uniform = 2;
        }
        fast.grids[g] = {gp.lo,           gp.hi,   gp.inv_h, gp.last_d, gp.x.data(),
                         gp.inv_w.data(), gp.last, gp.axis,  uniform};
    }
    fast.shared_pair = 1;
    for (std::size_t t = 0; t < plan.tables.size(); ++t) {
        const detail::TablePlan& tp = plan.tables[t];
        detail::FastTable& ft = fast.tables[t];
        ft = detail::FastTable{};
        if (tp.n_stored > detail::fast_max_stored) return false;
        ft.values = tp.values.data();
        ft.n_stored = tp.n_stored;
        ft.direct = !tp.rated && tp.n_columns == detail::n_slots ? 1 : 0;
        for (std::size_t c = 0; c < static_cast<std::size_t>(detail::fast_max_stored); ++c) {
            int d = detail::fast_padding_slot;
            if (c < static_cast<std::size_t>(tp.n_columns)) {
                const int f = tp.factor[c];
                d = detail::n_slots * (f == detail::unit_factor ? 0 : 1 + f) + tp.slot[c];
            }
            ft.dest[c] = static_cast<std::int8_t>(d);
        }
        for (std::size_t k = 0; k < static_cast<std::size_t>(detail::n_axes); ++k) {
            ft.stride[k] = tp.stride[k];
            ft.grid[k] = tp.grid[k];
        }
        ft.n_active = tp.n_active;
        if (ft.n_active <= 4) {
            for (std::size_t c = 0; c < (std::size_t{1} << ft.n_active); ++c) {
                std::size_t o = 0;
                for (std::size_t k = 0; k < static_cast<std::size_t>(ft.n_active); ++k)
                    if ((c >> k) & 1u) o += ft.stride[k];
                ft.corner_offset[c] = o;
            }
        }
        if (ft.n_active < 2 || ft.grid[0] != fast.tables[0].grid[0] ||
            ft.grid[1] != fast.tables[0].grid[1])
            fast.shared_pair = 0;
    }
    return true;
}

void reset_counters(AeroDatabase::Impl& impl) {
    for (std::size_t k = 0; k < impl.counter_owner.size(); ++k) {
        auto& r = impl.range[k];
        r.below.store(0, std::memory_order_relaxed);
        r.above.store(0, std::memory_order_relaxed);
        r.lowest.store(std::numeric_limits<double>::infinity(), std::memory_order_relaxed);
        r.highest.store(-std::numeric_limits<double>::infinity(), std::memory_order_relaxed);
    }
    impl.evaluations.reset();
}

std::unique_ptr<AeroDatabase::Impl> make_impl(DatabaseInfo info, ForceAxes force_axes,
                                              Extrapolation extrapolation,
                                              std::vector<Table> tables) {
    if (auto issue = detail::validate(tables, force_axes)) throw InputError(issue->message);
    auto impl = std::make_unique<AeroDatabase::Impl>();
    impl->info = std::move(info);
    impl->force_axes = force_axes;
    impl->extrapolation = extrapolation;
    impl->tables = std::move(tables);
    impl->plan = compile(impl->tables, force_axes, extrapolation, impl->counter_owner);
    impl->has_fast_plan = make_fast_plan(impl->plan, impl->fast);
    impl->range = std::make_unique<detail::RangeCounter[]>(impl->counter_owner.size());
    reset_counters(*impl);
    return impl;
}

}  // namespace

}  // namespace detail

// ---------------------------------------------------------------- AeroDatabase

AeroDatabase::AeroDatabase(DatabaseInfo info, ForceAxes force_axes, Extrapolation extrapolation,
                           std::vector<Table> tables)
    : impl_(detail::make_impl(std::move(info), force_axes, extrapolation, std::move(tables))) {}

AeroDatabase::AeroDatabase(const AeroDatabase& other)
    : impl_(detail::make_impl(other.impl_->info, other.impl_->force_axes,
                              other.impl_->extrapolation, other.impl_->tables)) {
    // A copy starts with a snapshot of the original's counters.
    for (std::size_t k = 0; k < impl_->counter_owner.size(); ++k) {
        const auto& from = other.impl_->range[k];
        auto& to = impl_->range[k];
        to.below.store(from.below.load(std::memory_order_relaxed), std::memory_order_relaxed);
        to.above.store(from.above.load(std::memory_order_relaxed), std::memory_order_relaxed);
        to.lowest.store(from.lowest.load(std::memory_order_relaxed), std::memory_order_relaxed);
        to.highest.store(from.highest.load(std::memory_order_relaxed), std::memory_order_relaxed);
    }
    impl_->evaluations.shards[detail::EvaluationCounter::n_owned].n.store(
        other.impl_->evaluations.total(), std::memory_order_relaxed);
}

AeroDatabase& AeroDatabase::operator=(const AeroDatabase& other) {
    if (this != &other) *this = AeroDatabase(other);
    return *this;
}

AeroDatabase::AeroDatabase(AeroDatabase&&) noexcept = default;
AeroDatabase& AeroDatabase::operator=(AeroDatabase&&) noexcept = default;
AeroDatabase::~AeroDatabase() = default;

const detail::FastPlan* AeroDatabase::fast_plan() const noexcept {
    return impl_->has_fast_plan ? &impl_->fast : nullptr;
}

void AeroDatabase::count_evaluation() const noexcept {
    impl_->evaluations.add();
}

const DatabaseInfo& AeroDatabase::info() const {
    return impl_->info;
}
ForceAxes AeroDatabase::force_axes() const {
    return impl_->force_axes;
}
Extrapolation AeroDatabase::extrapolation() const {
    return impl_->extrapolation;
}
const std::vector<Table>& AeroDatabase::tables() const {
    return impl_->tables;
}

OutOfRangeReport AeroDatabase::out_of_range() const {
    OutOfRangeReport report;
    report.evaluations = impl_->evaluations.total();
    for (std::size_t k = 0; k < impl_->counter_owner.size(); ++k) {
        const auto& r = impl_->range[k];
        const auto below = r.below.load(std::memory_order_relaxed);
        const auto above = r.above.load(std::memory_order_relaxed);
        if (below == 0 && above == 0) continue;
        const auto [t, a] = impl_->counter_owner[k];
        const Table& table = impl_->tables[static_cast<std::size_t>(t)];
        const GridAxis& axis = table.axes[static_cast<std::size_t>(a)];
        OutOfRangeEntry e;
        e.table = table.name;
        e.axis = axis.axis;
        e.below = below;
        e.above = above;
        e.lowest = below > 0 ? r.lowest.load(std::memory_order_relaxed) : 0.0;
        e.highest = above > 0 ? r.highest.load(std::memory_order_relaxed) : 0.0;
        e.table_min = axis.breakpoints.front();
        e.table_max = axis.breakpoints.back();
        report.entries.push_back(std::move(e));
    }
    return report;
}

void AeroDatabase::reset_out_of_range() const {
    detail::reset_counters(*impl_);
}

// ---------------------------------------------------------------- from_derivatives

namespace {

/// Table over `axes` whose column c at each grid point is f(point)[c].
template <class F>
Table tabulate(std::string name, TableKind kind, std::vector<GridAxis> axes,
               std::vector<std::string> columns, F&& f) {
    Table t;
    t.name = std::move(name);
    t.kind = kind;
    t.axes = std::move(axes);
    t.columns = std::move(columns);
    const std::size_t n = t.n_points();
    t.values.reserve(n * t.columns.size());
    std::vector<std::size_t> idx(t.axes.size(), 0);
    std::vector<double> point(t.axes.size());
    for (std::size_t p = 0; p < n; ++p) {
        for (std::size_t k = 0; k < idx.size(); ++k) point[k] = t.axes[k].breakpoints[idx[k]];
        // + 0.0 turns the -0.0 of products like 0 * (-x) into +0.0, which reads better in files.
        for (const double v : f(point)) t.values.push_back(v + 0.0);
        for (std::size_t k = idx.size(); k-- > 0;) {
            if (++idx[k] < t.axes[k].breakpoints.size()) break;
            idx[k] = 0;
        }
    }
    return t;
}

/// Drop the columns that are zero everywhere; an empty result means the table adds nothing.
void drop_zero_columns(Table& t) {
    const std::size_t nc = t.columns.size();
    std::vector<bool> keep(nc, false);
    for (std::size_t k = 0; k < t.values.size(); ++k)
        if (t.values[k] != 0.0) keep[k % nc] = true;
    std::vector<std::string> columns;
    std::vector<double> values;
    for (std::size_t c = 0; c < nc; ++c)
        if (keep[c]) columns.push_back(t.columns[c]);
    for (std::size_t k = 0; k < t.values.size(); ++k)
        if (keep[k % nc]) values.push_back(t.values[k]);
    t.columns = std::move(columns);
    t.values = std::move(values);
}

void require_grid(const std::vector<double>& grid, std::string_view name, bool needs_two,
                  std::string_view why) {
    if (grid.empty()) {
        throw InputError(
            fmt::format("aero database from derivatives: the {} grid is empty; expected at "
                        "least one breakpoint",
                        name));
    }
    if (needs_two && grid.size() < 2) {
        throw InputError(
            fmt::format("aero database from derivatives: the {} grid has one breakpoint but "
                        "{} is nonzero; a linear term needs at least two breakpoints",
                        name, why));
    }
}

}  // namespace

AeroDatabase AeroDatabase::from_derivatives(const LinearDerivatives& d,
                                            const DerivativeGrids& grids, DatabaseInfo info) {
    const LinearDerivatives& D = d;
    require_grid(grids.alpha, "alpha", D.CL_alpha != 0.0 || D.Cm_alpha != 0.0,
                 "CL_alpha or Cm_alpha");
    require_grid(grids.mach, "mach", false, "");
    require_grid(grids.beta, "beta", D.CY_beta != 0.0 || D.Cl_beta != 0.0 || D.Cn_beta != 0.0,
                 "CY_beta, Cl_beta or Cn_beta");
    if (!grids.elevator.empty())
        require_grid(grids.elevator, "elevator", D.CL_de != 0.0 || D.Cm_de != 0.0,
                     "CL_de or Cm_de");
    if (!grids.aileron.empty())
        require_grid(grids.aileron, "aileron", D.CY_da != 0.0 || D.Cl_da != 0.0 || D.Cn_da != 0.0,
                     "CY_da, Cl_da or Cn_da");
    if (!grids.rudder.empty())
        require_grid(grids.rudder, "rudder", D.CY_dr != 0.0 || D.Cl_dr != 0.0 || D.Cn_dr != 0.0,
                     "CY_dr, Cl_dr or Cn_dr");

    // Prandtl-Glauert factor on slopes at each Mach breakpoint.
    auto pg = [&](double mach) {
        if (!D.prandtl_glauert) return 1.0;
        return std::sqrt(1.0 - D.mach_ref * D.mach_ref) / std::sqrt(1.0 - mach * mach);
    };
    if (D.prandtl_glauert) {
        if (!(D.mach_ref >= 0.0 && D.mach_ref < 1.0)) {
            throw InputError(
                fmt::format("aero database from derivatives: mach_ref = {} with "
                            "prandtl_glauert; expected 0 <= mach_ref < 1",
                            D.mach_ref));
        }
        for (const double m : grids.mach) {
            if (!(m < 1.0)) {
                throw InputError(
                    fmt::format("aero database from derivatives: Mach breakpoint {} with "
                                "prandtl_glauert; the Prandtl-Glauert rule needs M < 1",
                                m));
            }
        }
    }
    auto axis = [](Axis a, const std::vector<double>& x) { return GridAxis{a, x}; };

    std::vector<Table> tables;
    // Static: CL = CL_0 + k CL_alpha alpha, CD = CD_0 + CD_k (CL - CL_min_drag)^2, ...
    tables.push_back(tabulate("static", TableKind::static_table,
                              {axis(Axis::alpha, grids.alpha), axis(Axis::mach, grids.mach),
                               axis(Axis::beta, grids.beta)},
                              {"CL", "CD", "CY", "Cl", "Cm", "Cn"},
                              [&](const std::vector<double>& p) {
                                  const double alpha = p[0], k = pg(p[1]), beta = p[2];
                                  const double CL = D.CL_0 + k * D.CL_alpha * alpha;
                                  const double dCL = CL - D.CL_min_drag;
                                  return std::vector<double>{CL,
                                                             D.CD_0 + D.CD_k * dCL * dCL,
                                                             k * D.CY_beta * beta,
                                                             k * D.Cl_beta * beta,
                                                             D.Cm_0 + k * D.Cm_alpha * alpha,
                                                             k * D.Cn_beta * beta};
                              }));
    // Control increments over (alpha, mach, delta); all-zero columns dropped, empty tables omitted.
    auto control = [&](std::string name, Axis a, const std::vector<double>& grid,
                       std::vector<std::string> columns, auto&& f) {
        if (grid.empty()) return;
        Table t = tabulate(
            std::move(name), TableKind::control,
            {axis(Axis::alpha, grids.alpha), axis(Axis::mach, grids.mach), axis(a, grid)},
            std::move(columns), [&](const std::vector<double>& p) { return f(pg(p[1]), p[2]); });
        drop_zero_columns(t);
        if (!t.columns.empty()) tables.push_back(std::move(t));
    };
    // CD_de multiplies delta^2 (drag grows with either sign of deflection and the term stays
    // smooth; |delta| would put a kink at zero).
    control(
        "elevator", Axis::elevator, grids.elevator, {"CL", "CD", "Cm"}, [&](double k, double de) {
            return std::vector<double>{k * D.CL_de * de, k * D.CD_de * de * de, k * D.Cm_de * de};
        });
    control("aileron", Axis::aileron, grids.aileron, {"CY", "Cl", "Cn"}, [&](double k, double da) {
        return std::vector<double>{k * D.CY_da * da, k * D.Cl_da * da, k * D.Cn_da * da};
    });
    control("rudder", Axis::rudder, grids.rudder, {"CY", "Cl", "Cn"}, [&](double k, double dr) {
        return std::vector<double>{k * D.CY_dr * dr, k * D.Cl_dr * dr, k * D.Cn_dr * dr};
    });
    // Dynamic derivatives over (alpha, mach), not scaled.
    Table dyn = tabulate("dynamic", TableKind::dynamic,
                         {axis(Axis::alpha, grids.alpha), axis(Axis::mach, grids.mach)},
                         {"CL_q", "Cm_q", "CY_p", "Cl_p", "Cn_p", "CY_r", "Cl_r", "Cn_r",
                          "CL_alphadot", "Cm_alphadot"},
                         [&](const std::vector<double>&) {
                             return std::vector<double>{D.CL_q,        D.Cm_q,       D.CY_p, D.Cl_p,
                                                        D.Cn_p,        D.CY_r,       D.Cl_r, D.Cn_r,
                                                        D.CL_alphadot, D.Cm_alphadot};
                         });
    drop_zero_columns(dyn);
    if (!dyn.columns.empty()) tables.push_back(std::move(dyn));

    if (info.source.empty()) info.source = "linear-derivatives";
    if (info.description.empty()) {
        info.description = fmt::format(
            "tabulated from linear stability and control derivatives{}",
            D.prandtl_glauert
                ? fmt::format(" with Prandtl-Glauert scaling from M_ref = {}", D.mach_ref)
                : "");
    }
    // Linear extrapolation keeps the linear terms of the model outside the grid as well.
    return AeroDatabase(std::move(info), ForceAxes::wind, Extrapolation::linear, std::move(tables));
}

}  // namespace manta::aero
