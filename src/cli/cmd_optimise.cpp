/// @file cmd_optimise.cpp
/// `manta optimise`: optimal control by Legendre–Gauss–Lobatto collocation and IPOPT
/// (docs/optimal-control.md): the solver's validation problems (--problem), and aircraft
/// manoeuvres (--aircraft, --manoeuvre; docs/manoeuvres.md) with trajectory CSV, summary JSON
/// and time-history plots; with --adaptive, error-driven ph mesh refinement
/// (optimal::solve_adaptive) from the problem's or the manoeuvre's mesh.

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "checks.hpp"
#include "commands.hpp"
#include "manta/aircraft/aircraft.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/manoeuvres/manoeuvre.hpp"
#include "manta/manoeuvres/problem.hpp"
#include "manta/optimal/problems.hpp"
#include "manta/optimal/refine.hpp"
#include "manta/optimal/solve.hpp"
#include "svg_plot.hpp"

namespace manta::cli {

namespace {

namespace fs = std::filesystem;

struct OptimiseOptions {
    std::string problem;
    std::string aircraft;   ///< aircraft file (manoeuvre form)
    std::string manoeuvre;  ///< manoeuvre file (manoeuvre form)
    std::string tables;     ///< aero database replacing the aircraft's (manoeuvre form)
    bool nodes_given = false;
    bool hessian_given = false;
    bool tolerance_given = false;
    int nodes = 40;
    int segments = 1;
    bool free_breaks = false;
    bool refine = false;
    bool adaptive = false;             ///< error-driven ph refinement (solve_adaptive)
    double adaptive_tolerance = 1e-6;  ///< its relative error target per segment
    int max_passes = 10;               ///< its most solves, the first included
    int min_nodes = 4;                 ///< its points per segment created by a split
    int max_nodes = 12;                ///< its most points per segment by degree increase
    std::string hessian = "exact";
    double tolerance = 1e-8;
    int max_iterations = 3000;
    std::string atmosphere = "us1976";
    std::string out;
    bool json = false;
    bool progress = false;
    int ipopt_print_level = 0;
    std::vector<std::string> ipopt;  ///< KEY=VALUE IPOPT options
};

/// IPOPT options given as KEY=VALUE.
std::vector<std::pair<std::string, std::string>> ipopt_pairs(const std::vector<std::string>& kv) {
    std::vector<std::pair<std::string, std::string>> r;
    for (const auto& s : kv) {
        const auto eq = s.find('=');
        if (eq == std::string::npos || eq == 0) {
            throw InputError("--ipopt '" + s + "': expected KEY=VALUE (an IPOPT option)");
        }
        r.emplace_back(s.substr(0, eq), s.substr(eq + 1));
    }
    return r;
}

/// Options of the error-driven refinement from the command line (the library's defaults else).
optimal::RefinementOptions refinement_options(const OptimiseOptions& o) {
    optimal::RefinementOptions ro;
    ro.tolerance = o.adaptive_tolerance;
    ro.max_passes = o.max_passes;
    ro.min_nodes = o.min_nodes;
    ro.max_nodes = o.max_nodes;
    return ro;
}

/// The refinement passes for --json and summary.json, and the report as printed.
nlohmann::json refinement_fields(const optimal::AdaptiveSolution& a,
                                 const optimal::RefinementOptions& ro) {
    nlohmann::json passes = nlohmann::json::array();
    for (const optimal::RefinementPass& p : a.passes) {
        passes.push_back({{"pass", p.pass},
                          {"segments", p.mesh.n_segments()},
                          {"total_nodes", p.total_nodes},
                          {"nodes_per_segment", p.mesh.nodes},
                          {"max_error", p.max_error},
                          {"segment_errors", p.segment_errors},
                          {"iterations", p.iterations},
                          {"cpu_time", p.cpu_s},
                          {"status", optimal::to_string(p.status)},
                          {"objective", p.objective},
                          {"final_time", p.final_time}});
    }
    return {{"status", optimal::to_string(a.status)},
            {"status_text", a.status_text},
            {"tolerance", ro.tolerance},
            {"max_passes", ro.max_passes},
            {"min_nodes", ro.min_nodes},
            {"max_nodes", ro.max_nodes},
            {"passes", passes},
            {"report", optimal::refinement_report(a)}};
}

/// LGL points of a mesh (segments' points summed).
int total_nodes(const optimal::Mesh& mesh) {
    int n = 0;
    for (const int k : mesh.nodes) n += k;
    return n;
}

/// The solution of the last pass with the IPOPT iterations and times of every pass (and of the
/// `previous` solve, when the refinement started from one) added up.
optimal::Solution adaptive_totals(const optimal::AdaptiveSolution& a,
                                  const optimal::Solution* previous = nullptr) {
    optimal::Solution s = a.solution;
    s.iterations = previous ? previous->iterations : 0;
    s.cpu_time = previous ? previous->cpu_time : 0.0;
    for (const optimal::RefinementPass& p : a.passes) {
        s.iterations += p.iterations;
        s.cpu_time += p.cpu_s;
    }
    return s;
}

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

/// The fields every optimise summary has: IPOPT's outcome, times, violations, re-simulation.
nlohmann::json solution_fields(const optimal::Solution& s, const optimal::Mesh& mesh,
                               const std::string& hessian) {
    nlohmann::json resim_abs = nlohmann::json::object();
    for (int r = 0; r < s.info.n_states(); ++r) {
        resim_abs[s.info.states[r].name] =
            s.resimulation.max_abs_error.size() > r ? s.resimulation.max_abs_error(r) : 0.0;
    }
    nlohmann::json j = {
        {"status", optimal::to_string(s.status)},
        {"converged", s.converged()},
        {"resolved", s.resolved()},
        {"ipopt_status", s.status_text},
        {"final_time", s.final_time},
        {"objective", s.objective},
        {"iterations", s.iterations},
        {"cpu_time", s.cpu_time},
        {"wall_time", s.wall_time},
        {"max_constraint_violation", s.max_violation},
        {"resimulation_error", s.resimulation.max_scaled_error},
        {"resimulation_max_abs_error", resim_abs},
        {"segments", mesh.n_segments()},
        {"breaks", s.breaks},
        {"hessian", hessian},
        {"n_variables", s.n_variables},
        {"n_constraints", s.n_constraints},
    };
    nlohmann::json worst = nlohmann::json::array();
    for (const auto& v : s.violations) {
        worst.push_back({{"name", v.name},
                         {"kind", v.kind},
                         {"segment", v.segment},
                         {"node", v.node},
                         {"time", v.time},
                         {"value", v.value},
                         {"violation", v.amount},
                         {"scaled", v.scaled}});
    }
    j["violations"] = worst;
    if (!s.resimulation.done) j["resimulation_message"] = s.resimulation.message;
    return j;
}

nlohmann::json summary(const OptimiseOptions& o, const optimal::Solution& s, const Case& c,
                       const optimal::Mesh& mesh) {
    nlohmann::json j = solution_fields(s, mesh, o.hessian);
    j["problem"] = o.problem;
    j["nodes"] = o.nodes;
    j["reference"] = c.reference;
    if (std::isfinite(c.reference_final_time)) {
        j["final_time_error"] = s.final_time - c.reference_final_time;
    }
    return j;
}

/// The progress callback: every iteration with --progress, else one line per block of 10.
std::function<bool(const optimal::IterationInfo&)> progress_printer(bool every) {
    return [every](const optimal::IterationInfo& it) {
        if (every || it.iteration % 10 == 0) {
            std::fprintf(stderr,
                         "iter %4d%s  objective %.10g  inf_pr %.2e  inf_du %.2e  mu %.1e  "
                         "step %.2e\n",
                         it.iteration, it.restoration ? "r" : " ", it.objective, it.infeasibility,
                         it.dual_infeasibility, it.mu, it.step);
        }
        return true;
    };
}

/// Time histories like the paper's Figs. 10-12 (states, then controls and load factor; angles
/// in degrees) and the 3-D flight path like its Fig. 9.
void write_plots(const manoeuvres::Trajectory& t, const std::string& name, const fs::path& out) {
    const std::vector<double> time = t.column("t");
    constexpr double deg = 180.0 / 3.14159265358979323846;
    auto panels = [&](const std::vector<std::tuple<std::string, std::string, double>>& cols) {
        std::vector<Panel> p;
        for (const auto& [col, label, factor] : cols) {
            std::vector<double> y = t.column(col);
            for (double& v : y) v *= factor;
            p.push_back({label, std::move(y)});
        }
        return p;
    };
    const std::string states = svg_time_histories(name + ": states", "time [s]", time,
                                                  panels({{"alpha", "alpha [deg]", deg},
                                                          {"beta", "beta [deg]", deg},
                                                          {"V", "V [m/s]", 1.0},
                                                          {"theta", "pitch angle [deg]", deg},
                                                          {"phi", "roll angle [deg]", deg},
                                                          {"psi", "yaw angle [deg]", deg},
                                                          {"altitude", "altitude [m]", 1.0},
                                                          {"nz", "load factor nz [-]", 1.0}}),
                                                  2);
    const std::string controls =
        svg_time_histories(name + ": controls", "time [s]", time,
                           panels({{"elevator", "elevator [deg]", deg},
                                   {"aileron", "aileron [deg]", deg},
                                   {"rudder", "rudder [deg]", deg},
                                   {"throttle", "throttle [-]", 1.0},
                                   {"p", "p [deg/s]", deg},
                                   {"q", "q [deg/s]", deg},
                                   {"r", "r [deg/s]", deg},
                                   {"roll_angle", "integral of p [deg]", deg}}),
                           2);
    FlightPath3d fp;
    fp.north = t.column("x");
    fp.east = t.column("y");
    fp.altitude = t.column("altitude");
    fp.phi = t.column("phi");
    fp.theta = t.column("theta");
    fp.psi = t.column("psi");
    fp.time = time;
    const std::string path = svg_flight_path_3d(name + ": flight path", fp);
    for (const auto& [file, text] :
         {std::pair{out / "states.svg", states}, std::pair{out / "controls.svg", controls},
          std::pair{out / "flight_path.svg", path}}) {
        core::write_file_atomic(file, text);
    }
}

int run_manoeuvre(const OptimiseOptions& o) {
    const auto aircraft = aircraft::load_aircraft(o.aircraft);
    manoeuvres::ManoeuvreSpec spec = manoeuvres::load_manoeuvre(o.manoeuvre);
    std::shared_ptr<const aero::AeroDatabase> tables;
    if (!o.tables.empty()) {
        tables = std::make_shared<const aero::AeroDatabase>(aero::AeroDatabase::read(o.tables));
    }
    if (o.nodes_given) spec.nodes = o.nodes;
    if (o.segments > 1) spec.segments = o.segments;
    const manoeuvres::ManoeuvreProblem problem(manoeuvres::manoeuvre_model(aircraft, spec, tables),
                                               spec);
    optimal::SolverOptions so;
    const std::string hessian = o.hessian_given ? o.hessian : spec.hessian;
    so.hessian =
        hessian == "exact" ? optimal::HessianMode::exact : optimal::HessianMode::limited_memory;
    so.tolerance = o.tolerance_given ? o.tolerance : spec.tolerance;
    so.max_iterations = std::min(o.max_iterations, spec.max_iterations);
    so.print_level = o.ipopt_print_level;
    so.ipopt_options = ipopt_pairs(o.ipopt);
    so.progress = progress_printer(o.progress);
    const fs::path out = o.out;
    std::optional<core::RunFolderLock> lock;
    if (!out.empty()) {
        lock.emplace(out, "optimise");
        so.failure_csv = out / "best_iterate.csv";
    }
    const auto wall_start = std::chrono::steady_clock::now();
    manoeuvres::ManoeuvreResult r = manoeuvres::fly(problem, so);
    // --adaptive: error-driven refinement from the manoeuvre's mesh, started from its solution
    std::optional<optimal::AdaptiveSolution> adaptive;
    const optimal::RefinementOptions ro = refinement_options(o);
    if (o.adaptive && r.solution.converged()) {
        const auto model = manoeuvres::make_model(problem);
        adaptive = optimal::solve_adaptive(*model, r.mesh,
                                           optimal::Guess::from_solution(r.solution), so, ro);
        const optimal::Solution first = r.solution;
        r.solution = adaptive_totals(*adaptive, &first);
        r.solution.wall_time =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
        r.mesh = adaptive->mesh;
    }
    const optimal::Solution& s = r.solution;
    // the phases: the refined mesh keeps the intermediate condition at its own junction, not at
    // the middle segment (ManoeuvreProblem::phase_of_segment)
    const int K = r.mesh.n_segments();
    auto phase_of_segment = [&](int k) {
        if (adaptive && !adaptive->interior_junctions.empty()) {
            return k < adaptive->interior_junctions.front() ? 0 : 1;
        }
        return problem.phase_of_segment(k, K);
    };
    // the same for the `phase` column of a trajectory: a row at the junction time belongs to
    // the first phase in the node trajectory (the junction closes its segment there) and to the
    // second in the dense one
    auto set_phases = [&](manoeuvres::Trajectory& t, bool junction_in_second) {
        if (!adaptive || adaptive->interior_junctions.empty()) return;
        const double tj = s.breaks[static_cast<std::size_t>(adaptive->interior_junctions.front())];
        const auto col = static_cast<std::size_t>(
            std::find(t.columns.begin(), t.columns.end(), "phase") - t.columns.begin());
        const auto tcol = static_cast<std::size_t>(
            std::find(t.columns.begin(), t.columns.end(), "t") - t.columns.begin());
        if (col >= t.columns.size() || tcol >= t.columns.size()) return;
        for (auto& row : t.rows) {
            const bool second = junction_in_second ? row[tcol] >= tj : row[tcol] > tj;
            row[col] = second ? 1.0 : 0.0;
        }
    };
    manoeuvres::Trajectory traj = manoeuvres::trajectory(problem, s);
    traj.metadata.insert(traj.metadata.begin() + 1, {"aircraft", o.aircraft});
    set_phases(traj, false);
    const manoeuvres::ConstraintCheck c = manoeuvres::check(problem, traj);
    nlohmann::json j = solution_fields(s, r.mesh, hessian);
    j["manoeuvre"] = spec.name;
    j["aircraft"] = aircraft.name;
    j["aero_tables"] = o.tables.empty() ? std::string("aircraft file") : o.tables;
    j["mass_kg"] = problem.model().mass.mass;
    j["nodes"] = s.n_nodes();
    if (adaptive) {
        j["nodes_per_segment"] = r.mesh.nodes;
        j["refinement"] = refinement_fields(*adaptive, ro);
    } else {
        j["nodes_per_segment"] = spec.nodes;
    }
    j["mass_case"] = traj.meta("mass_case");
    j["coarse_iterations"] = r.coarse_iterations;
    {
        // phases: names and time spans (the intermediate condition ends the first)
        const auto names = problem.phase_names();
        nlohmann::json ph = nlohmann::json::array();
        for (std::size_t q = 0; q < names.size(); ++q) {
            double t0 = s.final_time, t1 = s.initial_time;
            for (int k = 0; k < K; ++k) {
                if (phase_of_segment(k) != static_cast<int>(q)) continue;
                t0 = std::min(t0, s.breaks[static_cast<std::size_t>(k)]);
                t1 = std::max(t1, s.breaks[static_cast<std::size_t>(k + 1)]);
            }
            ph.push_back({{"name", names[q]}, {"t_start", t0}, {"t_end", t1}});
        }
        j["phases"] = ph;
    }
    j["checks"] = {{"alpha_max_deg", c.alpha_max_deg},
                   {"load_factor_min", c.load_factor_min},
                   {"load_factor_max", c.load_factor_max},
                   {"control_limit_excess", c.control_limit_excess},
                   {"final_heading_change_deg", c.final_heading_change_deg},
                   {"final_bank_deg", c.final_bank_deg},
                   {"final_speed", c.final_speed},
                   {"final_altitude", c.final_altitude}};
    if (!out.empty()) {
        manoeuvres::write_trajectory_csv(traj, out / "trajectory.csv");
        manoeuvres::Trajectory dense = manoeuvres::dense_trajectory(problem, s, 0.02);
        dense.metadata.insert(dense.metadata.begin() + 1, {"aircraft", o.aircraft});
        set_phases(dense, true);
        manoeuvres::write_trajectory_csv(dense, out / "trajectory_dense.csv");
        if (s.converged()) optimal::write_csv(s, out / "solution.csv");
        write_plots(traj, spec.name, out);
        core::write_file_atomic(out / "summary.json", j.dump(2) + '\n');
    }
    if (o.json) {
        print_json(j);
    } else {
        if (adaptive) {
            fmt::print("error-driven mesh refinement (tolerance {:.3g}):\n{}", ro.tolerance,
                       optimal::refinement_report(*adaptive));
        }
        fmt::print("{}: {} in {} IPOPT iterations, {:.2f} s CPU\n", spec.name, s.status_text,
                   s.iterations, s.cpu_time);
        fmt::print("  final time               {:.6g} s\n", s.final_time);
        fmt::print("  max constraint violation {:.3e}\n", s.max_violation);
        fmt::print("  re-simulation error      {:.3e} (scaled)\n", s.resimulation.max_scaled_error);
        fmt::print("  alpha max {:.3f} deg, nz [{:.3f}, {:.3f}], heading change {:.3f} deg\n",
                   c.alpha_max_deg, c.load_factor_min, c.load_factor_max,
                   c.final_heading_change_deg);
        if (adaptive) {
            fmt::print("  mesh                     {} segment(s), {} LGL points\n", K,
                       total_nodes(r.mesh));
        }
        if (!out.empty()) fmt::print("  written to               {}\n", out.string());
    }
    if (!s.converged()) {
        std::fputs(optimal::failure_report(s, so.failure_csv).c_str(), stderr);
        return 1;
    }
    if (!s.resolved()) fmt::print(stderr, "warning: {}: {}\n", spec.name, s.status_text);
    if (adaptive && adaptive->status != optimal::RefinementStatus::tolerance_met) {
        fmt::print(stderr, "warning: {}: mesh refinement {}: {}\n", spec.name,
                   optimal::to_string(adaptive->status), adaptive->status_text);
    }
    return 0;
}

}  // namespace

void add_optimise(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand(
        "optimise", "Optimal control by Legendre-Gauss-Lobatto collocation and IPOPT");
    auto o = std::make_shared<OptimiseOptions>();
    auto* problem_opt =
        cmd->add_option("--problem", o->problem,
                        "Validation problem: brachistochrone, min-time-to-climb, double-integrator")
            ->check(CLI::IsMember({"brachistochrone", "min-time-to-climb", "double-integrator"}));
    auto* aircraft_opt =
        cmd->add_option("--aircraft", o->aircraft, "Aircraft file (with --manoeuvre)")
            ->check(CLI::ExistingFile);
    auto* manoeuvre_opt =
        cmd->add_option("--manoeuvre", o->manoeuvre, "Manoeuvre file (docs/manoeuvres.md)")
            ->check(CLI::ExistingFile);
    cmd->add_option("--tables", o->tables, "Aero database replacing the aircraft's")
        ->check(CLI::ExistingFile);
    aircraft_opt->needs(manoeuvre_opt);
    manoeuvre_opt->needs(aircraft_opt);
    problem_opt->excludes(aircraft_opt);
    problem_opt->excludes(manoeuvre_opt);
    auto* nodes_opt = cmd->add_option("--nodes", o->nodes,
                                      "LGL points per segment (default 40, or the manoeuvre's)")
                          ->check(integer_in(2, 400));
    cmd->add_option("--segments", o->segments, "Number of equal segments, hp (default 1)")
        ->check(integer_in(1, 200));
    cmd->add_flag("--free-breaks", o->free_breaks, "Segment breaks are decision variables");
    auto* refine_opt =
        cmd->add_flag("--refine", o->refine,
                      "After solving, break the mesh where a control jumps and re-solve (hp)");
    auto* adaptive_opt = cmd->add_flag(
        "--adaptive", o->adaptive,
        "Error-driven ph mesh refinement from the problem's or manoeuvre's mesh: split segments "
        "or raise their degree until every segment's error estimate is below --adaptive-tol "
        "(docs/optimal-control.md)");
    adaptive_opt->excludes(refine_opt);
    cmd->add_option("--adaptive-tol", o->adaptive_tolerance,
                    "--adaptive: relative error target per segment (default 1e-6)")
        ->check(real_positive(1.0))
        ->needs(adaptive_opt);
    cmd->add_option("--max-passes", o->max_passes,
                    "--adaptive: most solves, the first mesh's included (default 10)")
        ->check(integer_in(1, 100))
        ->needs(adaptive_opt);
    cmd->add_option("--min-nodes", o->min_nodes,
                    "--adaptive: LGL points of each segment a split creates (default 4)")
        ->check(integer_in(2, 400))
        ->needs(adaptive_opt);
    cmd->add_option("--max-nodes", o->max_nodes,
                    "--adaptive: most LGL points a segment reaches by raising its degree "
                    "(default 12)")
        ->check(integer_in(2, 400))
        ->needs(adaptive_opt);
    auto* hessian_opt =
        cmd->add_option("--hessian", o->hessian, "exact (default) or limited-memory")
            ->check(CLI::IsMember({"exact", "limited-memory"}));
    auto* tol_opt =
        cmd->add_option("--tol", o->tolerance, "IPOPT tolerance (default 1e-8, or the manoeuvre's)")
            ->check(real_positive(1.0));
    cmd->add_option("--max-iter", o->max_iterations, "IPOPT iteration limit (default 3000)")
        ->check(integer_in(1, 1000000));
    cmd->add_option("--atmosphere", o->atmosphere,
                    "min-time-to-climb atmosphere: us1976 (default) or troposphere-only")
        ->check(CLI::IsMember({"us1976", "troposphere-only"}));
    cmd->add_option("--out", o->out, "Write solution.csv and summary.json into this folder")
        ->check(output_path());
    cmd->add_flag("--json", o->json, "Print one JSON object (SI units unless the name says)");
    cmd->add_flag("--progress", o->progress, "Print a progress line per IPOPT iteration (stderr)");
    cmd->add_option("--ipopt-print-level", o->ipopt_print_level,
                    "IPOPT's own console output, 0 (default) to 12")
        ->check(integer_in(0, 12));
    cmd->add_option("--ipopt", o->ipopt, "Further IPOPT option KEY=VALUE (repeatable)");
    cmd->callback([o, &action, nodes_opt, hessian_opt, tol_opt, problem_opt, aircraft_opt] {
        o->nodes_given = nodes_opt->count() > 0;
        o->hessian_given = hessian_opt->count() > 0;
        o->tolerance_given = tol_opt->count() > 0;
        if (problem_opt->count() == 0 && aircraft_opt->count() == 0) {
            throw CLI::ValidationError("optimise",
                                       "give --problem NAME, or --aircraft FILE --manoeuvre FILE");
        }
        if (o->adaptive && o->max_nodes < o->min_nodes) {
            throw CLI::ValidationError("optimise",
                                       fmt::format("--max-nodes {} is below --min-nodes "
                                                   "{}; expected --max-nodes >= "
                                                   "--min-nodes",
                                                   o->max_nodes, o->min_nodes));
        }
        action = [o]() -> int {
            if (!o->aircraft.empty()) return run_manoeuvre(*o);
            Case c = make_case(*o);
            optimal::Mesh mesh = optimal::Mesh::uniform(o->segments, o->nodes);
            mesh.free_breaks = o->free_breaks;
            optimal::SolverOptions so;
            so.hessian = o->hessian == "exact" ? optimal::HessianMode::exact
                                               : optimal::HessianMode::limited_memory;
            so.tolerance = o->tolerance;
            so.max_iterations = o->max_iterations;
            so.print_level = o->ipopt_print_level;
            so.ipopt_options = ipopt_pairs(o->ipopt);
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
            std::optional<core::RunFolderLock> lock;
            if (!out.empty()) {
                lock.emplace(out, "optimise");
                so.failure_csv = out / "best_iterate.csv";
            }
            const auto wall_start = std::chrono::steady_clock::now();
            std::optional<optimal::AdaptiveSolution> adaptive;
            const optimal::RefinementOptions ro = refinement_options(*o);
            optimal::Solution s;
            if (o->adaptive) {
                adaptive = optimal::solve_adaptive(*c.model, mesh, c.guess, so, ro);
                s = adaptive_totals(*adaptive);
                s.wall_time =
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start)
                        .count();
                mesh = adaptive->mesh;
            } else {
                s = optimal::solve(*c.model, mesh, c.guess, so);
            }
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
            nlohmann::json j = summary(*o, s, c, mesh);
            if (adaptive) {
                j["nodes"] = s.n_nodes();
                j["nodes_per_segment"] = mesh.nodes;
                j["refinement"] = refinement_fields(*adaptive, ro);
            }
            if (!out.empty()) {
                if (s.converged()) optimal::write_csv(s, out / "solution.csv");
                core::write_file_atomic(out / "summary.json", j.dump(2) + '\n');
            }
            if (o->json) {
                print_json(j);
            } else {
                if (adaptive) {
                    fmt::print("error-driven mesh refinement (tolerance {:.3g}):\n{}", ro.tolerance,
                               optimal::refinement_report(*adaptive));
                }
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
                if (adaptive) {
                    fmt::print("  mesh                     {} segment(s), {} LGL points\n",
                               mesh.n_segments(), total_nodes(mesh));
                } else {
                    fmt::print("  mesh                     {} segment(s) x {} LGL points\n",
                               mesh.n_segments(), o->nodes);
                }
                if (!out.empty()) fmt::print("  written to               {}\n", out.string());
            }
            if (!s.converged()) {
                std::fputs(optimal::failure_report(s, so.failure_csv).c_str(), stderr);
                return 1;
            }
            if (!s.resolved()) fmt::print(stderr, "warning: {}\n", s.status_text);
            if (adaptive && adaptive->status != optimal::RefinementStatus::tolerance_met) {
                fmt::print(stderr, "warning: mesh refinement {}: {}\n",
                           optimal::to_string(adaptive->status), adaptive->status_text);
            }
            return 0;
        };
    });
}

}  // namespace manta::cli
