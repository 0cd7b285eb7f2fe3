/// @file refine.cpp
/// Error-driven ph mesh refinement (refine.hpp; Patterson, Hager & Rao, Optim. Control Appl.
/// Meth. 36, 2015): segment error estimates, the ph rule, and the adaptive solve loop.

#include "manta/optimal/refine.hpp"

#include <fmt/format.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>

#include "manta/core/error.hpp"
#include "manta/optimal/lgl.hpp"

namespace manta::optimal {

void RefinementOptions::validate() const {
    auto fail = [](const char* key, double v, const char* expected) {
        throw InputError(fmt::format("refinement option {} = {}, expected {}", key, v, expected));
    };
    if (!(tolerance > 0.0) || !std::isfinite(tolerance)) fail("tolerance", tolerance, "> 0");
    if (min_nodes < 2) fail("min_nodes", min_nodes, ">= 2");
    if (max_nodes < min_nodes) fail("max_nodes", max_nodes, ">= min_nodes");
    if (max_passes < 1) fail("max_passes", max_passes, ">= 1");
    if (max_total_nodes < 2) fail("max_total_nodes", max_total_nodes, ">= 2");
    if (extra_points < 1) fail("extra_points", extra_points, ">= 1");
    if (!(jump_threshold > 0.0) || !(jump_threshold <= 1.0))
        fail("jump_threshold", jump_threshold, "in (0, 1]");
}

std::string to_string(RefinementStatus status) {
    switch (status) {
        case RefinementStatus::tolerance_met:
            return "tolerance_met";
        case RefinementStatus::pass_limit:
            return "pass_limit";
        case RefinementStatus::node_limit:
            return "node_limit";
        case RefinementStatus::solve_failed:
            return "solve_failed";
    }
    return "unknown";
}

Eigen::MatrixXd lgl_integration_matrix(int n_points) {
    const LglRule rule = lgl_rule(n_points);  // throws for n_points < 2
    const int n = n_points;
    // f = V c in the Legendre basis (V_jm = P_m(tau_j)); integral from -1 to tau of P_0 is
    // tau + 1 and of P_m (m >= 1) is (P_{m+1}(tau) - P_{m-1}(tau)) / (2m + 1).
    Eigen::MatrixXd V(n, n), W(n, n);
    for (int j = 0; j < n; ++j) {
        const double tau = rule.points(j);
        for (int m = 0; m < n; ++m) {
            const LegendreValue pm = legendre(m, tau);
            V(j, m) = pm.p;
            W(j, m) = m == 0 ? tau + 1.0
                             : (legendre(m + 1, tau).p - pm.pm1) / static_cast<double>(2 * m + 1);
        }
    }
    // I = W V^-1, i.e. I^T = V^-T W^T
    return V.transpose().partialPivLu().solve(W.transpose()).transpose();
}

std::vector<double> control_jumps(const Solution& sol, double threshold) {
    if (sol.segments.empty()) throw InputError("control jumps: the solution has no segments");
    const double t0 = sol.initial_time;
    const double dt = sol.final_time - sol.initial_time;
    if (!(dt > 0.0)) throw InputError("control jumps: the solution has zero duration");
    // a candidate break: its fraction and the fraction spacing of the two nodes around it
    struct Candidate {
        double at;
        double spacing;
    };
    std::vector<Candidate> jumps;
    const int nu = sol.info.n_controls();
    for (int j = 0; j < nu; ++j) {
        double lo = sol.info.controls[j].lower;
        double hi = sol.info.controls[j].upper;
        if (!std::isfinite(lo) || !std::isfinite(hi)) {
            lo = kInf;
            hi = -kInf;
            for (const auto& s : sol.segments) {
                lo = std::min(lo, s.controls.col(j).minCoeff());
                hi = std::max(hi, s.controls.col(j).maxCoeff());
            }
        }
        const double range = hi - lo;
        if (!(range > 0.0)) continue;
        for (const auto& s : sol.segments) {
            const Eigen::Index n = s.time.size();
            Eigen::Index i = 0;
            while (i + 1 < n) {
                if (std::abs(s.controls(i + 1, j) - s.controls(i, j)) <= threshold * range) {
                    ++i;
                    continue;
                }
                // a run of large steps of one sign: one jump
                Eigen::Index e = i + 1;
                const double sign = s.controls(i + 1, j) - s.controls(i, j);
                while (e + 1 < n && (s.controls(e + 1, j) - s.controls(e, j)) * sign > 0.0 &&
                       std::abs(s.controls(e + 1, j) - s.controls(e, j)) > 0.05 * range) {
                    ++e;
                }
                const double mid = 0.5 * (s.controls(i, j) + s.controls(e, j));
                double tj = 0.5 * (s.time(i) + s.time(e));
                double h = s.time(e) - s.time(i);
                for (Eigen::Index q = i; q < e; ++q) {
                    const double a = s.controls(q, j) - mid;
                    const double b = s.controls(q + 1, j) - mid;
                    if (a * b <= 0.0 && a != b) {
                        tj = s.time(q) + a / (a - b) * (s.time(q + 1) - s.time(q));
                        h = s.time(q + 1) - s.time(q);
                        break;
                    }
                }
                jumps.push_back({(tj - t0) / dt, h / dt});
                i = e;
            }
        }
    }
    std::sort(jumps.begin(), jumps.end(),
              [](const Candidate& a, const Candidate& b) { return a.at < b.at; });
    // Merge jumps closer than about one node spacing (1.5 spacings of the nodes around them):
    // a chattering control (a singular arc, a control the mesh cannot follow) gives a run of
    // jumps one node apart; it becomes one break, or two at its ends when it spans more than
    // three spacings.
    std::vector<double> fr;
    for (std::size_t g = 0; g < jumps.size();) {
        std::size_t e = g;
        while (e + 1 < jumps.size() && jumps[e + 1].at - jumps[e].at <
                                           1.5 * std::max(jumps[e + 1].spacing, jumps[e].spacing)) {
            ++e;
        }
        const double span = jumps[e].at - jumps[g].at;
        if (e > g && span > 3.0 * std::max(jumps[g].spacing, jumps[e].spacing)) {
            fr.push_back(jumps[g].at);
            fr.push_back(jumps[e].at);
        } else {
            fr.push_back(0.5 * (jumps[g].at + jumps[e].at));
        }
        g = e + 1;
    }
    return fr;
}

std::vector<double> segment_errors(const Model& model, const Solution& sol, int extra_points) {
    if (sol.segments.empty()) throw InputError("segment errors: the solution has no segments");
    if (extra_points < 1) {
        throw InputError(
            fmt::format("segment errors: extra_points {}, expected >= 1", extra_points));
    }
    const ProblemInfo& info = model.info();
    const int nx = info.n_states();
    const int nu = info.n_controls();
    if (sol.segments.front().states.cols() != nx || sol.segments.front().controls.cols() != nu) {
        throw InputError(fmt::format(
            "segment errors: solution with {} states and {} controls, model '{}' has {} and {}",
            sol.segments.front().states.cols(), sol.segments.front().controls.cols(), info.name, nx,
            nu));
    }
    const std::vector<double> p(sol.parameters.data(),
                                sol.parameters.data() + sol.parameters.size());
    std::vector<double> errors(sol.segments.size(), 0.0);
    std::vector<double> x(static_cast<std::size_t>(nx)), u(static_cast<std::size_t>(nu)),
        f(static_cast<std::size_t>(nx));
    for (std::size_t k = 0; k < sol.segments.size(); ++k) {
        const SegmentSolution& seg = sol.segments[k];
        const double a = sol.breaks[k];
        const double b = sol.breaks[k + 1];
        if (!(b > a)) continue;
        const int m = static_cast<int>(seg.tau.size()) + extra_points;
        const LglRule rule = lgl_rule(m);
        const Eigen::MatrixXd I = lgl_integration_matrix(m);
        Eigen::MatrixXd X(m, nx), F(m, nx);
        for (int j = 0; j < m; ++j) {
            const double tau = rule.points(j);
            const Eigen::RowVectorXd ell = lagrange_basis(seg.tau, seg.bary, tau);
            for (int r = 0; r < nx; ++r) x[r] = X(j, r) = ell.dot(seg.states.col(r));
            for (int c = 0; c < nu; ++c) {
                // the control polynomial may overshoot between nodes: clamp it to its bounds
                u[c] = std::clamp(ell.dot(seg.controls.col(c)), info.controls[c].lower,
                                  info.controls[c].upper);
            }
            const double t = a + 0.5 * (b - a) * (tau + 1.0);
            model.dynamics(x, u, p, t, f);
            for (int r = 0; r < nx; ++r) F(j, r) = f[r];
        }
        // integrated state from the segment's first point
        const Eigen::MatrixXd Xi = X.row(0).replicate(m, 1) + 0.5 * (b - a) * (I * F);
        double e = 0.0;
        for (int r = 0; r < nx; ++r) {
            const double scale = 1.0 + X.col(r).cwiseAbs().maxCoeff();
            e = std::max(e, (Xi.col(r) - X.col(r)).cwiseAbs().maxCoeff() / scale);
        }
        errors[k] = std::isfinite(e) ? e : kInf;
    }
    return errors;
}

Mesh refine_mesh(const Solution& sol, const Mesh& mesh, const std::vector<double>& errors,
                 const RefinementOptions& opt, std::vector<int>* old_index) {
    opt.validate();
    mesh.validate();
    const int K = mesh.n_segments();
    if (static_cast<int>(sol.segments.size()) != K || static_cast<int>(errors.size()) != K ||
        sol.breaks.size() != static_cast<std::size_t>(K) + 1) {
        throw InputError(fmt::format(
            "mesh refinement: mesh of {} segments, solution of {} and {} segment errors", K,
            sol.segments.size(), errors.size()));
    }
    const double t0 = sol.initial_time;
    const double dt = sol.final_time - sol.initial_time;
    if (!(dt > 0.0)) throw InputError("mesh refinement: the solution has zero duration");
    // the breaks where the solver left them, as fractions
    std::vector<double> frac(static_cast<std::size_t>(K) + 1);
    for (int k = 0; k <= K; ++k) frac[k] = (sol.breaks[k] - t0) / dt;
    frac.front() = 0.0;
    frac.back() = 1.0;
    // which old breaks stay free (with free breaks): the phase breaks, else every interior one
    std::vector<bool> was_free(static_cast<std::size_t>(K) + 1, false);
    const bool free = mesh.free_breaks && K > 1;
    if (free) {
        if (mesh.phase_breaks.empty()) {
            for (int k = 1; k < K; ++k) was_free[k] = true;
        } else {
            for (const int k : mesh.phase_breaks) was_free[k] = true;
        }
    }
    const std::vector<double> jumps =
        opt.breaks_at_jumps ? control_jumps(sol, opt.jump_threshold) : std::vector<double>{};
    Mesh out;
    std::vector<int> index;     // old index per new break
    std::vector<bool> is_jump;  // new break at a jump (free)
    out.breaks.push_back(0.0);
    index.push_back(0);
    is_jump.push_back(false);
    for (int k = 0; k < K; ++k) {
        const int n = mesh.nodes[k];
        {
            // jumps inside the segment, more than one node spacing from its ends
            const double a = frac[k], b = frac[k + 1];
            const double h = (b - a) / static_cast<double>(n - 1);
            std::vector<double> cuts;
            for (const double f : jumps) {
                if (f > a + h && f < b - h && (cuts.empty() || f - cuts.back() > h))
                    cuts.push_back(f);
            }
            if (!cuts.empty()) {
                cuts.insert(cuts.begin(), a);
                cuts.push_back(b);
                for (std::size_t q = 0; q + 1 < cuts.size(); ++q) {
                    const double len = cuts[q + 1] - cuts[q];
                    const int need =
                        static_cast<int>(std::ceil(static_cast<double>(n) * len / (b - a) - 1e-9));
                    out.nodes.push_back(std::max({need, opt.min_nodes, 2}));
                    out.breaks.push_back(cuts[q + 1]);
                    const bool last = q + 2 == cuts.size();
                    index.push_back(last ? k + 1 : -1);
                    is_jump.push_back(!last);
                }
                continue;
            }
        }
        int pieces = 1;
        int nodes = n;
        const double e = errors[k];
        if (e > opt.tolerance) {
            // predicted degree increase: the error is taken to fall like N^-P
            const double ratio = std::isfinite(e) ? e / opt.tolerance : 1e300;
            const int P = std::max(
                1, static_cast<int>(
                       std::ceil(std::log(ratio) / std::log(static_cast<double>(std::max(n, 2))))));
            if (n + P <= opt.max_nodes) {
                nodes = n + P;
            } else {
                pieces = std::max((n + P + opt.min_nodes - 1) / opt.min_nodes, 2);
                nodes = opt.min_nodes;
            }
        }
        const double a = frac[k];
        const double b = frac[k + 1];
        for (int q = 0; q < pieces; ++q) {
            out.nodes.push_back(nodes);
            if (q + 1 < pieces) {
                out.breaks.push_back(a + (b - a) * static_cast<double>(q + 1) / pieces);
                index.push_back(-1);
                is_jump.push_back(false);
            }
        }
        out.breaks.push_back(b);
        index.push_back(k + 1);
        is_jump.push_back(false);
    }
    out.breaks.back() = 1.0;
    const int Kn = out.n_segments();
    for (int j = 1; j < Kn; ++j) {
        if (is_jump[j] || (free && index[j] > 0 && was_free[index[j]]))
            out.phase_breaks.push_back(j);
    }
    out.free_breaks = !out.phase_breaks.empty();
    double shortest = 1.0;
    for (int k = 0; k < Kn; ++k) shortest = std::min(shortest, out.breaks[k + 1] - out.breaks[k]);
    out.min_segment_fraction = std::min(mesh.min_segment_fraction, 0.5 * shortest);
    out.validate();
    if (old_index != nullptr) *old_index = std::move(index);
    return out;
}

std::string refinement_report(const AdaptiveSolution& res) {
    std::string r = fmt::format("{:>4} {:>8} {:>6} {:>10} {:>8} {:>6} {:>16} {:>14}  {}\n", "pass",
                                "segments", "points", "max error", "IPOPT it", "CPU s", "status",
                                "objective", "points per segment");
    for (const RefinementPass& p : res.passes) {
        std::string per;
        for (std::size_t k = 0; k < p.mesh.nodes.size(); ++k) {
            if (k > 0) per += ' ';
            if (k == 12 && p.mesh.nodes.size() > 16) {
                per += fmt::format("... ({} more)", p.mesh.nodes.size() - 12);
                break;
            }
            per += std::to_string(p.mesh.nodes[k]);
        }
        const bool converged = p.status == SolveStatus::solved ||
                               p.status == SolveStatus::solved_acceptable ||
                               p.status == SolveStatus::solved_unresolved;
        r += fmt::format("{:>4} {:>8} {:>6} {:>10} {:>8} {:>6.3f} {:>16} {:>14.10g}  {}\n", p.pass,
                         p.mesh.n_segments(), p.total_nodes,
                         converged ? fmt::format("{:.3e}", p.max_error) : std::string("-"),
                         p.iterations, p.cpu_s, to_string(p.status), p.objective, per);
    }
    r += to_string(res.status) + ": " + res.status_text + "\n";
    return r;
}

namespace {

/// A model whose interior events sit at other junctions of a refined mesh: info() carries the
/// new junction indices, and the wrapped problem is called with its own (first-mesh) index.
class RemappedModel final : public Model {
public:
    /// `user_junction[j]`: the first mesh's junction index of junction j of the present mesh
    /// (-1: none). `junction_of_event[e]`: the present junction of interior event e.
    RemappedModel(const Model& base, std::vector<int> user_junction,
                  const std::vector<int>& junction_of_event)
        : base_(base), info_(base.info()), user_(std::move(user_junction)) {
        for (std::size_t e = 0; e < info_.interior_events.size(); ++e)
            info_.interior_events[e].junction = junction_of_event[e];
    }
    [[nodiscard]] const ProblemInfo& info() const override { return info_; }
    [[nodiscard]] bool has_lagrange() const override { return base_.has_lagrange(); }
    [[nodiscard]] bool has_mayer() const override { return base_.has_mayer(); }
    void dynamics(std::span<const double> x, std::span<const double> u, std::span<const double> p,
                  double t, std::span<double> xdot) const override {
        base_.dynamics(x, u, p, t, xdot);
    }
    void path(std::span<const double> x, std::span<const double> u, std::span<const double> p,
              double t, std::span<double> g) const override {
        base_.path(x, u, p, t, g);
    }
    void node_values(std::span<const double> v, const NodePlacement& at,
                     std::span<double> out) const override {
        base_.node_values(v, at, out);
    }
    void node_jacobian(std::span<const double> v, const NodePlacement& at, std::span<double> out,
                       std::span<double> jac) const override {
        base_.node_jacobian(v, at, out, jac);
    }
    void node_hessian(std::span<const double> v, const NodePlacement& at,
                      std::span<const double> weights, std::span<double> hess) const override {
        base_.node_hessian(v, at, weights, hess);
    }
    void boundary_values(std::span<const double> v, std::span<double> out) const override {
        base_.boundary_values(v, out);
    }
    void boundary_jacobian(std::span<const double> v, std::span<double> out,
                           std::span<double> jac) const override {
        base_.boundary_jacobian(v, out, jac);
    }
    void boundary_hessian(std::span<const double> v, std::span<const double> weights,
                          std::span<double> hess) const override {
        base_.boundary_hessian(v, weights, hess);
    }
    void interior_values(int junction, std::span<const double> v,
                         std::span<double> out) const override {
        base_.interior_values(user(junction), v, out);
    }
    void interior_jacobian(int junction, std::span<const double> v, std::span<double> out,
                           std::span<double> jac) const override {
        base_.interior_jacobian(user(junction), v, out, jac);
    }
    void interior_hessian(int junction, std::span<const double> v, std::span<const double> weights,
                          std::span<double> hess) const override {
        base_.interior_hessian(user(junction), v, weights, hess);
    }

private:
    [[nodiscard]] int user(int junction) const {
        return junction >= 0 && junction < static_cast<int>(user_.size()) && user_[junction] >= 0
                   ? user_[junction]
                   : junction;
    }
    const Model& base_;
    ProblemInfo info_;
    std::vector<int> user_;
};

int total_nodes(const Mesh& mesh) {
    int n = 0;
    for (const int k : mesh.nodes) n += k;
    return n;
}

}  // namespace

AdaptiveSolution solve_adaptive(const Model& model, const Mesh& mesh, const Guess& guess,
                                const SolverOptions& solver_options,
                                const RefinementOptions& ropt) {
    ropt.validate();
    mesh.validate();
    const ProblemInfo& info = model.info();
    const int ne = info.n_interior_events();
    // user_junction[j]: the first mesh's index of break j of the present mesh (-1: new break)
    std::vector<int> user_junction(mesh.breaks.size());
    for (std::size_t j = 0; j < user_junction.size(); ++j) user_junction[j] = static_cast<int>(j);
    std::vector<int> event_junction(static_cast<std::size_t>(ne));
    for (int e = 0; e < ne; ++e) event_junction[e] = info.interior_events[e].junction;

    AdaptiveSolution res;
    Mesh current = mesh;
    Guess start = guess;
    // the last converged pass, to refine again from when a solve on its refinement fails
    bool have_converged = false;
    bool retried = false;
    RefinementOptions active = ropt;  // min_nodes raised to max_nodes after a failed solve
    Solution last;
    Mesh last_mesh;
    std::vector<double> last_errors;
    std::vector<int> last_user, last_event;

    // the next mesh from the last converged pass, with the junctions mapped onto it
    auto advance = [&](const RefinementOptions& o) {
        std::vector<int> old_index;
        Mesh next = refine_mesh(last, last_mesh, last_errors, o, &old_index);
        std::vector<int> new_user(next.breaks.size(), -1);
        std::vector<int> new_of_old(last_mesh.breaks.size(), -1);
        for (std::size_t j = 0; j < old_index.size(); ++j) {
            if (old_index[j] >= 0) {
                new_user[j] = last_user[old_index[j]];
                new_of_old[old_index[j]] = static_cast<int>(j);
            }
        }
        event_junction = last_event;
        for (int e = 0; e < ne; ++e) event_junction[e] = new_of_old[event_junction[e]];
        user_junction = std::move(new_user);
        return next;
    };

    for (int pass = 1;; ++pass) {
        const RemappedModel m(model, user_junction, event_junction);
        Solution sol = solve(m, current, start, solver_options);
        RefinementPass rec;
        rec.pass = pass;
        rec.mesh = current;
        rec.iterations = sol.iterations;
        rec.cpu_s = sol.cpu_time;
        rec.status = sol.status;
        rec.objective = sol.objective;
        rec.final_time = sol.final_time;
        rec.total_nodes = total_nodes(current);
        if (!sol.converged()) {
            const std::string why = fmt::format("refinement pass {} did not converge ({}: {})",
                                                pass, to_string(rec.status), sol.status_text);
            res.passes.push_back(std::move(rec));
            if (have_converged && !retried && pass < ropt.max_passes) {
                // once: split into fewer, higher-degree pieces (min_nodes = max_nodes), and so
                // for the rest of the run
                active.min_nodes = ropt.max_nodes;
                Mesh next = advance(active);
                if (next.nodes != current.nodes && total_nodes(next) <= ropt.max_total_nodes) {
                    retried = true;
                    current = std::move(next);
                    continue;  // start is still the last converged solution
                }
            }
            res.status = RefinementStatus::solve_failed;
            res.status_text = why + (have_converged ? "; returned the last converged solution"
                                                    : "; returned its best iterate");
            if (!have_converged) {
                res.solution = std::move(sol);
                res.mesh = current;
                res.interior_junctions = event_junction;
            }
            return res;
        }
        rec.segment_errors = segment_errors(m, sol, ropt.extra_points);
        rec.max_error = *std::max_element(rec.segment_errors.begin(), rec.segment_errors.end());
        res.passes.push_back(rec);
        res.solution = sol;
        res.mesh = current;
        res.interior_junctions = event_junction;
        have_converged = true;
        retried = false;
        last = sol;
        last_mesh = current;
        last_errors = rec.segment_errors;
        last_user = user_junction;
        last_event = event_junction;
        Mesh next = advance(active);
        if (rec.max_error <= ropt.tolerance && next.nodes == current.nodes) {
            res.status = RefinementStatus::tolerance_met;
            res.status_text = fmt::format(
                "error estimate {:.3e} at or below the tolerance {:.3e} after {} pass(es), {} "
                "segments, {} LGL points",
                rec.max_error, ropt.tolerance, pass, current.n_segments(), rec.total_nodes);
            return res;
        }
        if (pass >= ropt.max_passes) {
            res.status = RefinementStatus::pass_limit;
            res.status_text = fmt::format(
                "error estimate {:.3e} (tolerance {:.3e}){} after the pass limit of {} solves "
                "({} LGL points); raise max_passes",
                rec.max_error, ropt.tolerance,
                rec.max_error <= ropt.tolerance ? ", control jumps inside segments" : "",
                ropt.max_passes, rec.total_nodes);
            return res;
        }
        if (total_nodes(next) > ropt.max_total_nodes) {
            res.status = RefinementStatus::node_limit;
            res.status_text = fmt::format(
                "error estimate {:.3e} (tolerance {:.3e}); the next mesh would have {} "
                "LGL points, above max_total_nodes {}",
                rec.max_error, ropt.tolerance, total_nodes(next), ropt.max_total_nodes);
            return res;
        }
        current = std::move(next);
        start = Guess::from_solution(sol);
    }
}

}  // namespace manta::optimal
