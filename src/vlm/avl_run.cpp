#include "manta/vlm/avl_run.hpp"

#include <fmt/format.h>

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/vlm/detail/avl_text.hpp"

namespace manta::vlm {

namespace {

using detail::avl::Line;
using detail::avl::Word;

constexpr double deg = std::numbers::pi / 180.0;

/// A run-case parameter AVL 3.40 writes, with the range MANTA accepts.
struct ParameterSpec {
    std::string_view name;
    double lo, hi;
    std::string_view what;
};

constexpr std::array<ParameterSpec, 30> parameter_specs = {{
    {"alpha", -90.0, 90.0, "an angle [deg]"},
    {"beta", -90.0, 90.0, "an angle [deg]"},
    {"pb/2V", -1.0, 1.0, "a non-dimensional rate"},
    {"qc/2V", -1.0, 1.0, "a non-dimensional rate"},
    {"rb/2V", -1.0, 1.0, "a non-dimensional rate"},
    {"CL", -10.0, 10.0, "a lift coefficient"},
    {"CDo", 0.0, 10.0, "a profile-drag coefficient"},
    {"bank", -360.0, 360.0, "an angle [deg]"},
    {"elevation", -360.0, 360.0, "an angle [deg]"},
    {"heading", -360.0, 360.0, "an angle [deg]"},
    {"Mach", 0.0, 0.95, "a Mach number (Prandtl-Glauert, below 0.95)"},
    {"velocity", 0.0, 1e6, "a speed"},
    {"density", 0.0, 1e6, "a density"},
    {"grav.acc.", 0.0, 1e6, "an acceleration"},
    {"turn_rad.", -1e12, 1e12, "a radius"},
    {"load_fac.", -100.0, 100.0, "a load factor"},
    {"X_cg", -1e6, 1e6, "a coordinate [Lunit]"},
    {"Y_cg", -1e6, 1e6, "a coordinate [Lunit]"},
    {"Z_cg", -1e6, 1e6, "a coordinate [Lunit]"},
    {"mass", 0.0, 1e15, "a mass"},
    {"Ixx", 0.0, 1e18, "a moment of inertia"},
    {"Iyy", 0.0, 1e18, "a moment of inertia"},
    {"Izz", 0.0, 1e18, "a moment of inertia"},
    {"Ixy", -1e18, 1e18, "a product of inertia"},
    {"Iyz", -1e18, 1e18, "a product of inertia"},
    {"Izx", -1e18, 1e18, "a product of inertia"},
    {"visc CL_a", -100.0, 100.0, "a coefficient"},
    {"visc CL_u", -100.0, 100.0, "a coefficient"},
    {"visc CM_a", -100.0, 100.0, "a coefficient"},
    {"visc CM_u", -100.0, 100.0, "a coefficient"},
}};

constexpr std::array<std::string_view, 5> rate_and_angle_names = {"alpha", "beta", "pb/2V", "qc/2V",
                                                                  "rb/2V"};

/// Runs of blanks collapsed to one.
std::string collapse(std::string_view s) {
    std::string out;
    bool blank = false;
    for (char c : detail::avl::trim(s)) {
        if (detail::avl::is_space(c)) {
            blank = true;
            continue;
        }
        if (blank && !out.empty()) out += ' ';
        blank = false;
        out += c;
    }
    return out;
}

bool starts_with_run_case(const std::string& t) {
    return detail::avl::lower(t.substr(0, 8)) == "run case";
}

class RunReader {
public:
    RunReader(std::string_view text, const std::string& source)
        : lines_(detail::avl::significant_lines(text)), source_(source) {}

