/// `manta cfd`: a steady Euler solution on an unstructured mesh (docs/euler.md), serial or with
/// `mpirun -np N manta cfd ...`.

#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "checks.hpp"
#include "commands.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/core/version.hpp"
#include "manta/euler/config.hpp"
#include "manta/euler/output.hpp"
#include "manta/euler/solver.hpp"
#include "manta/mesh/dual.hpp"
#include "manta/mesh/readers.hpp"
#include "manta/mesh/reorder.hpp"
#include "manta/mesh/vtu.hpp"
#include "manta/parallel/distributed.hpp"
#include "manta/parallel/mpi.hpp"

namespace manta::cli {

namespace {

constexpr double deg = 3.14159265358979323846 / 180.0;

struct CfdArgs {
    std::string mesh, config, out, initial;
    std::optional<double> mach, alpha_deg, beta_deg;
    std::optional<int> max_iterations;
    std::optional<int> order;
    bool restart = false;
    bool json = false;
};

/// Peak resident memory of this process [bytes] (Linux /proc; 0 elsewhere).
double peak_rss_bytes() {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("VmHWM:", 0) == 0) return 1024.0 * std::stod(line.substr(6));
    return 0.0;
}

nlohmann::json forces_json(const euler::ForceCoefficients& f) {
    return {{"CL", f.CL},   {"CD", f.CD},   {"CY", f.CY},   {"CFx", f.CFx},
            {"CFy", f.CFy}, {"CFz", f.CFz}, {"CMx", f.CMx}, {"CMy", f.CMy},
            {"CMz", f.CMz}, {"Cl", f.Cl()}, {"Cm", f.Cm()}, {"Cn", f.Cn()}};
}

int run_cfd(const CfdArgs& a) {
    using clock = std::chrono::steady_clock;
    const auto t_start = clock::now();
    parallel::MpiEnvironment env;
    const parallel::Communicator& comm = env.communicator();
    const bool root = comm.rank() == 0;

    euler::CfdConfig cfg;
    if (!a.config.empty()) cfg = euler::read_cfd_config(a.config);
    euler::CaseSetup setup;
    const std::optional<double> mach = a.mach ? a.mach : cfg.mach;
    if (!mach)
        throw InputError(
            "manta cfd: no Mach number; give --mach or flow.mach in the configuration");
    setup.flow.mach = *mach;
    setup.flow.alpha = a.alpha_deg ? *a.alpha_deg * deg : cfg.alpha.value_or(0.0);
    setup.flow.beta = a.beta_deg ? *a.beta_deg * deg : cfg.beta.value_or(0.0);
    setup.flow.gamma = cfg.gamma;
    setup.flow.validate();
    setup.reference = cfg.reference;
    setup.spatial = cfg.spatial;
    if (a.order) setup.spatial.order = *a.order;
    setup.solver = cfg.solver;
    if (a.max_iterations) setup.solver.max_iterations = *a.max_iterations;

    // Rank 0 writes --out: it checks and locks the folder before the mesh is read (a second
    // `manta cfd` on the same folder stops here with exit 2; every process stops with it).
    std::optional<core::RunFolderLock> lock;
    {
        std::exception_ptr lock_error;
        if (root) {
            try {
                lock.emplace(a.out, "cfd");
            } catch (...) {
                lock_error = std::current_exception();
            }
        }
        parallel::rethrow_root_error(lock_error, comm);
    }

    // Rank 0 reads the mesh and distributes it.
    const auto t_read = clock::now();
    // Nodes renumbered in reverse Cuthill-McKee order (locality for the implicit solver);
    // surface.csv gives the file's node numbers.
    std::optional<mesh::Mesh> global;
    std::vector<mesh::Index> file_node;
    std::exception_ptr read_error;
    if (root) {
        try {
            mesh::ReorderedMesh r = mesh::reorder_reverse_cuthill_mckee(mesh::read_mesh(a.mesh));
            global.emplace(std::move(r.mesh));
            file_node = std::move(r.old_from_new);
        } catch (...) {
            read_error = std::current_exception();
        }
    }
    // Every process stops with rank 0's error (none waits for it forever).
    parallel::rethrow_root_error(read_error, comm);
    parallel::LocalMesh local = comm.size() == 1
                                    ? parallel::serial_local_mesh(std::move(*global))
                                    : parallel::distribute(global ? &*global : nullptr, comm);
    if (comm.size() == 1) global.reset();  // the local mesh is the global one
    const mesh::DualMetrics dual = mesh::compute_dual_metrics(local.mesh);
    const double read_s = std::chrono::duration<double>(clock::now() - t_read).count();
    setup.roles = euler::resolve_roles(local.mesh, cfg);
    const mesh::Mesh& out_mesh = comm.size() == 1 ? local.mesh : *global;

    euler::Domain domain{&local.mesh, &dual, local.n_owned, local.halo.get()};
    euler::SteadySolver solver(domain, comm, setup);

    const std::filesystem::path out(a.out);
    const std::filesystem::path restart_file = out / "restart.bin";
    const std::string fingerprint =
        euler::mesh_fingerprint(local.mesh, local.global_node, local.n_owned, comm);

    // 5 values per global node -> 5 per local node (owned and ghosts).
    auto to_local = [&]<class T>(const std::vector<T>& global_values) {
        std::vector<T> v(5 * static_cast<std::size_t>(local.mesh.n_nodes()));
        for (std::size_t i = 0; i < local.global_node.size(); ++i)
            for (int k = 0; k < 5; ++k)
                v[5 * i + k] =
                    global_values[5 * static_cast<std::size_t>(local.global_node[i]) + k];
        return v;
    };
    auto scatter = [&](const std::vector<double>& U_global) {
        const std::vector<double> v = to_local(U_global);
        solver.set_state(Eigen::Map<const euler::NodeStates>(v.data(), 5, local.mesh.n_nodes()));
    };

    // Continue from this folder's restart file, or warm-start from another run's.
    int resumed_from = -1;
    std::vector<std::string> history;
    if (std::filesystem::exists(restart_file) && !a.restart) {
        const euler::RestartData r = euler::read_restart(restart_file, local.n_global_nodes);
        if (r.fingerprint != fingerprint || r.mach != setup.flow.mach ||
            r.alpha != setup.flow.alpha || r.beta != setup.flow.beta)
            throw InputError(fmt::format(
                "{}: this restart file belongs to another mesh or flow condition (Mach {}, alpha "
                "{:.6g} deg, beta {:.6g} deg); run with --restart to start over, or point "
                "--initial at it from a new --out folder",
                restart_file.string(), r.mach, r.alpha / deg, r.beta / deg));
        scatter(r.U);
        solver.set_iteration_state(r.state);
        if (!r.U_backoff.empty()) solver.set_backoff_state(to_local(r.U_backoff));
        if (r.state.limiter_frozen && !r.limiter.empty()) {
            solver.set_frozen_limiter(to_local(r.limiter));
        } else if (r.state.limiter_frozen && !solver.limiter_values().empty()) {
            throw InputError(fmt::format(
                "{}: corrupt restart file (the limiter is frozen but its values are missing); "
                "run with --restart to start over",
                restart_file.string()));
        }
        resumed_from = r.state.iteration;
        if (root && std::filesystem::exists(out / "history.csv")) {
            std::ifstream in(out / "history.csv");
            std::string line;
            std::getline(in, line);  // header
            while (std::getline(in, line)) {
                if (std::stoi(line.substr(0, line.find(','))) >= resumed_from) break;
                history.push_back(line);
            }
        }
    } else if (!a.initial.empty()) {
        const euler::RestartData r = euler::read_restart(a.initial, local.n_global_nodes);
        if (r.fingerprint != fingerprint)
            throw InputError(
                fmt::format("{}: the initial solution was computed on another mesh "
                            "({}; this mesh: {})",
                            a.initial, r.fingerprint, fingerprint));
        scatter(r.U);
        // The residual drop counts from the peak of the run that computed the initial solution.
        euler::IterationState st = solver.iteration_state();
        st.peak_log10_residual = r.state.peak_log10_residual;
        solver.set_iteration_state(st);
    }

    auto write_restart = [&]() {
        const std::vector<double> U = parallel::gather_owned(
            local,
            std::span<const double>(solver.state().data(),
                                    static_cast<std::size_t>(solver.state().size())),
            5, comm);
        // The back-off state and the frozen limiter: a resumed run continues bit for bit.
        const std::vector<float>& good = solver.backoff_state();
        const std::vector<double> good_global =
            parallel::gather_owned(local, std::vector<double>(good.begin(), good.end()), 5, comm);
        // A scheme without a limiter (JST, first order) has no values to keep, on every rank.
        const std::vector<double> phi_local = solver.iteration_state().limiter_frozen
                                                  ? solver.limiter_values()
                                                  : std::vector<double>{};
        const std::vector<double> phi = phi_local.empty()
                                            ? std::vector<double>{}
                                            : parallel::gather_owned(local, phi_local, 5, comm);
        if (!root) return;
        euler::RestartData r;
        r.U_backoff.assign(good_global.begin(), good_global.end());
        r.limiter = phi;
        r.fingerprint = fingerprint;
        r.state = solver.iteration_state();
        r.mach = setup.flow.mach;
        r.alpha = setup.flow.alpha;
        r.beta = setup.flow.beta;
        r.U = U;
        euler::write_restart(restart_file, r);
        std::string h = euler::history_header() + "\n";
        for (const std::string& l : history) h += l + "\n";
        core::write_file_atomic(out / "history.csv", h);
    };

    const bool tty = isatty(fileno(stderr)) != 0;
    const double every = tty ? 1.0 : 10.0;
    double last_print = -every, last_checkpoint = 0.0;
    double drop_rate = 0.0;
    double prev_t = 0.0, prev_drop = 0.0, peak = solver.iteration_state().peak_log10_residual;
    bool printed = false;
    const double target = setup.solver.residual_drop;
    auto monitor = [&](const euler::IterationRecord& r) {
        if (root) history.push_back(euler::history_row(r));
        peak = std::max(peak, r.log10_residual[0]);
        const double drop = peak - r.log10_residual[0];
        if (r.wall_s - prev_t > 2.0) {
            const double rate = (drop - prev_drop) / (r.wall_s - prev_t);
            drop_rate = drop_rate == 0.0 ? rate : 0.5 * (drop_rate + rate);
            prev_t = r.wall_s;
            prev_drop = drop;
        }
        if (root && r.wall_s - last_print >= every) {
            last_print = r.wall_s;
            printed = true;
            const std::string left =
                drop_rate > 1e-6 && drop < target
                    ? fmt::format(", about {:.0f} s left", (target - drop) / drop_rate)
                    : "";
            std::fprintf(stderr,
                         "%scfd: iteration %d  log10 res %.2f (%.2f of %.0f orders)  CL %.5f  "
                         "CD %.5f  CFL %.3g  %.0f s%s%s",
                         tty ? "\r" : "", r.iteration, r.log10_residual[0], drop, target,
                         r.forces.CL, r.forces.CD, r.cfl, r.wall_s, left.c_str(),
                         tty ? "   " : "\n");
        }
        const double interval = cfg.output.checkpoint_interval_s;
        if (interval > 0 && comm.max(r.wall_s) - last_checkpoint >= interval) {
            last_checkpoint = comm.max(r.wall_s);
            write_restart();
        }
        return true;
    };

    const euler::SolveOutcome oc = solver.solve(monitor);
    if (root && tty && printed) std::fprintf(stderr, "\n");
    write_restart();

    // Output fields, gathered to rank 0 in the global numbering.
    const std::vector<double> prim_local = solver.primitive_state();
    const std::vector<double> cp_local = solver.pressure_coefficient();
    const std::vector<double> mach_local = solver.mach_number();
    const std::vector<double> prim = parallel::gather_owned(local, prim_local, 5, comm);
    const std::vector<double> cp = parallel::gather_owned(local, cp_local, 1, comm);
    const std::vector<double> machs = parallel::gather_owned(local, mach_local, 1, comm);
    const double own_peak = peak_rss_bytes();
    double memory = comm.sum(own_peak);
    const double solver_memory = comm.sum(static_cast<double>(solver.memory_bytes()));
    if (!root) return 0;

    const auto n = static_cast<std::size_t>(out_mesh.n_nodes());
    std::vector<double> rho(n), velocity(3 * n), p(n);
    for (std::size_t i = 0; i < n; ++i) {
        rho[i] = prim[5 * i];
        for (int k = 0; k < 3; ++k) velocity[3 * i + k] = prim[5 * i + 1 + k];
        p[i] = prim[5 * i + 4];
    }
    // Velocity as one 3-component array (ParaView glyphs and stream tracers take it directly).
    const std::vector<mesh::VtuField> fields{
        {"density", rho}, {"Velocity", velocity, 3}, {"pressure", p}, {"Cp", cp}, {"Mach", machs}};
    if (cfg.output.surface) {
        euler::write_surface_csv(out / "surface.csv", out_mesh, setup.roles, prim, cp, machs,
                                 file_node);
        mesh::write_vtu_surface(out / "surface.vtu", out_mesh, fields);
    }
    if (cfg.output.volume) mesh::write_vtu_volume(out / "flow.vtu", out_mesh, fields);

    // The outputs are written: this process's peak may have grown while writing them.
    memory += peak_rss_bytes() - own_peak;
    const double wall = std::chrono::duration<double>(clock::now() - t_start).count();
    nlohmann::json j;
    j["manta_version"] = core::version();
    j["mesh"] = a.mesh;
    j["nodes"] = out_mesh.n_nodes();
    j["processes"] = comm.size();
    j["flow"] = {{"mach", setup.flow.mach},
                 {"alpha_deg", setup.flow.alpha / deg},
                 {"beta_deg", setup.flow.beta / deg},
                 {"gamma", setup.flow.gamma}};
    j["reference"] = {{"area", solver.reference_area()},
                      {"chord", setup.reference.chord},
                      {"span", setup.reference.span},
                      {"moment_point",
                       {setup.reference.moment_point.x(), setup.reference.moment_point.y(),
                        setup.reference.moment_point.z()}}};
    j["coefficients"] = forces_json(oc.forces);
    j["converged"] = oc.converged;
    j["reason"] = oc.reason;
    j["iterations"] = oc.iterations;
    j["residual_drop"] = oc.residual_drop;
    j["cfl_backoffs"] = oc.backoffs;
    j["resumed_from"] = resumed_from;
    j["wall_time_s"] = wall;
    j["solve_time_s"] = oc.wall_s;
    j["mesh_time_s"] = read_s;
    j["seconds_per_iteration_per_node"] = oc.iterations > (resumed_from > 0 ? resumed_from : 0)
                                              ? oc.wall_s /
                                                    (oc.iterations - std::max(0, resumed_from)) /
                                                    static_cast<double>(out_mesh.n_nodes())
                                              : 0.0;
    j["peak_memory_bytes"] = memory;
    j["solver_memory_bytes"] = solver_memory;
    j["bytes_per_node"] = memory / static_cast<double>(out_mesh.n_nodes());
    core::write_file_atomic(out / "summary.json", j.dump(2) + "\n");
    if (a.json) {
        print_json(j);
    } else {
        fmt::print("{} ({} nodes, {} process{}): M {:g}, alpha {:g} deg, beta {:g} deg\n", a.mesh,
                   out_mesh.n_nodes(), comm.size(), comm.size() == 1 ? "" : "es", setup.flow.mach,
                   setup.flow.alpha / deg, setup.flow.beta / deg);
        fmt::print("{} after {} iterations in {:.1f} s\n", oc.reason, oc.iterations, oc.wall_s);
        fmt::print(
            "CL {:.6f}  CD {:.6f}  CY {:.6f}  CMx {:.6f}  CMy {:.6f}  CMz {:.6f}  (area "
            "{:.6g} m^2)\n",
            oc.forces.CL, oc.forces.CD, oc.forces.CY, oc.forces.CMx, oc.forces.CMy, oc.forces.CMz,
            solver.reference_area());
        fmt::print("peak memory {:.1f} MiB ({:.0f} bytes per node); wrote {}\n", memory / 1048576.0,
                   memory / static_cast<double>(out_mesh.n_nodes()), out.string());
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
        "command continues from its restart file.");
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
    cmd->add_option("--config", a->config,
                    "Configuration YAML: marker roles, reference values, numerics "
                    "(docs/formats.md#cfd-configuration)")
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
    cmd->add_flag("--restart", a->restart, "Start over, ignoring the restart file in --out");
    cmd->add_flag("--json", a->json, "Print the summary as JSON");
    cmd->callback([a, &action] { action = [a] { return run_cfd(*a); }; });
}

}  // namespace manta::cli
