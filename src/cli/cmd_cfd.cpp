/// `manta cfd`: a steady Euler solution on an unstructured mesh (docs/euler.md), serial or with
/// `mpirun -np N manta cfd ...`, or with `--motion` a time-accurate one along a motion file. The
/// arguments and the printing; the case itself is `euler::CfdCase` (euler/case.hpp).

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "checks.hpp"
#include "commands.hpp"
#include "manta/euler/case.hpp"
#include "manta/parallel/mpi.hpp"

namespace manta::cli {

namespace {

constexpr double deg = 3.14159265358979323846 / 180.0;

struct CfdArgs {
    std::string mesh, config, out, initial;
    std::optional<double> mach, alpha_deg, beta_deg;
    std::optional<double> elevator_deg, aileron_deg, rudder_deg;
    std::optional<double> p_hat, q_hat, r_hat;
    std::optional<int> max_iterations;
    std::optional<int> order;
    std::string motion;
    std::optional<double> dt;
    std::optional<int> max_steps;
    bool restart = false;
    bool json = false;
};

int run_cfd(const CfdArgs& a) {
    parallel::MpiEnvironment env;
    const parallel::Communicator& comm = env.communicator();
    const bool root = comm.rank() == 0;

    euler::CaseInputs in;
    in.mesh = a.mesh;
    in.config = a.config;
    in.out = a.out;
    in.initial = a.initial;
    in.mach = a.mach;
    if (a.alpha_deg) in.alpha = *a.alpha_deg * deg;
    if (a.beta_deg) in.beta = *a.beta_deg * deg;
    if (a.elevator_deg) in.elevator = *a.elevator_deg * deg;
    if (a.aileron_deg) in.aileron = *a.aileron_deg * deg;
    if (a.rudder_deg) in.rudder = *a.rudder_deg * deg;
    in.p_hat = a.p_hat;
    in.q_hat = a.q_hat;
    in.r_hat = a.r_hat;
    in.max_iterations = a.max_iterations;
    in.order = a.order;
    in.restart = a.restart;
    in.motion = a.motion;
    in.dt = a.dt;
    in.max_steps = a.max_steps;
    euler::CfdCase cfd(std::move(in), comm);

    // The progress line: rewritten in place on a terminal, every 10 s in a log.
    const bool tty = isatty(fileno(stderr)) != 0;
    const double every = tty ? 1.0 : 10.0;
    double last_print = -every;
    bool printed = false;
    auto progress = [&](const euler::CaseProgress& p) {
        if (p.unsteady) {
            if (p.wall_s - last_print < every && p.step < p.n_steps) return;
            last_print = p.wall_s;
            printed = true;
            std::fprintf(stderr,
                         "%scfd: step %d of %d  t %.6g of %.6g s  %d inner (%.2f orders)  CL %.5f  "
                         "CD %.5f  %.0f s, about %.0f s left%s",
                         tty ? "\r" : "", p.step, p.n_steps, p.time, p.end_time, p.iteration,
                         p.drop, p.CL, p.CD, p.wall_s, p.seconds_left.value_or(0.0),
                         tty ? "   " : "\n");
            return;
        }
        if (p.wall_s - last_print < every) return;
        last_print = p.wall_s;
        printed = true;
        const std::string left =
            p.seconds_left ? fmt::format(", about {:.0f} s left", *p.seconds_left) : "";
        std::fprintf(stderr,
                     "%scfd: iteration %d  log10 res %.2f (%.2f of %.0f orders)  CL %.5f  "
                     "CD %.5f  CFL %.3g  %.0f s%s%s",
                     tty ? "\r" : "", p.iteration, p.log10_residual, p.drop, p.target, p.CL, p.CD,
                     p.cfl, p.wall_s, left.c_str(), tty ? "   " : "\n");
    };
    const euler::CaseResult r = cfd.run(progress);
    if (root && tty && printed) std::fprintf(stderr, "\n");
    if (!root) return 0;

    const nlohmann::json& j = r.summary;
    const euler::SolveOutcome& oc = r.outcome;
    const double nodes = j["nodes"].get<double>();
    const double memory = j["peak_memory_bytes"].get<double>();
    if (a.json) {
        print_json(j);
    } else if (cfd.unsteady()) {
        fmt::print("{} ({} nodes) along {}: M {:g}, dt {:g} s, {} steps\n", a.mesh, cfd.n_nodes(),
                   a.motion, cfd.setup().flow.mach, cfd.dt(), cfd.n_steps());
        fmt::print("{}: {} inner iterations ({:.1f} per step) in {:.1f} s ({:.2f} s per step)\n",
                   oc.reason, oc.iterations, j["inner_iterations_per_step"].get<double>(),
                   oc.wall_s, j["seconds_per_step"].get<double>());
        fmt::print("last step: CL {:.6f}  CD {:.6f}  CMy {:.6f}; wrote {}\n", oc.forces.CL,
                   oc.forces.CD, oc.forces.CMy, a.out);
    } else {
        const euler::FlowCondition& f = cfd.setup().flow;
        std::string deflected;
        const auto& d = cfd.deflections();
        const char* modes[] = {"elevator", "aileron", "rudder"};
        for (std::size_t k = 0; k < d.size(); ++k)
            if (d[k] != 0.0) deflected += fmt::format(", {} {:g} deg", modes[k], d[k] / deg);
        const auto& w = cfd.rates();
        const char* rate_names[] = {"p_hat", "q_hat", "r_hat"};
        for (std::size_t k = 0; k < w.size(); ++k)
            if (w[k] != 0.0) deflected += fmt::format(", {} {:g}", rate_names[k], w[k]);
        fmt::print("{} ({} nodes, {} process{}): M {:g}, alpha {:g} deg, beta {:g} deg{}\n", a.mesh,
                   cfd.n_nodes(), comm.size(), comm.size() == 1 ? "" : "es", f.mach, f.alpha / deg,
                   f.beta / deg, deflected);
        fmt::print("{} after {} iterations in {:.1f} s\n", oc.reason, oc.iterations, oc.wall_s);
        fmt::print(
            "CL {:.6f}  CD {:.6f}  CY {:.6f}  CMx {:.6f}  CMy {:.6f}  CMz {:.6f}  (area "
            "{:.6g} m^2)\n",
            oc.forces.CL, oc.forces.CD, oc.forces.CY, oc.forces.CMx, oc.forces.CMy, oc.forces.CMz,
            cfd.solver().reference_area());
        fmt::print("peak memory {:.1f} MiB ({:.0f} bytes per node); wrote {}\n", memory / 1048576.0,
                   memory / nodes, a.out);
    }
    if (!oc.converged)
        std::fprintf(stderr, "manta: warning: not converged: %s\n", oc.reason.c_str());
    return 0;
}

}  // namespace

void add_cfd(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand(
        "cfd",
        "Steady Euler solution on an unstructured mesh (docs/euler.md): history.csv,\n"
        "surface.csv, surface.vtu, flow.vtu, summary.json and restart.bin in --out. Run with\n"
        "`mpirun -np N manta cfd ...` for N processes. A run started again with the same\n"
        "command continues from its restart file. With --motion: time-accurate along the\n"
        "motion (moving mesh, control surfaces from the configuration): coefficients.csv,\n"
        "summary.json, .pvd time series, restart_unsteady.bin. --elevator-deg, --aileron-deg,\n"
        "--rudder-deg deflect the control surfaces of the configuration or the mesh companion\n"
        "(steady runs; the mesh deforms before the solve); --p-hat, --q-hat, --r-hat solve in\n"
        "the frame turning with the body at those rates.");
    auto a = std::make_shared<CfdArgs>();
    cmd->add_option("--mesh", a->mesh, "Mesh file (.su2, .su2.gz, .msh, .cgns; docs/mesh.md)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("--mach", a->mach, "Free-stream Mach number (or flow.mach in --config)")
        ->check(real_in(0.0, 10.0));  // 0 is refused by the flow set-up, with its reason
    cmd->add_option("--alpha-deg", a->alpha_deg, "Angle of attack [deg] (default 0)")
        ->check(real_in(-range::max_angle_deg, range::max_angle_deg, "deg"));
    cmd->add_option("--beta-deg", a->beta_deg, "Sideslip [deg], wind from the right (default 0)")
        ->check(real_in(-range::max_angle_deg, range::max_angle_deg, "deg"));
    // Deflections: each control surface (`control_surfaces:` of the configuration or the mesh
    // companion) turns by gain times its mode's deflection (docs/euler.md, "Control
    // deflections"); beyond 45 deg the deformation of the volume is far outside its design.
    constexpr double max_deflection_deg = 45.0;
    cmd->add_option("--elevator-deg", a->elevator_deg,
                    "Elevator deflection [deg] (default 0; steady runs): the control surfaces "
                    "of mode elevator turn by gain times it about their hinges")
        ->check(real_in(-max_deflection_deg, max_deflection_deg, "deg"));
    cmd->add_option("--aileron-deg", a->aileron_deg,
                    "Aileron deflection [deg] (default 0; steady runs): the control surfaces "
                    "of mode aileron turn by gain times it (the gains' signs give the sides)")
        ->check(real_in(-max_deflection_deg, max_deflection_deg, "deg"));
    cmd->add_option("--rudder-deg", a->rudder_deg,
                    "Rudder deflection [deg] (default 0; steady runs): the control surfaces of "
                    "mode rudder turn by gain times it about their hinges")
        ->check(real_in(-max_deflection_deg, max_deflection_deg, "deg"));
    // Body rates: the steady flow in the frame turning with the body (docs/euler.md, "Rotation
    // rates"); beyond 1 the wing tip turns faster than the body flies.
    cmd->add_option("--p-hat", a->p_hat,
                    "Non-dimensional roll rate p b/(2V) (default 0, or flow.p_hat; steady runs): "
                    "the steady solution in the frame turning with the body about the moment point")
        ->check(real_in(-1.0, 1.0));
    cmd->add_option("--q-hat", a->q_hat,
                    "Non-dimensional pitch rate q c/(2V) (default 0, or flow.q_hat; steady runs)")
        ->check(real_in(-1.0, 1.0));
    cmd->add_option("--r-hat", a->r_hat,
                    "Non-dimensional yaw rate r b/(2V) (default 0, or flow.r_hat; steady runs)")
        ->check(real_in(-1.0, 1.0));
    cmd->add_option("--config", a->config,
                    "Configuration YAML: marker roles, reference values, numerics "
                    "(docs/formats.md#cfd-configuration); the mesh's companion file X.mesh.yaml "
                    "from `manta mesh`, when there is one, gives what it leaves out")
        ->check(CLI::ExistingFile);
    cmd->add_option("--out", a->out, "Output folder")->required()->check(output_path());
    cmd->add_option("--max-iterations", a->max_iterations,
                    "Iteration limit (overrides solver.max_iterations)")
        ->check(integer_in(1, 1000000000));
    cmd->add_option("--order", a->order, "Spatial order 1 or 2 (overrides numerics.order)")
        ->check(integer_in(1, 2));
    cmd->add_option("--initial", a->initial,
                    "Start from this restart file (another run's restart.bin on the same mesh)")
        ->check(CLI::ExistingFile);
    cmd->add_option("--motion", a->motion,
                    "Motion file (docs/formats.md#motion-file): run time-accurately along it "
                    "(coefficients.csv per physical step)")
        ->check(CLI::ExistingFile);
    cmd->add_option("--dt", a->dt,
                    "Physical time step [s] with --motion (default: the motion's sample spacing; "
                    "must divide its duration)")
        ->check(real_in(1e-12, 1e6, "s"));
    cmd->add_option("--max-steps", a->max_steps,
                    "With --motion: stop after this many physical steps in all (the same command "
                    "with a larger value continues)")
        ->check(integer_in(1, 1000000000));
    cmd->add_flag("--restart", a->restart, "Start over, ignoring the restart file in --out");
    cmd->add_flag("--json", a->json, "Print the summary as JSON");
    cmd->callback([a, &action] { action = [a] { return run_cfd(*a); }; });
}

}  // namespace manta::cli
