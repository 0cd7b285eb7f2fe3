/// @file case.cpp
/// The CFD case driver (case.hpp, docs/euler.md#the-case-driver).

#include "manta/euler/case.hpp"

#include <fmt/format.h>

#include <chrono>
#include <exception>
#include <fstream>
#include <span>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/core/version.hpp"
#include "manta/euler/output.hpp"
#include "manta/mesh/dual.hpp"
#include "manta/mesh/readers.hpp"
#include "manta/mesh/reorder.hpp"
#include "manta/mesh/vtu.hpp"
#include "manta/parallel/distributed.hpp"

namespace manta::euler {

namespace {

constexpr double deg = 3.14159265358979323846 / 180.0;
using clock = std::chrono::steady_clock;

/// Peak resident memory of this process [bytes] (Linux /proc; 0 elsewhere).
double peak_rss_bytes() {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("VmHWM:", 0) == 0) return 1024.0 * std::stod(line.substr(6));
    return 0.0;
}

double seconds_since(clock::time_point t) {
    return std::chrono::duration<double>(clock::now() - t).count();
}

}  // namespace

CaseSetup case_setup(const CfdConfig& config) {
    CaseSetup setup;
    if (config.mach) setup.flow.mach = *config.mach;
    setup.flow.alpha = config.alpha.value_or(0.0);
    setup.flow.beta = config.beta.value_or(0.0);
    setup.flow.gamma = config.gamma;
    setup.reference = config.reference;
    setup.spatial = config.spatial;
    setup.solver = config.solver;
    return setup;
}

CaseMesh read_case_mesh(const std::filesystem::path& file) {
    // Nodes renumbered in reverse Cuthill-McKee order (locality for the implicit solver);
    // surface.csv gives the file's node numbers.
    mesh::ReorderedMesh r = mesh::reorder_reverse_cuthill_mckee(mesh::read_mesh(file));
    return {std::move(r.mesh), std::move(r.old_from_new)};
}

nlohmann::json to_json(const ForceCoefficients& f) {
    return {{"CL", f.CL},   {"CD", f.CD},   {"CY", f.CY},   {"CFx", f.CFx},
            {"CFy", f.CFy}, {"CFz", f.CFz}, {"CMx", f.CMx}, {"CMy", f.CMy},
            {"CMz", f.CMz}, {"Cl", f.Cl()}, {"Cm", f.Cm()}, {"Cn", f.Cn()}};
}

struct CfdCase::Impl {
    CaseInputs in;
    const parallel::Communicator& comm;
    const bool root;
    clock::time_point t_start = clock::now();
    CfdConfig cfg;
    CaseSetup setup;
    std::optional<core::RunFolderLock> lock;
    std::optional<mesh::Mesh> global;  ///< rank 0 with several processes: the whole mesh
    std::vector<mesh::Index> file_node;
    parallel::LocalMesh local;
    mesh::DualMetrics dual;
    double read_s = 0;
    std::unique_ptr<SteadySolver> solver;
    std::filesystem::path restart_file;
    std::string fingerprint;
    int resumed_from = -1;
    std::vector<std::string> history;  ///< rank 0: history.csv's rows so far

    Impl(CaseInputs inputs, const parallel::Communicator& c)
        : in(std::move(inputs)), comm(c), root(c.rank() == 0) {}

    [[nodiscard]] const mesh::Mesh& out_mesh() const {
        return comm.size() == 1 ? local.mesh : *global;
    }

    /// 5 values per global node -> 5 per local node (owned and ghosts).
    template <class T>
    [[nodiscard]] std::vector<T> to_local(const std::vector<T>& global_values) const {
        std::vector<T> v(5 * static_cast<std::size_t>(local.mesh.n_nodes()));
        for (std::size_t i = 0; i < local.global_node.size(); ++i)
            for (int k = 0; k < 5; ++k)
                v[5 * i + k] =
                    global_values[5 * static_cast<std::size_t>(local.global_node[i]) + k];
        return v;
    }
    [[nodiscard]] NodeStates local_state(const std::vector<double>& U_global) const {
        const std::vector<double> v = to_local(U_global);
        return Eigen::Map<const NodeStates>(v.data(), 5, local.mesh.n_nodes());
    }

