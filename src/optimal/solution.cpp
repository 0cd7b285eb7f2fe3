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

}  // namespace

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
    };
    for (const auto& v : states) check_var(v, "state");
    for (const auto& v : controls) check_var(v, "control");
    for (const auto& v : parameters) check_var(v, "parameter");
    for (const auto& c : path)
        check_bounds(who + " path constraint '" + c.name + "'", c.lower, c.upper);
    for (const auto& c : events) check_bounds(who + " event '" + c.name + "'", c.lower, c.upper);
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
        check_bounds(who + " initial " + states[r].name, initial_states[r].lower,
                     initial_states[r].upper);
        check_meets(initial_states[r], states[r], "initial");
    }
    for (std::size_t r = 0; r < final_states.size(); ++r) {
        check_bounds(who + " final " + states[r].name, final_states[r].lower,
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