    std::vector<RunCase> read() {
        for (const Line& l : lines_) {
            const std::string& t = l.text;
            if (starts_with_run_case(t)) {
                start_case(l);
                continue;
            }
            if (t.find_first_not_of("-=") == std::string::npos) continue;  // separator line
            if (cases_.empty())
                fail(l,
                     "expected 'Run case N: name' before the first constraint or parameter "
                     "line");
            const auto arrow = t.find("->");
            if (arrow != std::string::npos) {
                constraint(l, arrow);
                continue;
            }
            const auto eq = t.find('=');
            if (eq != std::string::npos) {
                parameter(l, eq);
                continue;
            }
            fail(l, fmt::format("'{}' is not a run-case line; expected 'variable -> constraint = "
                                "value', 'parameter = value' or 'Run case N: name'",
                                t));
        }
        if (cases_.empty()) {
            const int end = lines_.empty() ? 1 : lines_.back().number;
            throw InputError(fmt::format(
                "{}:{}: no run case in the file; expected a line 'Run case N: name' and its "
                "constraint and parameter lines",
                source_, end));
        }
        return std::move(cases_);
    }

private:
    std::vector<Line> lines_;
    const std::string& source_;
    std::vector<RunCase> cases_;

    [[noreturn]] void fail(const Line& l, std::string_view message) const {
        throw InputError(fmt::format("{}:{}: {}", source_, l.number, message));
    }

    void start_case(const Line& l) {
        const std::string& t = l.text;
        const auto colon = t.find(':');
        if (colon == std::string::npos)
            fail(l, fmt::format("'{}': no ':'; expected 'Run case N: name'", t));
        const std::string n = detail::avl::trim(std::string_view(t).substr(8, colon - 8));
        double v = 0.0;
        if (detail::avl::read_word(n, v) != Word::number || v != std::floor(v) || v < 1 || v > 1e6)
            fail(l, fmt::format("run case number '{}'; expected an integer >= 1 in 'Run case N: "
                                "name'",
                                n));
        RunCase rc;
        rc.number = static_cast<int>(v);
        for (const RunCase& o : cases_)
            if (o.number == rc.number)
                fail(l, fmt::format("run case {} again (first at line {}); expected each number "
                                    "once",
                                    rc.number, o.line));
        rc.name = detail::avl::trim(std::string_view(t).substr(colon + 1));
        rc.line = l.number;
        rc.source = source_;
        cases_.push_back(std::move(rc));
    }

    /// The number after '=' (the first word; a unit name may follow).
    double value_after(const Line& l, std::size_t eq, std::string_view key,
                       std::string_view expected) const {
        const auto ws = detail::avl::words(std::string_view(l.text).substr(eq + 1));
        if (ws.empty()) fail(l, fmt::format("{}: no value after '='; expected {}", key, expected));
        double v = 0.0;
        switch (detail::avl::read_word(ws[0], v)) {
            case Word::number:
                return v;
            case Word::non_finite:
                fail(l,
                     fmt::format("{}: {}", key, detail::avl::non_finite_message(ws[0], expected)));
            case Word::text:
                break;
        }
        fail(l, fmt::format("{}: '{}' is not a number; expected {}", key, ws[0], expected));
    }

    void check_range(const Line& l, std::string_view key, double v, double lo, double hi,
                     std::string_view what, bool hi_open = false) const {
        if (!(v >= lo && (hi_open ? v < hi : v <= hi)))
            fail(l, fmt::format("{} = {:g}; expected {} in [{:g}, {:g}{}", key, v, what, lo, hi,
                                hi_open ? ")" : "]"));
    }