    void prepare();
    void resume_or_warm_start();
    void write_restart();
};

void CfdCase::Impl::prepare() {
    if (!in.config.empty()) cfg = read_cfd_config(in.config);
    setup = case_setup(cfg);
    const std::optional<double> mach = in.mach ? in.mach : cfg.mach;
    if (!mach)
        throw InputError(
            "manta cfd: no Mach number; give --mach or flow.mach in the configuration");
    setup.flow.mach = *mach;
    if (in.alpha) setup.flow.alpha = *in.alpha;
    if (in.beta) setup.flow.beta = *in.beta;
    setup.flow.validate();
    if (in.order) setup.spatial.order = *in.order;
    if (in.max_iterations) setup.solver.max_iterations = *in.max_iterations;

    // Rank 0 writes the run folder: it checks and locks it before the mesh is read (a second
    // `manta cfd` on the same folder stops here with exit 2; every process stops with it).
    {
        std::exception_ptr lock_error;
        if (root) {
            try {
                lock.emplace(in.out, "cfd");
            } catch (...) {
                lock_error = std::current_exception();
            }
        }
        parallel::rethrow_root_error(lock_error, comm);
    }

    // Rank 0 reads the mesh and distributes it.
    const auto t_read = clock::now();
    std::exception_ptr read_error;
    if (root) {
        try {
            CaseMesh r = read_case_mesh(in.mesh);
            global.emplace(std::move(r.mesh));
            file_node = std::move(r.file_node);
        } catch (...) {
            read_error = std::current_exception();
        }
    }
    // Every process stops with rank 0's error (none waits for it forever).
    parallel::rethrow_root_error(read_error, comm);
    local = comm.size() == 1 ? parallel::serial_local_mesh(std::move(*global))
                             : parallel::distribute(global ? &*global : nullptr, comm);
    if (comm.size() == 1) global.reset();  // the local mesh is the global one
    dual = mesh::compute_dual_metrics(local.mesh);
    read_s = seconds_since(t_read);
    setup.roles = resolve_roles(local.mesh, cfg);

    const Domain domain{&local.mesh, &dual, local.n_owned, local.halo.get()};
    solver = std::make_unique<SteadySolver>(domain, comm, setup);
    restart_file = in.out / "restart.bin";
    fingerprint = mesh_fingerprint(local.mesh, local.global_node, local.n_owned, comm);
    resume_or_warm_start();
}

void CfdCase::Impl::resume_or_warm_start() {
    // Continue from this folder's restart file, or warm-start from another run's.
    if (std::filesystem::exists(restart_file) && !in.restart) {
        const RestartData r = read_restart(restart_file, local.n_global_nodes);
        if (r.fingerprint != fingerprint || r.mach != setup.flow.mach ||
            r.alpha != setup.flow.alpha || r.beta != setup.flow.beta)
            throw InputError(fmt::format(
                "{}: this restart file belongs to another mesh or flow condition (Mach {}, alpha "
                "{:.6g} deg, beta {:.6g} deg); run with --restart to start over, or point "
                "--initial at it from a new --out folder",
                restart_file.string(), r.mach, r.alpha / deg, r.beta / deg));
        solver->set_state(local_state(r.U));
        solver->set_iteration_state(r.state);
        if (!r.U_backoff.empty()) solver->set_backoff_state(to_local(r.U_backoff));
        if (r.state.limiter_frozen && !r.limiter.empty()) {
            solver->set_frozen_limiter(to_local(r.limiter));
        } else if (r.state.limiter_frozen && !solver->limiter_values().empty()) {
            throw InputError(fmt::format(
                "{}: corrupt restart file (the limiter is frozen but its values are missing); "
                "run with --restart to start over",
                restart_file.string()));
        }
        resumed_from = r.state.iteration;
        if (root && std::filesystem::exists(in.out / "history.csv")) {
            std::ifstream hin(in.out / "history.csv");
            std::string line;
            std::getline(hin, line);  // header
            while (std::getline(hin, line)) {
                if (std::stoi(line.substr(0, line.find(','))) >= resumed_from) break;
                history.push_back(line);
            }
        }
    } else if (!in.initial.empty()) {
        const RestartData r = read_restart(in.initial, local.n_global_nodes);
        if (r.fingerprint != fingerprint)
            throw InputError(
                fmt::format("{}: the initial solution was computed on another mesh "
                            "({}; this mesh: {})",
                            in.initial.string(), r.fingerprint, fingerprint));
        // The residual drop counts from the peak of the run that computed the initial solution.
        solver->warm_start(local_state(r.U), r.state.peak_log10_residual);
    }
}

