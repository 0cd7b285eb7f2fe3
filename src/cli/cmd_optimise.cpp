/// @file cmd_optimise.cpp
/// `manta optimise`: optimal control by Legendre–Gauss–Lobatto collocation and IPOPT
/// (docs/optimal-control.md). Now: the solver's validation problems; the mesh, solver and
/// output options are problem-agnostic so that aircraft manoeuvres (--aircraft, --manoeuvre)
/// can share them.

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "commands.hpp"
#include "manta/core/error.hpp"
#include "manta/optimal/problems.hpp"
#include "manta/optimal/solve.hpp"

namespace manta::cli {

namespace {

namespace fs = std::filesystem;

struct OptimiseOptions {
    std::string problem;
    int nodes = 40;
    int segments = 1;
    bool free_breaks = false;
    bool refine = false;
    std::string hessian = "exact";
    double tolerance = 1e-8;
    int max_iterations = 3000;
    std::string atmosphere = "us1976";
    std::string out;
    bool json = false;
    bool progress = false;
    int ipopt_print_level = 0;
};

/// A validation problem, its guess and its known optimum (if any).
struct Case {
    std::unique_ptr<optimal::Model> model;
    optimal::Guess guess;
    nlohmann::json reference;  ///< published or analytic values
    double reference_final_time = NAN;
};

Case make_case(const OptimiseOptions& o) {
    Case c;
    if (o.problem == "brachistochrone") {
        const optimal::Brachistochrone p;
        const auto cyc = optimal::brachistochrone_cycloid(p.x_final, p.y_final, p.gravity);
        c.model = optimal::make_model(p);
        c.guess = p.guess();
        c.reference_final_time = cyc.final_time;
        c.reference = {{"source", "cycloid through the end point (analytic)"},
                       {"final_time", cyc.final_time},
                       {"end_point", {p.x_final, p.y_final}},
                       {"gravity", p.gravity}};
    } else if (o.problem == "double-integrator") {
        const optimal::DoubleIntegrator p;
        const auto bb = optimal::double_integrator_bang_bang(p.x0, p.v0);
        c.model = optimal::make_model(p);
        c.guess = p.guess();
        c.reference_final_time = bb.final_time;
        c.reference = {{"source", "bang-bang (analytic)"},
                       {"final_time", bb.final_time},
                       {"switch_time", bb.switch_time}};
    } else {
        optimal::MinTimeToClimb p;
        if (o.atmosphere == "troposphere-only") {
            p.atmosphere = optimal::MinTimeToClimb::Atmosphere::troposphere_only;
        }
        c.model = optimal::make_model(p);
        c.guess = p.guess();
        c.reference_final_time = 321.11;
        c.reference = {{"source", "PSOPT documented optimum (Bryson, Desai & Hoffman 1969 data)"},
                       {"final_time", 321.11},
                       {"atmosphere", o.atmosphere}};
    }
    return c;
}

nlohmann::json summary(const OptimiseOptions& o, const optimal::Solution& s, const Case& c,
                       const optimal::Mesh& mesh) {
    nlohmann::json resim_abs = nlohmann::json::object();
    for (int r = 0; r < s.info.n_states(); ++r) {
        resim_abs[s.info.states[r].name] =
            s.resimulation.max_abs_error.size() > r ? s.resimulation.max_abs_error(r) : 0.0;
    }
    nlohmann::json j = {
        {"problem", o.problem},
        {"status", optimal::to_string(s.status)},
        {"converged", s.converged()},
        {"ipopt_status", s.status_text},
        {"final_time", s.final_time},
        {"objective", s.objective},
        {"iterations", s.iterations},
        {"cpu_time", s.cpu_time},
        {"wall_time", s.wall_time},
        {"max_constraint_violation", s.max_violation},
        {"resimulation_error", s.resimulation.max_scaled_error},
        {"resimulation_max_abs_error", resim_abs},
        {"nodes", o.nodes},
        {"segments", mesh.n_segments()},
        {"breaks", s.breaks},
        {"hessian", o.hessian},
        {"n_variables", s.n_variables},
        {"n_constraints", s.n_constraints},
        {"reference", c.reference},
    };
    if (std::isfinite(c.reference_final_time)) {
        j["final_time_error"] = s.final_time - c.reference_final_time;
    }
    if (!s.resimulation.done) j["resimulation_message"] = s.resimulation.message;
    return j;
}

}  // namespace

void add_optimise(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand(
        "optimise", "Optimal control by Legendre-Gauss-Lobatto collocation and IPOPT");
    auto o = std::make_shared<OptimiseOptions>();
    cmd->add_option("--problem", o->problem,
                    "Validation problem: brachistochrone, min-time-to-climb, double-integrator")
        ->required()
        ->check(CLI::IsMember({"brachistochrone", "min-time-to-climb", "double-integrator"}));
    cmd->add_option("--nodes", o->nodes, "LGL points per segment (default 40)")
        ->check(CLI::Range(2, 400));
    cmd->add_option("--segments", o->segments, "Number of equal segments, hp (default 1)")
        ->check(CLI::Range(1, 200));
    cmd->add_flag("--free-breaks", o->free_breaks, "Segment breaks are decision variables");
    cmd->add_flag("--refine", o->refine,
                  "After solving, break the mesh where a control jumps and re-solve (hp)");
    cmd->add_option("--hessian", o->hessian, "exact (default) or limited-memory")
        ->check(CLI::IsMember({"exact", "limited-memory"}));
    cmd->add_option("--tol", o->tolerance, "IPOPT tolerance (default 1e-8)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--max-iter", o->max_iterations, "IPOPT iteration limit (default 3000)")
        ->check(CLI::Range(1, 1000000));
    cmd->add_option("--atmosphere", o->atmosphere,
                    "min-time-to-climb atmosphere: us1976 (default) or troposphere-only")
        ->check(CLI::IsMember({"us1976", "troposphere-only"}));
    cmd->add_option("--out", o->out, "Write solution.csv and summary.json into this folder");
    cmd->add_flag("--json", o->json, "Print one JSON object (SI units unless the name says)");
    cmd->add_flag("--progress", o->progress, "Print a progress line per IPOPT iteration (stderr)");
    cmd->add_option("--ipopt-print-level", o->ipopt_print_level,
                    "IPOPT's own console output, 0 (default) to 12")
        ->check(CLI::Range(0, 12));
    cmd->callback([o, &action] {
        action = [o]() -> int {
            Case c = make_case(*o);
            optimal::Mesh mesh = optimal::Mesh::uniform(o->segments, o->nodes);
            mesh.free_breaks = o->free_breaks;
            optimal::SolverOptions so;
            so.hessian = o->hessian == "exact" ? optimal::HessianMode::exact
                                               : optimal::HessianMode::limited_memory;
            so.tolerance = o->tolerance;
            so.max_iterations = o->max_iterations;
            so.print_level = o->ipopt_print_level;
            if (o->progress) {
                so.progress = [](const optimal::IterationInfo& it) {
                    std::fprintf(stderr,
                                 "iter %4d%s  objective %.10g  inf_pr %.2e  inf_du %.2e  mu %.1e  "
                                 "step %.2e\n",
                                 it.iteration, it.restoration ? "r" : " ", it.objective,
                                 it.infeasibility, it.dual_infeasibility, it.mu, it.step);
                    return true;
                };
            }
            const fs::path out = o->out;
            if (!out.empty()) so.failure_csv = out / "best_iterate.csv";
            optimal::Solution s = optimal::solve(*c.model, mesh, c.guess, so);
            if (o->refine && s.converged()) {
                const optimal::Mesh refined = optimal::refine_at_control_jumps(s, o->nodes);
                if (refined.n_segments() > mesh.n_segments() || !mesh.free_breaks) {
                    const double cpu = s.cpu_time;
                    const double wall = s.wall_time;
                    const int its = s.iterations;
                    mesh = refined;
                    s = optimal::solve(*c.model, mesh, optimal::Guess::from_solution(s), so);
                    s.cpu_time += cpu;
                    s.wall_time += wall;
                    s.iterations += its;
                }
            }
            const nlohmann::json j = summary(*o, s, c, mesh);
            if (!out.empty()) {
                fs::create_directories(out);
                if (s.converged()) optimal::write_csv(s, out / "solution.csv");
                std::ofstream f(out / "summary.json");
                if (!f) throw IoError("cannot write '" + (out / "summary.json").string() + "'");
                f << j.dump(2) << '\n';
            }
            if (o->json) {
                print_json(j);
            } else {
                fmt::print("{}: {} in {} IPOPT iterations, {:.3f} s CPU\n", o->problem,
                           s.status_text, s.iterations, s.cpu_time);
                fmt::print("  final time               {:.10g} s\n", s.final_time);
                if (std::isfinite(c.reference_final_time)) {
                    fmt::print("  reference                {:.10g} s (error {:.3e})\n",
                               c.reference_final_time, s.final_time - c.reference_final_time);
                }
                fmt::print("  max constraint violation {:.3e}\n", s.max_violation);
                fmt::print("  re-simulation error      {:.3e} (scaled)\n",
                           s.resimulation.max_scaled_error);
                fmt::print("  mesh                     {} segment(s) x {} LGL points\n",
                           mesh.n_segments(), o->nodes);
                if (!out.empty()) fmt::print("  written to               {}\n", out.string());
            }
            if (!s.converged()) {
                std::fputs(optimal::failure_report(s, so.failure_csv).c_str(), stderr);
                return 1;
            }
            return 0;
        };
    });
}

}  // namespace manta::cli