    void constraint(const Line& l, std::size_t arrow) {
        const std::string& t = l.text;
        const auto eq = t.find('=', arrow);
        if (eq == std::string::npos)
            fail(l, fmt::format("'{}': no '=' after '->'; expected 'variable -> constraint = "
                                "value'",
                                t));
        RunConstraint c;
        c.line = l.number;
        const std::string var = collapse(std::string_view(t).substr(0, arrow));
        const std::string con = collapse(std::string_view(t).substr(arrow + 2, eq - arrow - 2));
        if (var.empty() || var.find(' ') != std::string::npos)
            fail(l, fmt::format("variable '{}'; expected alpha, beta, pb/2V, qc/2V, rb/2V or a "
                                "control name",
                                var));
        const bool fixed_var = std::find(rate_and_angle_names.begin(), rate_and_angle_names.end(),
                                         var) != rate_and_angle_names.end();
        c.variable = fixed_var ? var : detail::avl::lower(var);
        std::string what = "a control deflection [deg]";
        double lo = -90.0, hi = 90.0;
        if (con == "alpha" || con == "beta") {
            c.constraint = con;
            what = "an angle [deg]";
        } else if (con == "pb/2V" || con == "qc/2V" || con == "rb/2V") {
            c.constraint = con;
            lo = -1.0, hi = 1.0, what = "a non-dimensional rate";
        } else if (con == "CL" || con == "CY") {
            c.constraint = con;
            lo = -10.0, hi = 10.0, what = "a force coefficient";
        } else if (con == "Cl roll mom" || con == "Cl" || con == "Cm pitchmom" || con == "Cm" ||
                   con == "Cn yaw mom" || con == "Cn") {
            c.constraint = con.substr(0, 2);
            lo = -10.0, hi = 10.0, what = "a moment coefficient";
        } else if (!con.empty() && con.find(' ') == std::string::npos) {
            c.constraint = detail::avl::lower(con);  // a control, checked against the model
        } else {
            fail(l, fmt::format("constraint '{}' of variable '{}'; expected alpha, beta, pb/2V, "
                                "qc/2V, rb/2V, CL, CY, Cl roll mom, Cm pitchmom, Cn yaw mom or a "
                                "control name",
                                con, var));
        }
        const std::string key = fmt::format("{} -> {}", var, con);
        c.value = value_after(l, eq, key, what);
        check_range(l, key, c.value, lo, hi, what);
        RunCase& rc = cases_.back();
        for (const RunConstraint& o : rc.constraints) {
            if (o.variable == c.variable)
                fail(l, fmt::format("variable '{}' is constrained again (first at line {}); "
                                    "expected one constraint per variable",
                                    var, o.line));
            if (o.constraint == c.constraint)
                fail(l, fmt::format("constraint '{}' is used again (first at line {} for '{}'); "
                                    "expected each constraint once (as AVL requires)",
                                    con, o.line, o.variable));
        }
        rc.constraints.push_back(std::move(c));
    }

