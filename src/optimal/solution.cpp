/// @file solution.cpp
/// Problem and mesh checks, initial guesses, solution interpolation, CSV and failure report.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/optimal/lgl.hpp"
#include "manta/optimal/solve.hpp"

namespace manta::optimal {

namespace {

void check_bounds(const std::string& where, double lo, double hi) {
    if (std::isnan(lo) || std::isnan(hi) || lo > hi) {
        throw InputError(
            fmt::format("{}: bounds [{}, {}], expected lower <= upper", where, lo, hi));
    }
}

/// Index of `name` among `items` (with a `name` member, or a Constraint); InputError listing
/// the known names otherwise.
template <class V>
int find_name(const std::string& who, const char* kind, const std::vector<V>& items,
              std::string_view name) {
    for (std::size_t i = 0; i < items.size(); ++i) {
        if (items[i].name == name) return static_cast<int>(i);
    }
    std::string known;
    for (const auto& v : items) known += (known.empty() ? "" : ", ") + v.name;
    throw InputError(fmt::format("{}: no {} named '{}', expected one of: {}", who, kind, name,
                                 known.empty() ? std::string("(none)") : known));
}

std::string problem_label(const std::string& name) {
    return "optimal control problem '" + name + "'";
}

/// A value inside the bounds: v moved into [lo, hi].
double into(double v, double lo, double hi) {
    return std::clamp(v, lo, std::max(lo, hi));
}

/// JSON string literal of s (quotes, backslashes and control characters escaped).
std::string json_string(std::string_view s) {
    std::string r = "\"";
    for (const char c : s) {
        if (c == '"' || c == '\\') {
            r += '\\';
            r += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            r += fmt::format("\\u{:04x}", static_cast<int>(c));
        } else {
            r += c;
        }
    }
    return r + "\"";
}

/// JSON number (null for NaN or infinity).
std::string json_number(double v) {
    return std::isfinite(v) ? fmt::format("{:.17g}", v) : std::string("null");
}

}  // namespace

int ProblemInfo::state_index(std::string_view n) const {
    return find_name(problem_label(name), "state", states, n);
}
int ProblemInfo::control_index(std::string_view n) const {
    return find_name(problem_label(name), "control", controls, n);
}
int ProblemInfo::parameter_index(std::string_view n) const {
    return find_name(problem_label(name), "parameter", parameters, n);
}
int ProblemInfo::integral_index(std::string_view n) const {
    return find_name(problem_label(name), "integral constraint", integrals, n);
}

void ProblemInfo::set_initial(std::string_view state, Bounds b) {
    const auto r = idx(state_index(state));
    if (initial_states.empty()) initial_states.assign(states.size(), Bounds{});
    initial_states.at(r) = b;
}

void ProblemInfo::set_final(std::string_view state, Bounds b) {
    const auto r = idx(state_index(state));
    if (final_states.empty()) final_states.assign(states.size(), Bounds{});
    final_states.at(r) = b;
}

void ProblemInfo::validate() const {
    const std::string who = "optimal control problem '" + name + "'";
    if (states.empty()) throw InputError(who + ": no states, expected at least one");
    std::set<std::string> seen;
    auto check_var = [&](const Variable& v, const char* kind) {
        if (v.name.empty()) throw InputError(who + ": a " + kind + " without a name");
        if (!seen.insert(v.name).second) {
            throw InputError(who + ": name '" + v.name + "' used twice, expected unique names");
        }
        check_bounds(who + " " + kind + " '" + v.name + "'", v.lower, v.upper);
        if (v.scale < 0.0 || !std::isfinite(v.scale)) {
            throw InputError(
                fmt::format("{}: {} '{}' scale {}, expected >= 0", who, kind, v.name, v.scale));
        }
        if (v.ref0 && !v.ref) {
            throw InputError(fmt::format("{}: {} '{}' has ref0 = {} but no ref, expected ref too",
                                         who, kind, v.name, *v.ref0));
        }
        if (v.ref) {
            const double r0 = v.ref0.value_or(0.0);
            if (!std::isfinite(*v.ref) || !std::isfinite(r0) || *v.ref == r0) {
                throw InputError(fmt::format(
                    "{}: {} '{}' ref = {} and ref0 = {}, expected finite and different values", who,
                    kind, v.name, *v.ref, r0));
            }
        }
        if (v.has_rate_bounds() && std::string_view(kind) != "control") {
            throw InputError(
                fmt::format("{}: {} '{}' has rate bounds [{}, {}], expected them on controls only",
                            who, kind, v.name, v.rate.lower, v.rate.upper));
        }
        check_bounds(who + " " + kind + " '" + v.name + "' rate", v.rate.lower, v.rate.upper);
    };
    for (const auto& v : states) check_var(v, "state");
    for (const auto& v : controls) check_var(v, "control");
    for (const auto& v : parameters) check_var(v, "parameter");
    for (const auto& c : path)
        check_bounds(who + " path constraint '" + c.name + "'", c.lower, c.upper);
    for (const auto& c : events) check_bounds(who + " event '" + c.name + "'", c.lower, c.upper);
    std::set<std::string> integral_names;
    for (const auto& c : integrals) {
        if (c.name.empty()) throw InputError(who + ": an integral constraint without a name");
        if (!integral_names.insert(c.name).second) {
            throw InputError(who + ": integral constraint name '" + c.name +
                             "' used twice, expected unique names");
        }
        check_bounds(who + " integral constraint '" + c.name + "'", c.lower, c.upper);
    }
    for (const auto& e : interior_events) {
        check_bounds(who + " interior event '" + e.constraint.name + "'", e.constraint.lower,
                     e.constraint.upper);
        if (e.junction < 1) {
            throw InputError(fmt::format("{}: interior event '{}' at junction {}, expected >= 1",
                                         who, e.constraint.name, e.junction));
        }
    }
    check_bounds(who + " initial time", initial_time.lower, initial_time.upper);
    check_bounds(who + " final time", final_time.lower, final_time.upper);
    if (!initial_states.empty() && initial_states.size() != states.size()) {
        throw InputError(fmt::format("{}: {} initial-state bounds, expected {} (one per state)",
                                     who, initial_states.size(), states.size()));
    }
    if (!final_states.empty() && final_states.size() != states.size()) {
        throw InputError(fmt::format("{}: {} final-state bounds, expected {} (one per state)", who,
                                     final_states.size(), states.size()));
    }
    // Boundary bounds must meet the state's own bounds: the NLP takes their intersection.
    auto check_meets = [&](const Bounds& b, const Variable& v, const char* which) {
        if (b.lower > v.upper || b.upper < v.lower)
            throw InputError(fmt::format(
                "{}: {} {} in [{:g}, {:g}] lies outside the state's bounds [{:g}, {:g}]; "
                "expected a {} value within them",
                who, which, v.name, b.lower, b.upper, v.lower, v.upper, which));
    };
    for (std::size_t r = 0; r < initial_states.size(); ++r) {
        check_bounds(who + " initial '" + states[r].name + "'", initial_states[r].lower,
                     initial_states[r].upper);
        check_meets(initial_states[r], states[r], "initial");
    }
    for (std::size_t r = 0; r < final_states.size(); ++r) {
        check_bounds(who + " final '" + states[r].name + "'", final_states[r].lower,
                     final_states[r].upper);
        check_meets(final_states[r], states[r], "final");
    }
}

Mesh Mesh::uniform(int segments, int nodes_per_segment) {
    if (segments < 1) {
        throw InputError(fmt::format("mesh: {} segments, expected at least 1", segments));
    }
    Mesh m;
    m.nodes.assign(static_cast<std::size_t>(segments), nodes_per_segment);
    for (int k = 0; k <= segments; ++k) m.breaks.push_back(static_cast<double>(k) / segments);
    m.validate();
    return m;
}

void Mesh::validate() const {
    if (nodes.empty()) throw InputError("mesh: no segments, expected at least 1");
    for (const int n : nodes) {
        if (n < 2) throw InputError(fmt::format("mesh: {} nodes in a segment, expected >= 2", n));
    }
    if (breaks.size() != nodes.size() + 1) {
        throw InputError(fmt::format("mesh: {} breaks for {} segments, expected {}", breaks.size(),
                                     nodes.size(), nodes.size() + 1));
    }
    if (breaks.front() != 0.0 || breaks.back() != 1.0) {
        throw InputError(fmt::format("mesh: breaks from {} to {}, expected 0 to 1", breaks.front(),
                                     breaks.back()));
    }
    for (std::size_t k = 1; k < breaks.size(); ++k) {
        if (!(breaks[k] > breaks[k - 1])) {
            throw InputError(fmt::format("mesh: break {} = {} not above the previous {}", k,
                                         breaks[k], breaks[k - 1]));
        }
    }
    for (std::size_t i = 0; i < phase_breaks.size(); ++i) {
        const int k = phase_breaks[i];
        if (k < 1 || k >= static_cast<int>(nodes.size()) || (i > 0 && k <= phase_breaks[i - 1])) {
            throw InputError(fmt::format(
                "mesh: phase break {} of {} segments, expected increasing indices 1 to {}", k,
                nodes.size(), nodes.size() - 1));
        }
    }
    if (!(min_segment_fraction > 0.0) ||
        min_segment_fraction * static_cast<double>(nodes.size()) >= 1.0) {
        throw InputError(fmt::format("mesh: min_segment_fraction {}, expected in (0, 1/K)",
                                     min_segment_fraction));
    }
}

Guess Guess::linear(double t0, double tf, const Eigen::VectorXd& x0, const Eigen::VectorXd& xf,
                    const Eigen::VectorXd& u0, const Eigen::VectorXd& uf,
                    const Eigen::VectorXd& parameters) {
    if (x0.size() != xf.size() || u0.size() != uf.size()) {
        throw InputError("linear guess: initial and final vectors of different sizes");
    }
    Eigen::MatrixXd x(2, x0.size());
    x.row(0) = x0.transpose();
    x.row(1) = xf.transpose();
    Eigen::MatrixXd u(2, u0.size());
    u.row(0) = u0.transpose();
    u.row(1) = uf.transpose();
    return from_history({t0, tf}, std::move(x), std::move(u), parameters);
}

Guess Guess::linear(const ProblemInfo& info, double t0, double tf,
                    const std::vector<NamedValue>& values) {
    const std::string who = "guess of " + problem_label(info.name);
    if (!(tf > t0)) {
        throw InputError(fmt::format("{}: t0 = {}, tf = {}, expected tf > t0", who, t0, tf));
    }
    const auto nx = static_cast<Eigen::Index>(info.states.size());
    const auto nu = static_cast<Eigen::Index>(info.controls.size());
    const auto np = static_cast<Eigen::Index>(info.parameters.size());
    Eigen::MatrixXd x(2, nx), u(2, nu);
    Eigen::VectorXd p(np);
    // defaults: fixed boundary values, else 0 moved into the bounds
    for (Eigen::Index r = 0; r < nx; ++r) {
        const Variable& v = info.states[static_cast<std::size_t>(r)];
        const double mid = into(0.0, v.lower, v.upper);
        const auto ri = static_cast<std::size_t>(r);
        const bool f0 = !info.initial_states.empty() && info.initial_states[ri].is_fixed();
        const bool ff = !info.final_states.empty() && info.final_states[ri].is_fixed();
        x(0, r) = f0 ? info.initial_states[ri].lower : mid;
        x(1, r) = ff ? info.final_states[ri].lower : mid;
    }
    for (Eigen::Index j = 0; j < nu; ++j) {
        const Variable& v = info.controls[static_cast<std::size_t>(j)];
        u(0, j) = u(1, j) = into(0.0, v.lower, v.upper);
    }
    for (Eigen::Index j = 0; j < np; ++j) {
        const Variable& v = info.parameters[static_cast<std::size_t>(j)];
        p(j) = into(0.0, v.lower, v.upper);
    }
    std::set<std::string> seen;
    auto check = [&](const Variable& v, double value, const char* when) {
        if (std::isnan(value) || value < v.lower || value > v.upper) {
            throw InputError(fmt::format("{}: '{}' = {} at {}, outside its bounds [{}, {}]", who,
                                         v.name, value, when, v.lower, v.upper));
        }
    };
    for (const NamedValue& nv : values) {
        if (!seen.insert(nv.name).second) {
            throw InputError(fmt::format("{}: '{}' given twice, expected once", who, nv.name));
        }
        const auto is = [&](const std::vector<Variable>& vs) {
            return std::any_of(vs.begin(), vs.end(),
                               [&](const Variable& v) { return v.name == nv.name; });
        };
        if (is(info.states)) {
            const auto r = info.state_index(nv.name);
            const Variable& v = info.states[static_cast<std::size_t>(r)];
            check(v, nv.start, "t0");
            check(v, nv.end, "tf");
            x(0, r) = nv.start;
            x(1, r) = nv.end;
        } else if (is(info.controls)) {
            const auto j = info.control_index(nv.name);
            const Variable& v = info.controls[static_cast<std::size_t>(j)];
            check(v, nv.start, "t0");
            check(v, nv.end, "tf");
            u(0, j) = nv.start;
            u(1, j) = nv.end;
        } else if (is(info.parameters)) {
            const auto j = info.parameter_index(nv.name);
            check(info.parameters[static_cast<std::size_t>(j)], nv.start, "t0");
            p(j) = nv.start;
        } else {
            std::string known;
            for (const auto* vs : {&info.states, &info.controls, &info.parameters}) {
                for (const auto& v : *vs) known += (known.empty() ? "" : ", ") + v.name;
            }
            throw InputError(
                fmt::format("{}: no state, control or parameter named '{}', "
                            "expected one of: {}",
                            who, nv.name, known));
        }
    }
    return from_history({t0, tf}, std::move(x), std::move(u), p);
}

void validate_guess(const ProblemInfo& info, const Guess& guess) {
    const std::string who = "guess of " + problem_label(info.name);
    std::vector<double> times = guess.time_;
    if (guess.solution_) times = guess.solution_->node_times();
    if (times.empty()) times = {guess.t0_, guess.tf_};
    Eigen::VectorXd x, u;
    auto check = [&](const Variable& v, const char* kind, double value, double t) {
        if (std::isnan(value) || value < v.lower || value > v.upper) {
            throw InputError(fmt::format("{}: {} '{}' = {} at t = {}, outside its bounds [{}, {}]",
                                         who, kind, v.name, value, t, v.lower, v.upper));
        }
    };
    for (const double t : times) {
        guess.at(t, x, u);
        if (x.size() != info.n_states() || u.size() != info.n_controls()) {
            throw InputError(fmt::format("{}: {} states and {} controls, expected {} and {}", who,
                                         x.size(), u.size(), info.n_states(), info.n_controls()));
        }
        for (Eigen::Index r = 0; r < x.size(); ++r)
            check(info.states[static_cast<std::size_t>(r)], "state", x(r), t);
        for (Eigen::Index j = 0; j < u.size(); ++j)
            check(info.controls[static_cast<std::size_t>(j)], "control", u(j), t);
    }
    for (Eigen::Index j = 0; j < guess.p_.size() && j < info.n_parameters(); ++j)
        check(info.parameters[static_cast<std::size_t>(j)], "parameter", guess.p_(j), guess.t0_);
    const auto check_time = [&](const char* what, double value, const Bounds& b) {
        if (value < b.lower || value > b.upper) {
            throw InputError(fmt::format("{}: {} = {}, outside its bounds [{}, {}]", who, what,
                                         value, b.lower, b.upper));
        }
    };
    check_time("initial time", guess.t0_, info.initial_time);
    check_time("final time", guess.tf_, info.final_time);
}

Guess Guess::from_history(std::vector<double> time, Eigen::MatrixXd states,
                          Eigen::MatrixXd controls, const Eigen::VectorXd& parameters) {
    if (time.size() < 2) {
        throw InputError(
            fmt::format("guess history: {} samples, expected at least 2", time.size()));
    }
    for (std::size_t i = 1; i < time.size(); ++i) {
        if (!(time[i] > time[i - 1])) {
            throw InputError(fmt::format("guess history: time {} at sample {} not above {}",
                                         time[i], i, time[i - 1]));
        }
    }
    if (states.rows() != static_cast<Eigen::Index>(time.size()) ||
        controls.rows() != static_cast<Eigen::Index>(time.size())) {
        throw InputError(fmt::format("guess history: {} times but {} state and {} control rows",
                                     time.size(), states.rows(), controls.rows()));
    }
    Guess g;
    g.t0_ = time.front();
    g.tf_ = time.back();
    g.p_ = parameters;
    g.time_ = std::move(time);
    g.x_ = std::move(states);
    g.u_ = std::move(controls);
    return g;
}

Guess Guess::from_solution(const Solution& previous) {
    Guess g;
    g.t0_ = previous.initial_time;
    g.tf_ = previous.final_time;
    g.p_ = previous.parameters;
    g.solution_ = std::make_shared<const Solution>(previous);
    return g;
}

void Guess::at(double t, Eigen::VectorXd& x, Eigen::VectorXd& u) const {
    if (solution_) {
        x = solution_->state(t);
        u = solution_->control(t);
        return;
    }
    const auto it = std::upper_bound(time_.begin(), time_.end(), t);
    std::size_t i = it == time_.begin() ? 0 : static_cast<std::size_t>(it - time_.begin()) - 1;
    i = std::min(i, time_.size() - 2);
    const double a = std::clamp((t - time_[i]) / (time_[i + 1] - time_[i]), 0.0, 1.0);
    const auto ii = static_cast<Eigen::Index>(i);
    x = ((1.0 - a) * x_.row(ii) + a * x_.row(ii + 1)).transpose();
    u = ((1.0 - a) * u_.row(ii) + a * u_.row(ii + 1)).transpose();
}

int Solution::segment_of(double t) const {
    const int K = static_cast<int>(segments.size());
    for (int k = 0; k < K - 1; ++k) {
        if (t < breaks[static_cast<std::size_t>(k) + 1]) return k;
    }
    return K - 1;
}

Eigen::VectorXd Solution::interpolate(double t, int which) const {
    if (segments.empty()) return {};
    const int k = segment_of(t);
    const SegmentSolution& s = segments[static_cast<std::size_t>(k)];
    const double a = breaks[static_cast<std::size_t>(k)];
    const double b = breaks[static_cast<std::size_t>(k) + 1];
    const double tau = b > a ? std::clamp(2.0 * (t - a) / (b - a) - 1.0, -1.0, 1.0) : -1.0;
    const Eigen::RowVectorXd ell = lagrange_basis(s.tau, s.bary, tau);
    const Eigen::MatrixXd& m = which == 0 ? s.states : which == 1 ? s.controls : s.costates;
    return (ell * m).transpose();
}

Eigen::VectorXd Solution::state(double t) const {
    return interpolate(t, 0);
}
Eigen::VectorXd Solution::control(double t) const {
    return interpolate(t, 1);
}
Eigen::VectorXd Solution::costate(double t) const {
    return interpolate(t, 2);
}

int Solution::n_nodes() const {
    int n = 0;
    for (const auto& s : segments) n += static_cast<int>(s.time.size());
    return n;
}

double Solution::state(double t, std::string_view name) const {
    return state(t)(info.state_index(name));
}
double Solution::control(double t, std::string_view name) const {
    const int j = info.control_index(name);
    return control(t)(j);
}
double Solution::initial_state(std::string_view name) const {
    const int r = info.state_index(name);
    if (segments.empty()) return std::nan("");
    return segments.front().states(0, r);
}
double Solution::final_state(std::string_view name) const {
    const int r = info.state_index(name);
    if (segments.empty()) return std::nan("");
    const Eigen::MatrixXd& x = segments.back().states;
    return x(x.rows() - 1, r);
}
double Solution::parameter(std::string_view name) const {
    return parameters(info.parameter_index(name));
}
double Solution::integral(std::string_view name) const {
    const int j = info.integral_index(name);
    return j < integrals.size() ? integrals(j) : std::nan("");
}

std::vector<double> Solution::node_times() const {
    std::vector<double> t;
    for (const auto& s : segments) {
        for (Eigen::Index i = 0; i < s.time.size(); ++i) t.push_back(s.time(i));
    }
    return t;
}

std::vector<double> Solution::history(std::string_view name) const {
    const bool is_state = std::any_of(info.states.begin(), info.states.end(),
                                      [&](const Variable& v) { return v.name == name; });
    const int c = is_state ? info.state_index(name) : info.control_index(name);
    std::vector<double> h;
    for (const auto& s : segments) {
        const Eigen::MatrixXd& m = is_state ? s.states : s.controls;
        for (Eigen::Index i = 0; i < m.rows(); ++i) h.push_back(m(i, c));
    }
    return h;
}

std::string to_string(SolveStatus status) {
    switch (status) {
        case SolveStatus::solved:
            return "solved";
        case SolveStatus::solved_acceptable:
            return "solved_acceptable";
        case SolveStatus::solved_unresolved:
            return "solved_unresolved";
        case SolveStatus::infeasible:
            return "infeasible";
        case SolveStatus::iteration_limit:
            return "iteration_limit";
        case SolveStatus::stopped:
            return "stopped";
        case SolveStatus::failed:
            return "failed";
    }
    return "unknown";
}

std::string failure_report(const Solution& sol, const std::filesystem::path& csv) {
    std::string r = fmt::format(
        "optimal control problem '{}' not solved: IPOPT {} after {} iterations "
        "({:.3f} s CPU)\n",
        sol.info.name, sol.status_text, sol.iterations, sol.cpu_time);
    r += fmt::format(
        "  best iterate: max constraint violation {:.3e} (scaled {:.3e}), "
        "objective {:.10g}, tf {:.6g}\n",
        sol.max_violation, sol.max_scaled_violation, sol.objective, sol.final_time);
    if (!sol.violations.empty()) {
        r += "  most violated constraints (scaled violation, worst first):\n";
        for (const Violation& v : sol.violations) {
            const std::string where = v.segment >= 0 ? fmt::format("segment {} node {} t = {:.6g}",
                                                                   v.segment, v.node, v.time)
                                                     : fmt::format("t = {:.6g}", v.time);
            r += fmt::format(
                "    {:<8} {:<28} {}: value {:.6g}, bounds [{:.6g}, {:.6g}], "
                "violation {:.3e} (scaled {:.3e})\n",
                v.kind, v.name, where, v.value, v.lower, v.upper, v.amount, v.scaled);
        }
    }
    if (!csv.empty()) r += "  best iterate written to " + csv.string() + "\n";
    return r;
}

std::string summary(const Solution& sol) {
    const ProblemInfo& info = sol.info;
    std::string r =
        fmt::format("{}: {}, {} {:.10g} after {} iterations, t0 {:.10g}, tf {:.10g}\n", info.name,
                    to_string(sol.status), info.maximise ? "maximum" : "minimum", sol.objective,
                    sol.iterations, sol.initial_time, sol.final_time);
    std::size_t w = 8;
    for (const auto* vs : {&info.states, &info.parameters})
        for (const auto& v : *vs) w = std::max(w, v.name.size());
    for (const auto& c : info.integrals) w = std::max(w, c.name.size());
    if (!info.parameters.empty()) {
        r += "  parameters\n";
        for (std::size_t j = 0; j < info.parameters.size(); ++j) {
            r += fmt::format("    {:<{}} {:.10g}\n", info.parameters[j].name, w,
                             sol.parameters(static_cast<Eigen::Index>(j)));
        }
    }
    if (!sol.segments.empty()) {
        r += fmt::format("  {:<{}}   {:>17} {:>17}\n", "state", w + 2, "x(t0)", "x(tf)");
        for (const auto& v : info.states) {
            r += fmt::format("    {:<{}} {:>17.10g} {:>17.10g}\n", v.name, w,
                             sol.initial_state(v.name), sol.final_state(v.name));
        }
    }
    if (!info.integrals.empty()) {
        r += "  integrals\n";
        for (std::size_t j = 0; j < info.integrals.size(); ++j) {
            const Constraint& c = info.integrals[j];
            r += fmt::format("    {:<{}} {:.10g} in [{:g}, {:g}]\n", c.name, w,
                             sol.integral(c.name), c.lower, c.upper);
        }
    }
    return r;
}

std::string to_json(const Solution& sol) {
    const ProblemInfo& info = sol.info;
    std::string j = "{";
    j += "\"problem\": " + json_string(info.name);
    j += ", \"status\": " + json_string(to_string(sol.status));
    j += fmt::format(", \"converged\": {}, \"resolved\": {}", sol.converged(), sol.resolved());
    j += fmt::format(", \"sense\": \"{}\"", info.maximise ? "maximise" : "minimise");
    j += ", \"objective\": " + json_number(sol.objective);
    j += ", \"initial_time\": " + json_number(sol.initial_time);
    j += ", \"final_time\": " + json_number(sol.final_time);
    j += fmt::format(", \"iterations\": {}", sol.iterations);
    auto object = [&](const char* key, auto&& items, auto&& value) {
        j += fmt::format(", \"{}\": {{", key);
        bool first = true;
        for (const auto& v : items) {
            j += (first ? "" : ", ") + json_string(v.name) + ": " + json_number(value(v.name));
            first = false;
        }
        j += "}";
    };
    object("parameters", info.parameters, [&](const std::string& n) { return sol.parameter(n); });
    const bool have = !sol.segments.empty();
    object("initial_states", info.states,
           [&](const std::string& n) { return have ? sol.initial_state(n) : std::nan(""); });
    object("final_states", info.states,
           [&](const std::string& n) { return have ? sol.final_state(n) : std::nan(""); });
    object("integrals", info.integrals, [&](const std::string& n) { return sol.integral(n); });
    auto array = [&](const std::vector<double>& v) {
        std::string a = "[";
        for (std::size_t i = 0; i < v.size(); ++i) a += (i ? ", " : "") + json_number(v[i]);
        return a + "]";
    };
    j += ", \"nodes\": {\"t\": " + array(sol.node_times());
    for (const auto* vs : {&info.states, &info.controls}) {
        for (const auto& v : *vs)
            j += ", " + json_string(v.name) + ": " + array(sol.history(v.name));
    }
    j += "}}";
    return j;
}

void write_csv(const Solution& sol, const std::filesystem::path& file) {
    std::ostringstream out;
    out << "t,segment,node";
    for (const auto& v : sol.info.states) out << ',' << v.name;
    for (const auto& v : sol.info.controls) out << ',' << v.name;
    for (const auto& v : sol.info.states) out << ",lambda_" << v.name;
    for (const auto& c : sol.info.path) out << ',' << c.name;
    out << '\n';
    for (std::size_t k = 0; k < sol.segments.size(); ++k) {
        const SegmentSolution& s = sol.segments[k];
        for (Eigen::Index i = 0; i < s.time.size(); ++i) {
            out << fmt::format("{:.17g},{},{}", s.time(i), k, i);
            for (Eigen::Index r = 0; r < s.states.cols(); ++r)
                out << fmt::format(",{:.17g}", s.states(i, r));
            for (Eigen::Index r = 0; r < s.controls.cols(); ++r)
                out << fmt::format(",{:.17g}", s.controls(i, r));
            for (Eigen::Index r = 0; r < s.costates.cols(); ++r)
                out << fmt::format(",{:.17g}", s.costates(i, r));
            for (Eigen::Index r = 0; r < s.path.cols(); ++r)
                out << fmt::format(",{:.17g}", s.path(i, r));
            out << '\n';
        }
    }
    core::write_file_atomic(file, out.str());  // creates the folder
}

}  // namespace manta::optimal