void CfdCase::Impl::write_restart() {
    const std::vector<double> U = parallel::gather_owned(
        local,
        std::span<const double>(solver->state().data(),
                                static_cast<std::size_t>(solver->state().size())),
        5, comm);
    // The back-off state and the frozen limiter: a resumed run continues bit for bit.
    const std::vector<float>& good = solver->backoff_state();
    const std::vector<double> good_global =
        parallel::gather_owned(local, std::vector<double>(good.begin(), good.end()), 5, comm);
    // A scheme without a limiter (JST, first order) has no values to keep, on every rank.
    const std::vector<double> phi_local =
        solver->iteration_state().limiter_frozen ? solver->limiter_values() : std::vector<double>{};
    const std::vector<double> phi = phi_local.empty()
                                        ? std::vector<double>{}
                                        : parallel::gather_owned(local, phi_local, 5, comm);
    if (!root) return;
    RestartData r;
    r.U_backoff.assign(good_global.begin(), good_global.end());
    r.limiter = phi;
    r.fingerprint = fingerprint;
    r.state = solver->iteration_state();
    r.mach = setup.flow.mach;
    r.alpha = setup.flow.alpha;
    r.beta = setup.flow.beta;
    r.U = U;
    euler::write_restart(restart_file, r);
    std::string h = history_header() + "\n";
    for (const std::string& l : history) h += l + "\n";
    core::write_file_atomic(in.out / "history.csv", h);
}

CfdCase::CfdCase(CaseInputs inputs, const parallel::Communicator& comm)
    : impl_(std::make_unique<Impl>(std::move(inputs), comm)) {
    impl_->prepare();
}

CfdCase::~CfdCase() = default;

const CaseSetup& CfdCase::setup() const noexcept {
    return impl_->setup;
}
const CfdConfig& CfdCase::config() const noexcept {
    return impl_->cfg;
}
int CfdCase::resumed_from() const noexcept {
    return impl_->resumed_from;
}
std::int64_t CfdCase::n_nodes() const noexcept {
    return impl_->local.n_global_nodes;
}
const SteadySolver& CfdCase::solver() const noexcept {
    return *impl_->solver;
}