    void parameter(const Line& l, std::size_t eq) {
        const std::string name = collapse(std::string_view(l.text).substr(0, eq));
        const ParameterSpec* spec = nullptr;
        for (const auto& p : parameter_specs)
            if (p.name == name) spec = &p;
        if (!spec) {
            std::string known;
            for (const auto& p : parameter_specs)
                known += fmt::format("{}{}", known.empty() ? "" : ", ", p.name);
            fail(l, fmt::format("unknown parameter '{}'; expected one of AVL 3.40's: {}", name,
                                known));
        }
        const double v = value_after(l, eq, name, spec->what);
        check_range(l, name, v, spec->lo, spec->hi, spec->what, name == "Mach");
        RunCase& rc = cases_.back();
        if (const auto it = rc.parameters.find(name); it != rc.parameters.end())
            fail(l, fmt::format("parameter '{}' again (first at line {}); expected it once per "
                                "run case",
                                name, it->second.second));
        rc.parameters.emplace(name, std::make_pair(v, l.number));
    }
};

/// What a variable's constraint asks for.
enum class Target { alpha, beta, p, q, r, CL, CY, Cl, Cm, Cn, control };

}  // namespace

std::optional<double> RunCase::parameter(const std::string& name) const {
    const auto it = parameters.find(name);
    if (it == parameters.end()) return std::nullopt;
    return it->second.first;
}

std::string RunCase::where(const std::string& name) const {
    const auto it = parameters.find(name);
    return fmt::format("{}:{}", source, it == parameters.end() ? line : it->second.second);
}

std::vector<RunCase> parse_avl_run(std::string_view text, const std::string& source) {
    return RunReader(text, source).read();
}

std::vector<RunCase> read_avl_run(const std::filesystem::path& file) {
    const std::string text = core::read_file(file);
    return parse_avl_run(text, file.string());
}

const RunCase& find_run_case(const std::vector<RunCase>& cases, int number,
                             const std::string& source) {
    std::string have;
    for (const RunCase& c : cases) {
        if (c.number == number) return c;
        have += fmt::format("{}{}", have.empty() ? "" : ", ", c.number);
    }
    throw InputError(fmt::format("{}: no run case {}; the file has run case{} {}", source, number,
                                 cases.size() == 1 ? "" : "s", have));
}

ReferenceChoice choose_reference_point(const Model& model, const AvlMass* mass, const RunCase* run,
                                       const std::optional<Eigen::Vector3d>& xref) {
    ReferenceChoice c;
    c.point = model.reference.point;
    c.from = "the .avl header (Xref Yref Zref)";
    if (xref) {
        c.point = *xref;
        c.from = "--xref";
        return c;
    }
    if (mass) {
        c.point = mass->cg;
        c.from = fmt::format("{} (centre of gravity of {} items)", mass->source, mass->items);
    }
    if (run) {
        static const std::array<const char*, 3> keys = {"X_cg", "Y_cg", "Z_cg"};
        std::string given;
        int n = 0;
        for (int k = 0; k < 3; ++k) {
            if (const auto v = run->parameter(keys[static_cast<std::size_t>(k)])) {
                c.point[k] = *v;
                given += fmt::format("{}{}", given.empty() ? "" : " ",
                                     keys[static_cast<std::size_t>(k)]);
                ++n;
            }
        }
        if (n == 3)
            c.from = fmt::format("{} (run case {} {})", run->where("X_cg"), run->number, given);
        else if (n > 0)
            c.from = fmt::format("{} (run case {} {}), the rest from {}", run->where(keys[0]),
                                 run->number, given, c.from);
    }
    return c;
}

void apply_run_case(Model& model, const RunCase& run) {
    if (const auto m = run.parameter("Mach")) model.mach = *m;
    if (const auto cd = run.parameter("CDo")) model.profile_drag = *cd;
}

RunCaseSolution solve_run_case(const SteadySolver& solver, const RunCase& run) {
    const auto& controls = solver.lattice().control_names;
    const int nc = static_cast<int>(controls.size());
    const int n = 5 + nc;
    const auto control_index = [&](const std::string& name) {
        const auto it = std::find(controls.begin(), controls.end(), name);
        return it == controls.end() ? -1 : static_cast<int>(it - controls.begin());
    };
    const auto known_controls = [&] {
        std::string s;
        for (const auto& c : controls) s += fmt::format("{}{}", s.empty() ? "" : ", ", c);
        return s.empty() ? std::string("(none)") : s;
    };
    // Each variable's constraint: AVL's default is the variable itself = 0.
    std::vector<Target> target(static_cast<std::size_t>(n));
    std::vector<int> target_control(static_cast<std::size_t>(n), -1);
    std::vector<double> value(static_cast<std::size_t>(n), 0.0);
    std::vector<int> line(static_cast<std::size_t>(n), 0);
    for (int i = 0; i < n; ++i) {
        target[static_cast<std::size_t>(i)] = i < 5 ? static_cast<Target>(i) : Target::control;
        target_control[static_cast<std::size_t>(i)] = i < 5 ? -1 : i - 5;
    }
    for (const RunConstraint& c : run.constraints) {
        int v = -1;
        for (int k = 0; k < 5; ++k)
            if (c.variable == rate_and_angle_names[static_cast<std::size_t>(k)]) v = k;
        if (v < 0) {
            const int k = control_index(c.variable);
            if (k < 0)
                throw InputError(fmt::format(
                    "{}:{}: variable '{}' of run case {} is not a control of this model; expected "
                    "alpha, beta, pb/2V, qc/2V, rb/2V or one of its controls: {}",
                    run.source, c.line, c.variable, run.number, known_controls()));
            v = 5 + k;
        }
        const auto vi = static_cast<std::size_t>(v);
        static const std::array<std::pair<const char*, Target>, 10> fixed = {
            {{"alpha", Target::alpha},
             {"beta", Target::beta},
             {"pb/2V", Target::p},
             {"qc/2V", Target::q},
             {"rb/2V", Target::r},
             {"CL", Target::CL},
             {"CY", Target::CY},
             {"Cl", Target::Cl},
             {"Cm", Target::Cm},
             {"Cn", Target::Cn}}};
        bool found = false;
        for (const auto& [name, t] : fixed) {
            if (c.constraint == name) {
                target[vi] = t;
                target_control[vi] = -1;
                found = true;
            }
        }
        if (!found) {
            const int k = control_index(c.constraint);
            if (k < 0)
                throw InputError(fmt::format(
                    "{}:{}: constraint '{}' of run case {} is not a control of this model; "
                    "expected alpha, beta, pb/2V, qc/2V, rb/2V, CL, CY, Cl roll mom, Cm pitchmom, "
                    "Cn yaw mom or one of its controls: {}",
                    run.source, c.line, c.constraint, run.number, known_controls()));
            target[vi] = Target::control;
            target_control[vi] = k;
        }
        value[vi] = c.value;
        line[vi] = c.line;
    }
    // A constraint may serve one variable only (a default "flap -> flap" included).
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j) {
            const auto a = static_cast<std::size_t>(i), b = static_cast<std::size_t>(j);
            if (target[a] == target[b] && target_control[a] == target_control[b]) {
                const auto k = line[a] != 0 ? a : b;
                const auto name = [&](std::size_t x) {
                    return x < 5 ? std::string(rate_and_angle_names[x]) : controls[x - 5];
                };
                throw InputError(fmt::format(
                    "{}:{}: run case {} constrains '{}' and '{}' by the same quantity (a variable "
                    "without a constraint line is held at 0 by itself); expected each constraint "
                    "once",
                    run.source, line[k] != 0 ? line[k] : run.line, run.number, name(a), name(b)));
            }
        }

