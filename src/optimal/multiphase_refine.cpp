/// @file multiphase_refine.cpp
/// Error-driven mesh refinement of a multi-phase problem, phase by phase (multiphase.hpp).

#include <fmt/format.h>

#include <algorithm>
#include <numeric>
#include <string>
#include <utility>

#include "manta/core/error.hpp"
#include "manta/optimal/multiphase.hpp"

namespace manta::optimal {

namespace {

int total_nodes(const std::vector<Mesh>& meshes) {
    int n = 0;
    for (const auto& m : meshes) n += std::accumulate(m.nodes.begin(), m.nodes.end(), 0);
    return n;
}

}  // namespace

MultiPhaseAdaptiveSolution solve_adaptive(const MultiPhaseProblem& problem,
                                          const SolverOptions& solver_options,
                                          const RefinementOptions& ropt) {
    ropt.validate();
    problem.validate();
    for (int k = 0; k < problem.n_phases(); ++k) {
        if (problem.phases[static_cast<std::size_t>(k)].model->info().n_interior_events() > 0) {
            throw InputError(fmt::format(
                "multi-phase solve_adaptive: phase {} has interior events, expected none (make "
                "each interior event a phase boundary, or refine that problem alone)",
                k));
        }
    }
    MultiPhaseAdaptiveSolution res;
    MultiPhaseProblem current = problem;
    for (int pass = 1;; ++pass) {
        MultiPhaseSolution sol = solve(current, solver_options);
        MultiPhasePass rec;
        rec.pass = pass;
        for (const auto& ph : current.phases) rec.meshes.push_back(ph.mesh);
        rec.iterations = sol.iterations;
        rec.cpu_s = sol.cpu_time;
        rec.status = sol.status;
        rec.objective = sol.objective;
        rec.total_nodes = total_nodes(rec.meshes);
        if (!sol.converged()) {
            res.status = RefinementStatus::solve_failed;
            res.status_text =
                fmt::format("refinement pass {} did not converge ({}: {}){}", pass,
                            to_string(sol.status), sol.status_text,
                            res.passes.empty() ? "; returned its best iterate"
                                               : "; returned the last converged solution");
            res.passes.push_back(std::move(rec));
            if (res.passes.size() == 1) {
                res.solution = std::move(sol);
                res.meshes = res.passes.back().meshes;
            }
            return res;
        }
        std::vector<Mesh> next;
        bool unchanged = true;
        for (std::size_t k = 0; k < current.phases.size(); ++k) {
            const Model& model = *current.phases[k].model;
            rec.segment_errors.push_back(segment_errors(model, sol.phases[k], ropt.extra_points));
            const auto& e = rec.segment_errors.back();
            rec.max_error = std::max(rec.max_error, *std::max_element(e.begin(), e.end()));
            next.push_back(refine_mesh(sol.phases[k], current.phases[k].mesh, e, ropt));
            unchanged = unchanged && next.back().nodes == current.phases[k].mesh.nodes;
        }
        res.passes.push_back(rec);
        res.solution = sol;
        res.meshes = rec.meshes;
        if (rec.max_error <= ropt.tolerance && unchanged) {
            res.status = RefinementStatus::tolerance_met;
            res.status_text = fmt::format(
                "error estimate {:.3e} at or below the tolerance {:.3e} after {} "
                "pass(es), {} LGL points in {} phases",
                rec.max_error, ropt.tolerance, pass, rec.total_nodes, current.phases.size());
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
                "error estimate {:.3e} (tolerance {:.3e}); the next meshes would have {} LGL "
                "points, above max_total_nodes {}",
                rec.max_error, ropt.tolerance, total_nodes(next), ropt.max_total_nodes);
            return res;
        }
        for (std::size_t k = 0; k < current.phases.size(); ++k) {
            current.phases[k].mesh = std::move(next[k]);
            current.phases[k].guess = Guess::from_solution(sol.phases[k]);
        }
    }
}

std::string refinement_report(const MultiPhaseAdaptiveSolution& r) {
    std::string s = "pass | points per phase | max error | IPOPT it | CPU s | status | objective\n";
    for (const auto& p : r.passes) {
        std::string pts;
        for (const auto& m : p.meshes) {
            if (!pts.empty()) pts += " / ";
            for (std::size_t i = 0; i < m.nodes.size(); ++i) {
                if (i > 0) pts += ' ';
                pts += std::to_string(m.nodes[i]);
            }
        }
        s += fmt::format("{} | {} | {:.2e} | {} | {:.3f} | {} | {:.10g}\n", p.pass, pts,
                         p.max_error, p.iterations, p.cpu_s, to_string(p.status), p.objective);
    }
    s += to_string(r.status) + ": " + r.status_text + "\n";
    return s;
}

}  // namespace manta::optimal