CaseResult CfdCase::run(const Progress& progress) {
    Impl& c = *impl_;
    const parallel::Communicator& comm = c.comm;
    SteadySolver& solver = *c.solver;
    const CaseSetup& setup = c.setup;

    // Progress (the time left from the recent rate of residual drop), history rows and
    // checkpoints after every iteration. The checkpoint test is collective: every process
    // takes the same decision from the largest wall time.
    double last_checkpoint = 0.0;
    double drop_rate = 0.0;
    double prev_t = 0.0, prev_drop = 0.0, peak = solver.iteration_state().peak_log10_residual;
    const double target = setup.solver.residual_drop;
    auto monitor = [&](const IterationRecord& r) {
        if (c.root) c.history.push_back(history_row(r));
        peak = std::max(peak, r.log10_residual[0]);
        const double drop = peak - r.log10_residual[0];
        if (r.wall_s - prev_t > 2.0) {
            const double rate = (drop - prev_drop) / (r.wall_s - prev_t);
            drop_rate = drop_rate == 0.0 ? rate : 0.5 * (drop_rate + rate);
            prev_t = r.wall_s;
            prev_drop = drop;
        }
        if (c.root && progress) {
            CaseProgress p;
            p.iteration = r.iteration;
            p.log10_residual = r.log10_residual[0];
            p.drop = drop;
            p.target = target;
            p.CL = r.forces.CL;
            p.CD = r.forces.CD;
            p.cfl = r.cfl;
            p.wall_s = r.wall_s;
            if (drop_rate > 1e-6 && drop < target) p.seconds_left = (target - drop) / drop_rate;
            progress(p);
        }
        const double interval = c.cfg.output.checkpoint_interval_s;
        if (interval > 0 && comm.max(r.wall_s) - last_checkpoint >= interval) {
            last_checkpoint = comm.max(r.wall_s);
            c.write_restart();
        }
        return true;
    };

    // The steady solve. (A time-accurate run loops here over the physical steps.)
    CaseResult result;
    result.outcome = solver.solve(monitor);
    const SolveOutcome& oc = result.outcome;
    c.write_restart();

    // Output fields, gathered to rank 0 in the global numbering.
    const std::vector<double> prim =
        parallel::gather_owned(c.local, solver.primitive_state(), 5, comm);
    const std::vector<double> cp =
        parallel::gather_owned(c.local, solver.pressure_coefficient(), 1, comm);
    const std::vector<double> machs =
        parallel::gather_owned(c.local, solver.mach_number(), 1, comm);
    const double own_peak = peak_rss_bytes();
    double memory = comm.sum(own_peak);
    const double solver_memory = comm.sum(static_cast<double>(solver.memory_bytes()));
    if (!c.root) return result;

    const mesh::Mesh& out_mesh = c.out_mesh();
    const std::filesystem::path& out = c.in.out;
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
    if (c.cfg.output.surface) {
        write_surface_csv(out / "surface.csv", out_mesh, setup.roles, prim, cp, machs, c.file_node);
        mesh::write_vtu_surface(out / "surface.vtu", out_mesh, fields);
    }
    if (c.cfg.output.volume) mesh::write_vtu_volume(out / "flow.vtu", out_mesh, fields);

    // The outputs are written: this process's peak may have grown while writing them.
    memory += peak_rss_bytes() - own_peak;
    const double wall = seconds_since(c.t_start);
    nlohmann::json j;
    j["manta_version"] = core::version();
    j["mesh"] = c.in.mesh.string();
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
    j["coefficients"] = to_json(oc.forces);
    j["converged"] = oc.converged;
    j["reason"] = oc.reason;
    j["iterations"] = oc.iterations;
    j["residual_drop"] = oc.residual_drop;
    j["cfl_backoffs"] = oc.backoffs;
    j["resumed_from"] = c.resumed_from;
    j["wall_time_s"] = wall;
    j["solve_time_s"] = oc.wall_s;
    j["mesh_time_s"] = c.read_s;
    const int resumed = std::max(0, c.resumed_from);
    j["seconds_per_iteration_per_node"] =
        oc.iterations > resumed
            ? oc.wall_s / (oc.iterations - resumed) / static_cast<double>(out_mesh.n_nodes())
            : 0.0;
    j["peak_memory_bytes"] = memory;
    j["solver_memory_bytes"] = solver_memory;
    j["bytes_per_node"] = memory / static_cast<double>(out_mesh.n_nodes());
    core::write_file_atomic(out / "summary.json", j.dump(2) + "\n");
    result.summary = std::move(j);
    return result;
}

}  // namespace manta::euler