    // Unknowns: alpha, beta [rad], stability-axis rates p', q, r' (non-dimensional), deflections
    // [rad]. Start from the run case's parameter values, then the direct constraints.
    Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
    x[0] = run.parameter("alpha").value_or(0.0) * deg;
    x[1] = run.parameter("beta").value_or(0.0) * deg;
    x[2] = run.parameter("pb/2V").value_or(0.0);
    x[3] = run.parameter("qc/2V").value_or(0.0);
    x[4] = run.parameter("rb/2V").value_or(0.0);
    for (int i = 0; i < n; ++i) {
        const auto ii = static_cast<std::size_t>(i);
        const bool direct =
            (i < 5 && target[ii] == static_cast<Target>(i)) ||
            (i >= 5 && target[ii] == Target::control && target_control[ii] == i - 5);
        if (direct) x[i] = (i < 2 || i >= 5) ? value[ii] * deg : value[ii];
    }
    const auto state_of = [&](const Eigen::VectorXd& u) {
        FlowState s;
        s.alpha = u[0];
        s.beta = u[1];
        const double ca = std::cos(u[0]), sa = std::sin(u[0]);
        s.p_hat = u[2] * ca - u[4] * sa;
        s.q_hat = u[3];
        s.r_hat = u[2] * sa + u[4] * ca;
        s.deflection = u.tail(nc);
        return s;
    };

    constexpr int max_iterations = 30;
    constexpr double tolerance = 1e-10;
    RunCaseSolution sol;
    Eigen::VectorXd res(n);
    Eigen::MatrixXd jac(n, n);
    for (int it = 0;; ++it) {
        sol.state = state_of(x);
        sol.derivatives = solver.derivatives(sol.state);
        const Derivatives& d = sol.derivatives;
        const SteadyResult& r = d.state;
        const double ca = std::cos(x[0]), sa = std::sin(x[0]);
        jac.setZero();
        for (int i = 0; i < n; ++i) {
            const auto ii = static_cast<std::size_t>(i);
            const double v = value[ii];
            int row = -1;  // row of the derivative matrices
            double f = 0.0;
            switch (target[ii]) {
                case Target::alpha:
                case Target::beta:
                    res[i] = x[static_cast<int>(target[ii])] - v * deg;
                    jac(i, static_cast<int>(target[ii])) = 1.0;
                    continue;
                case Target::p:
                case Target::q:
                case Target::r:
                    res[i] = x[static_cast<int>(target[ii])] - v;
                    jac(i, static_cast<int>(target[ii])) = 1.0;
                    continue;
                case Target::control:
                    res[i] = x[5 + target_control[ii]] - v * deg;
                    jac(i, 5 + target_control[ii]) = 1.0;
                    continue;
                case Target::CL:
                    row = 0, f = r.CL;
                    break;
                case Target::CY:
                    row = 2, f = r.body.CY;
                    break;
                case Target::Cl:
                    row = 3, f = r.body.Cl * ca + r.body.Cn * sa;
                    break;
                case Target::Cm:
                    row = 4, f = r.body.Cm;
                    break;
                case Target::Cn:
                    row = 5, f = r.body.Cn * ca - r.body.Cl * sa;
                    break;
            }
            res[i] = f - v;
            jac.block(i, 0, 1, 5) = d.stability.row(row);
            if (nc > 0) jac.block(i, 5, 1, nc) = d.control_stability.row(row);
        }
        sol.iterations = it;
        sol.residual = res.cwiseAbs().maxCoeff();
        if (!std::isfinite(sol.residual))
            throw ConvergenceError(fmt::format(
                "{}:{}: run case {}: the solution is not finite after {} Newton iterations",
                run.source, run.line, run.number, it));
        if (sol.residual < tolerance) return sol;
        if (it == max_iterations)
            throw ConvergenceError(fmt::format(
                "{}:{}: run case {}: the constraints are not met after {} Newton iterations "
                "(largest residual {:.3g}); expected constraints the aircraft can meet",
                run.source, run.line, run.number, it, sol.residual));
        // Rank to a relative 1e-7: a derivative that is zero by symmetry comes out of the
        // single-precision influence matrices at about 1e-8 of the largest.
        constexpr double rank_threshold = 1e-7;
        Eigen::FullPivLU<Eigen::MatrixXd> lu(jac);
        lu.setThreshold(rank_threshold);
        if (lu.rank() < n) {
            // Name a constraint that no variable moves, or a variable that moves no constraint.
            const double small = rank_threshold * jac.cwiseAbs().maxCoeff();
            const auto var_name = [&](int i) {
                return i < 5 ? std::string(rate_and_angle_names[static_cast<std::size_t>(i)])
                             : controls[static_cast<std::size_t>(i - 5)];
            };
            const auto at = [&](int i) {
                const int l = line[static_cast<std::size_t>(i)];
                return l != 0 ? fmt::format("line {}", l) : std::string("no line, held at 0");
            };
            std::string which;
            for (int i = 0; i < n && which.empty(); ++i)
                if (jac.row(i).cwiseAbs().maxCoeff() < small)
                    which = fmt::format(
                        " (the constraint of '{}', {}, does not change with any "
                        "variable)",
                        var_name(i), at(i));
            for (int j = 0; j < n && which.empty(); ++j)
                if (jac.col(j).cwiseAbs().maxCoeff() < small)
                    which = fmt::format(" ('{}', {}, changes none of the constrained quantities)",
                                        var_name(j), at(j));
            throw ConvergenceError(fmt::format(
                "{}:{}: run case {}: the constraints do not determine the variables (singular "
                "Jacobian){}; expected constraints that the variables can meet",
                run.source, run.line, run.number, which));
        }
        Eigen::VectorXd dx = lu.solve(-res);
        // Steps of at most 5 deg in the angles and deflections keep Newton in the linear range.
        double big = 0.0;
        for (int i = 0; i < n; ++i)
            if (i < 2 || i >= 5) big = std::max(big, std::abs(dx[i]));
        if (big > 5.0 * deg) dx *= 5.0 * deg / big;
        x += dx;
    }
}

}  // namespace manta::vlm
