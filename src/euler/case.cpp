/// @file case.cpp
/// The CFD case driver (case.hpp, docs/euler.md#the-case-driver).

#include "manta/euler/case.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <exception>
#include <fstream>
#include <limits>
#include <span>

#include "detail/binary_io.hpp"
#include "manta/aero/motion.hpp"
#include "manta/aero/types.hpp"
#include "manta/core/error.hpp"
#include "manta/core/frames.hpp"
#include "manta/core/io.hpp"
#include "manta/core/version.hpp"
#include "manta/euler/deflection.hpp"
#include "manta/euler/output.hpp"
#include "manta/euler/unsteady.hpp"
#include "manta/mesh/dual.hpp"
#include "manta/mesh/readers.hpp"
#include "manta/mesh/reorder.hpp"
#include "manta/mesh/vtu.hpp"
#include "manta/meshmotion/mesh_motion.hpp"
#include "manta/parallel/distributed.hpp"

namespace manta::euler {

namespace {

constexpr double deg = 3.14159265358979323846 / 180.0;
/// How the messages name the body rates (`CaseInputs::p_hat` ...).
constexpr std::array<const char*, 3> rate_options{"--p-hat", "--q-hat", "--r-hat"};
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

/// FNV-1a 64 of a text.
std::uint64_t fnv1a(std::string_view text) {
    std::uint64_t h = 1469598103934665603ULL;
    for (const char ch : text) {
        h ^= static_cast<unsigned char>(ch);
        h *= 1099511628211ULL;
    }
    return h;
}

using detail::BinIn;
using detail::BinOut;
constexpr char unsteady_magic[9] = "MANTAUN1";

/// The restart fingerprint's part for the control deflections `d` [rad] (none when all are 0,
/// so that an undeflected run keeps the fingerprint of runs before deflections existed).
std::string deflection_fingerprint(const ModeDeflections& d) {
    if (!deflects(d)) return {};
    return fmt::format(" deflections_rad={},{},{}", core::format_exact(d[0]),
                       core::format_exact(d[1]), core::format_exact(d[2]));
}
constexpr std::string_view deflection_key = " deflections_rad=";

/// The restart fingerprint's part for the body rates `r` (none when all are 0, as the
/// deflections'; after them).
std::string rate_fingerprint(const BodyRates& r) {
    if (!rotates(r)) return {};
    return fmt::format(" rates_hat={},{},{}", core::format_exact(r[0]), core::format_exact(r[1]),
                       core::format_exact(r[2]));
}
constexpr std::string_view rate_key = " rates_hat=";

/// The mesh's part of a restart fingerprint (without `deflection_fingerprint` and
/// `rate_fingerprint`): a warm start (--initial) may come from another deflection or rate.
std::string mesh_part(const std::string& fingerprint) {
    return fingerprint.substr(
        0, std::min(fingerprint.find(deflection_key), fingerprint.find(rate_key)));
}

/// The three comma-separated values after `key` in a restart fingerprint (NaN where unreadable),
/// or none without the key.
std::optional<std::array<double, 3>> fingerprint_values(const std::string& fingerprint,
                                                        std::string_view key) {
    const std::size_t at = fingerprint.find(key);
    if (at == std::string::npos) return std::nullopt;
    std::string rest = fingerprint.substr(at + key.size());
    std::array<double, 3> v{};
    for (double& x : v) {
        const std::size_t end = rest.find_first_of(", ");
        x = std::numeric_limits<double>::quiet_NaN();
        try {
            x = std::stod(rest.substr(0, end));
        } catch (const std::exception&) {
        }
        rest = end == std::string::npos || rest[end] == ' ' ? std::string() : rest.substr(end + 1);
    }
    return v;
}

/// The deflections and rates a restart fingerprint names, for messages ("elevator 5 deg, aileron
/// 0 deg, rudder 0 deg, no rotation", "no deflection, p_hat 0, q_hat 0.02, r_hat 0").
std::string condition_words(const std::string& fingerprint) {
    std::string text;
    if (const auto d = fingerprint_values(fingerprint, deflection_key)) {
        for (std::size_t k = 0; k < deflection_modes.size(); ++k)
            text +=
                fmt::format("{}{} {:.6g} deg", k ? ", " : "", deflection_modes[k], (*d)[k] / deg);
    } else {
        text = "no deflection";
    }
    if (const auto r = fingerprint_values(fingerprint, rate_key))
        text +=
            fmt::format(", p_hat {:.6g}, q_hat {:.6g}, r_hat {:.6g}", (*r)[0], (*r)[1], (*r)[2]);
    else
        text += ", no rotation";
    return text;
}

/// The .pvd collection of the VTU files written so far.
std::string pvd_text(const std::vector<std::pair<double, std::string>>& files) {
    std::string s =
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" "
        "byte_order=\"LittleEndian\">\n  <Collection>\n";
    for (const auto& [t, f] : files)
        s += fmt::format("    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n",
                         core::format_exact(t), f);
    s += "  </Collection>\n</VTKFile>\n";
    return s;
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

void orient_mesh(mesh::Mesh& m, const CfdConfig& config) {
    if (config.mesh_up != "y") return;
    // A 2-D mesh's slab in the x-y plane: +90 deg about x, (x, y, z) -> (x, -z, y).
    std::vector<double> x(m.coordinates().begin(), m.coordinates().end());
    for (std::size_t i = 0; i + 2 < x.size(); i += 3) {
        const double y = x[i + 1], z = x[i + 2];
        x[i + 1] = -z;
        x[i + 2] = y;
    }
    m.set_coordinates(x);
}

MotionStepping motion_stepping(const aero::Motion& motion, const std::string& src, double mach,
                               std::optional<double> given_dt, const UnsteadySettings& inner,
                               const std::vector<meshmotion::ControlSurfaceSpec>& surfaces,
                               const std::string& dt_what, const std::string& motion_what) {
    if (motion.metadata.mach && std::abs(*motion.metadata.mach - mach) > 1e-6)
        throw InputError(
            fmt::format("{}: '# mach: {}' differs from the flow's Mach number {}; give one of them",
                        src, *motion.metadata.mach, mach));
    if (!motion.metadata.v0)
        throw InputError(fmt::format(
            "{}: no '# v0:' line; the unsteady CFD needs the entry speed [m/s] to relate the "
            "motion's seconds to the flow",
            src));
    MotionStepping st;
    st.v0 = *motion.metadata.v0;
    const double duration = motion.t.back() - motion.t.front();
    double dt = 0.0;
    if (given_dt) {
        dt = *given_dt;
    } else {
        dt = motion.t[1] - motion.t[0];
        for (std::size_t i = 1; i < motion.t.size(); ++i)
            if (std::abs(motion.t[i] - motion.t[i - 1] - dt) > 1e-9 * duration)
                throw InputError(fmt::format(
                    "{}: the samples are not evenly spaced (row {}: spacing {} s, first {} s); "
                    "give --dt",
                    src, i + 1, motion.t[i] - motion.t[i - 1], dt));
    }
    const double n = std::round(duration / dt);
    if (!(dt > 0) || n < 1 || std::abs(n * dt - duration) > 1e-9 * duration)
        throw InputError(fmt::format(
            "{} {} s does not divide the duration {} s of {}; expected a time step of duration / "
            "N to 1e-9 (such as {:.17g} s, N = {:.0f})",
            dt_what, dt, duration, motion_what.empty() ? "the motion " + src : motion_what,
            duration / std::max(1.0, std::isfinite(n) ? n : 1.0),
            std::max(1.0, std::isfinite(n) ? n : 1.0)));
    st.n_steps = static_cast<int>(n);
    st.dt = duration / n;  // exactly N steps
    const double c_inf = st.v0 / mach;
    st.time_unit = 1.0 / c_inf;  // mesh length unit 1 m
    st.time = inner;
    st.time.dt = st.dt / st.time_unit;
    st.time.validate();
    std::string cs;
    for (const auto& c : surfaces)
        cs += fmt::format("{}:{}:{},{},{}:{},{},{}:{};", c.mode, c.marker, c.hinge[0].x(),
                          c.hinge[0].y(), c.hinge[0].z(), c.hinge[1].x(), c.hinge[1].y(),
                          c.hinge[1].z(), c.gain);
    st.fingerprint = fmt::format("motion={:016x} dt={} steps={} surfaces={:016x}",
                                 fnv1a(aero::motion_to_text(motion)), core::format_exact(st.dt),
                                 st.n_steps, fnv1a(cs));
    return st;
}

std::unique_ptr<meshmotion::MeshMotion> place_mesh_motion(
    const mesh::Mesh& mesh, const aero::Motion& motion, const ReferenceValues& reference,
    const std::string& source, const std::vector<meshmotion::ControlSurfaceSpec>& surfaces,
    const meshmotion::DeformationOptions& options) {
    meshmotion::MotionPlacement placement;
    placement.reference_point = reference.moment_point;
    placement.motion_source = source;
    auto m = std::make_unique<meshmotion::MeshMotion>(mesh, motion, placement, surfaces, options);
    m->check_motion();
    return m;
}

aero::UnsteadySample motion_sample(const aero::Motion& motion, double t, double v0,
                                   const ForceCoefficients& f, const ReferenceValues& reference) {
    const aero::MotionState ms = motion.at(t);
    const meshmotion::RigidPose pose = meshmotion::rigid_pose(ms, reference.moment_point);
    // Flow-frame (mesh-like axes) force and moment (moment lengths per axis) about the moving
    // reference point, then body axes: v_body = C D v_flow.
    const Eigen::Vector3d F(f.CFx, f.CFy, f.CFz);
    const double span = reference.span, chord = reference.chord;
    Eigen::Vector3d M(f.CMx * span, f.CMy * chord, f.CMz * span);
    M -= (pose.reference - reference.moment_point).cross(F);
    const Eigen::Matrix3d C = core::dcm_body_from_earth(ms.euler);  // motion frame -> body
    const Eigen::Matrix3d D = core::dcm_body_from_geometry();
    const Eigen::Vector3d Fb = C * D * F, Mb = C * D * M;
    const Eigen::Vector3d vb =
        C * Eigen::Vector3d(v0 + ms.velocity[0], ms.velocity[1], ms.velocity[2]);
    aero::UnsteadySample s;
    s.t = t;
    s.airspeed = vb.norm();
    s.alpha = std::atan2(vb.z(), vb.x());
    s.beta = std::asin(vb.y() / s.airspeed);
    s.wind = aero::wind_from_body(Fb.x(), Fb.y(), Fb.z(), s.alpha, s.beta);
    s.body.CX = Fb.x();
    s.body.CY = Fb.y();
    s.body.CZ = Fb.z();
    s.body.Cl = Mb.x() / span;
    s.body.Cm = Mb.y() / chord;
    s.body.Cn = Mb.z() / span;
    return s;
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
    // Steady control deflections [rad] (elevator, aileron, rudder), how messages name them, the
    // undeflected mesh's fingerprint and the deformation's wall time.
    ModeDeflections deflection{0.0, 0.0, 0.0};
    DeflectionNaming deflection_naming;
    std::string mesh_fingerprint_text;
    double deflection_s = 0;
    // Steady body rates (p_hat, q_hat, r_hat) and the frame turning with the body at them.
    BodyRates rates{0.0, 0.0, 0.0};
    RotatingFrame frame;
    int resumed_from = -1;
    std::vector<std::string> history;  ///< rank 0: history.csv's rows so far

    // Time-accurate runs.
    bool unsteady = false;
    aero::Motion motion;
    std::unique_ptr<meshmotion::MeshMotion> mesh_motion;
    std::unique_ptr<UnsteadySolver> usolver;
    double dt = 0;         ///< physical time step [s]
    double time_unit = 1;  ///< seconds per solver time unit (1 m / c_inf)
    double v0 = 0;         ///< the motion's entry speed [m/s]
    int n_steps = 0;
    std::string motion_fingerprint;
    std::filesystem::path unsteady_restart;
    std::vector<std::string> rows;    ///< coefficients.csv rows, step 0 first
    std::vector<int> inner_per_step;  ///< inner iterations of each step (for the summary)
    /// Wall and CPU seconds of each call for the mesh's coordinates, and of each physical step.
    std::vector<double> motion_wall_s, motion_cpu_s, step_wall_s, step_cpu_s;
    int unconverged_steps = 0;

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
    /// Deform the mesh by `deflection` (collective): rank 0 deforms the whole mesh and checks
    /// it, every process takes its nodes' coordinates and updates its dual metrics.
    void deflect();
    /// The frame of `rates` (collective): InputError on every process when it turns the mesh
    /// through a symmetry plane.
    void place_rotating_frame();
    void resume_or_warm_start();
    void write_restart();
    void prepare_motion();
    /// The local nodes' coordinates at step `step` (collective with several processes).
    void coordinates(long step, Eigen::Matrix3Xd& x);
    /// Owned values of all processes in global order on rank 0 (as `gather_owned`).
    [[nodiscard]] std::vector<double> gather(const double* v, Index cols, int comps) const {
        return parallel::gather_owned(
            local, std::span<const double>(v, static_cast<std::size_t>(cols) * comps), comps, comm);
    }
    Eigen::Matrix3Xd global_x;  ///< rank 0: the whole mesh's coordinates (several processes)
    std::vector<double> x_buffer;
    void resume_unsteady();
    void write_unsteady_restart();
    [[nodiscard]] double step_time(long step) const { return motion.t.front() + step * dt; }
    [[nodiscard]] std::string coefficient_row(int step, const TimeStepRecord* rec) const;
    CaseResult run_unsteady(const Progress& progress);
};

void CfdCase::Impl::coordinates(long step, Eigen::Matrix3Xd& x) {
    const auto wall0 = clock::now();
    const std::clock_t cpu0 = std::clock();
    struct Timer {  // the deformation's cost, also when it throws
        Impl& impl;
        clock::time_point wall0;
        std::clock_t cpu0;
        ~Timer() {
            impl.motion_wall_s.push_back(seconds_since(wall0));
            impl.motion_cpu_s.push_back(static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC);
        }
    } timer{*this, wall0, cpu0};
    const double t = step_time(step);
    if (comm.size() == 1) {
        mesh_motion->coordinates_at(t, x, step);
        return;
    }
    const auto n = static_cast<std::size_t>(local.n_global_nodes);
    x_buffer.assign(3 * n, 0.0);
    std::exception_ptr err;
    if (root) {
        try {
            mesh_motion->coordinates_at(t, global_x, step);
            std::copy(global_x.data(), global_x.data() + 3 * n, x_buffer.begin());
        } catch (...) {
            err = std::current_exception();
        }
    }
    parallel::rethrow_root_error(err, comm);
    comm.sum(std::span<double>(x_buffer));  // rank 0's values to every process
    x.resize(3, local.mesh.n_nodes());
    for (Index i = 0; i < x.cols(); ++i) {
        const auto g = static_cast<std::size_t>(local.global_node[static_cast<std::size_t>(i)]);
        x.col(i) = Eigen::Vector3d(x_buffer[3 * g], x_buffer[3 * g + 1], x_buffer[3 * g + 2]);
    }
}

void CfdCase::Impl::prepare_motion() {
    const std::string src = in.motion.string();
    const MotionStepping st =
        motion_stepping(motion, src, setup.flow.mach, in.dt, cfg.unsteady, cfg.control_surfaces);
    if (cfg.alpha.value_or(0.0) != 0.0 || cfg.beta.value_or(0.0) != 0.0 || in.alpha || in.beta)
        throw InputError(fmt::format(
            "{}: flow.alpha and flow.beta must be 0 (or absent) with --motion; the attitude "
            "comes from the motion {}",
            cfg.source, src));
    v0 = st.v0;
    dt = st.dt;
    n_steps = st.n_steps;
    time_unit = st.time_unit;
    cfg.unsteady = st.time;
    motion_fingerprint = st.fingerprint;
    if (cfg.mesh_motion == meshmotion::BodyMotion::deforming)
        motion_fingerprint +=
            fmt::format(" mesh_motion=deforming rigid_radius={} fixed_radius={}",
                        core::format_exact(cfg.rigid_radius), core::format_exact(cfg.fixed_radius));
}

std::string CfdCase::Impl::coefficient_row(int step, const TimeStepRecord* rec) const {
    const ForceCoefficients f = rec ? rec->forces : usolver->forces();
    const aero::UnsteadySample s = motion_sample(motion, step_time(step), v0, f, setup.reference);
    using core::format_exact;
    return fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{}", format_exact(s.t),
                       format_exact(s.wind.CL), format_exact(s.wind.CD), format_exact(s.wind.CY),
                       format_exact(s.body.Cl), format_exact(s.body.Cm), format_exact(s.body.Cn),
                       format_exact(s.body.CX), format_exact(s.body.CZ), format_exact(s.alpha),
                       format_exact(s.beta), format_exact(s.airspeed),
                       rec ? rec->inner_iterations : 0,
                       rec ? format_exact(rec->residual_drop) : std::string("0"));
}

void CfdCase::Impl::write_unsteady_restart() {
    const TimeLevels l = usolver->time_levels();
    const NodeStates& Ul = usolver->state();
    // Global arrays on rank 0 (collective). The swept volumes are per local dual face: kept with
    // one process; with several a resumed run recomputes them from the two coordinate levels
    // (the same arithmetic, so the same values).
    const std::vector<double> U = gather(Ul.data(), Ul.cols(), 5);
    const std::vector<double> U_prev =
        l.U_prev.cols() ? gather(l.U_prev.data(), l.U_prev.cols(), 5) : std::vector<double>{};
    const std::vector<double> x = gather(l.x.data(), l.x.cols(), 3);
    const std::vector<double> x_prev =
        l.x_prev.cols() ? gather(l.x_prev.data(), l.x_prev.cols(), 3) : std::vector<double>{};
    if (!root) return;
    BinOut b;
    b.buf.append(unsteady_magic, 8);
    b.put_string(fingerprint);
    b.put_string(motion_fingerprint);
    b.put_string(in.motion.string());
    b.put(setup.flow.mach);
    b.put(static_cast<std::int32_t>(l.steps));
    b.put(l.cfl);
    b.put_doubles(U.data(), U.size());
    b.put_doubles(U_prev.data(), U_prev.size());
    b.put_doubles(x.data(), x.size());
    b.put_doubles(x_prev.data(), x_prev.size());
    const bool swept = comm.size() == 1 && l.x_prev.cols() > 0;
    b.put_doubles(l.swept_prev.edges.data(), swept ? l.swept_prev.edges.size() : 0);
    b.put(static_cast<std::uint64_t>(swept ? l.swept_prev.boundary.size() : 0));
    if (swept)
        for (const auto& v : l.swept_prev.boundary) b.put_doubles(v.data(), v.size());
    b.put(static_cast<std::int32_t>(unconverged_steps));
    b.put(static_cast<std::uint64_t>(rows.size()));
    for (const std::string& r : rows) b.put_string(r);
    for (const int k : inner_per_step) b.put(static_cast<std::int32_t>(k));
    core::write_file_atomic(unsteady_restart, b.buf);
    std::string csv =
        "t,CL,CD,CY,Cl,Cm,Cn,CX,CZ,alpha,beta,airspeed,inner_iterations,residual_drop\n";
    for (const std::string& r : rows) csv += r + "\n";
    core::write_file_atomic(in.out / "coefficients.csv", csv);
}

void CfdCase::Impl::resume_unsteady() {
    const std::string file = unsteady_restart.string();
    const std::string buf = core::read_file(unsteady_restart);
    if (buf.size() < 8 || buf.compare(0, 8, unsteady_magic) != 0)
        throw InputError(fmt::format(
            "{}: not a MANTA unsteady restart file; run with --restart to start over", file));
    BinIn b{buf, 8, file};
    const std::string fp = b.get_string(), mfp = b.get_string(), mfile = b.get_string();
    const auto mach = b.get<double>();
    if (fp != fingerprint || mach != setup.flow.mach)
        throw InputError(fmt::format(
            "{}: this restart file belongs to another mesh or Mach number ({}, Mach {}; this "
            "run: {}, Mach {}); run with --restart to start over",
            file, fp, mach, fingerprint, setup.flow.mach));
    if (mfp != motion_fingerprint)
        throw InputError(fmt::format(
            "{}: this restart file belongs to another motion ({}: {}); this run's is {} ({}); "
            "run with --restart to start over",
            file, mfile, mfp, in.motion.string(), motion_fingerprint));
    TimeLevels l;
    l.steps = b.get<std::int32_t>();
    l.cfl = b.get<double>();
    const auto n = static_cast<Index>(local.mesh.n_nodes());
    const auto n_global = static_cast<std::size_t>(local.n_global_nodes);
    auto fits = [&](const std::vector<double>& v, std::size_t comps, const char* what) {
        if (!v.empty() && v.size() != comps * n_global)
            throw InputError(fmt::format("{}: {} has {} values; expected {} per node of {}", file,
                                         what, v.size(), comps, n_global));
    };
    // Global values -> the local nodes.
    auto as5 = [&](const std::vector<double>& v) {
        fits(v, 5, "a state");
        NodeStates U(5, v.empty() ? 0 : n);
        for (Index i = 0; i < U.cols(); ++i)
            for (int k = 0; k < 5; ++k)
                U(k, i) =
                    v[5 * static_cast<std::size_t>(local.global_node[static_cast<std::size_t>(i)]) +
                      k];
        return U;
    };
    auto as3 = [&](const std::vector<double>& v) {
        fits(v, 3, "a coordinate level");
        Eigen::Matrix3Xd x(3, v.empty() ? 0 : n);
        for (Index i = 0; i < x.cols(); ++i)
            for (int k = 0; k < 3; ++k)
                x(k, i) =
                    v[3 * static_cast<std::size_t>(local.global_node[static_cast<std::size_t>(i)]) +
                      k];
        return x;
    };
    const NodeStates U = as5(b.get_doubles());
    l.U_prev = as5(b.get_doubles());
    l.x = as3(b.get_doubles());
    l.x_prev = as3(b.get_doubles());
    l.swept_prev.edges = b.get_doubles();
    const auto nb = b.get<std::uint64_t>();
    for (std::uint64_t k = 0; k < nb; ++k) l.swept_prev.boundary.push_back(b.get_doubles());
    if (U.cols() != n) throw InputError(fmt::format("{}: no state; corrupt file", file));
    unconverged_steps = b.get<std::int32_t>();
    const auto nr = b.get<std::uint64_t>();
    for (std::uint64_t k = 0; k < nr; ++k) rows.push_back(b.get_string());
    for (std::uint64_t k = 1; k < nr; ++k) inner_per_step.push_back(b.get<std::int32_t>());
    if (l.x_prev.cols() == 0 || comm.size() > 1) l.swept_prev = {};  // recomputed by restore
    usolver->restore(U, l);
    resumed_from = l.steps;
}

void CfdCase::Impl::prepare() {
    if (!in.config.empty()) cfg = read_cfd_config(in.config);
    apply_mesh_companion(cfg, in.mesh);  // the mesh's companion file, where the file is silent
    setup = case_setup(cfg);
    if (!in.motion.empty()) motion = aero::read_motion(in.motion);
    std::optional<double> mach = in.mach ? in.mach : cfg.mach;
    if (!mach && !in.motion.empty()) mach = motion.metadata.mach;
    if (!mach)
        throw InputError(
            "manta cfd: no Mach number; give --mach or flow.mach in the configuration (or # mach: "
            "in the motion file)");
    setup.flow.mach = *mach;
    if (in.alpha) setup.flow.alpha = *in.alpha;
    if (in.beta) setup.flow.beta = *in.beta;
    setup.flow.validate();
    if (in.order) setup.spatial.order = *in.order;
    if (in.max_iterations) setup.solver.max_iterations = *in.max_iterations;
    unsteady = !in.motion.empty();
    if (unsteady) {
        prepare_motion();
        if (!in.initial.empty())
            throw InputError(
                "manta cfd --motion starts from the free stream; --initial is not "
                "taken with --motion");
    } else if (in.dt || in.max_steps) {
        throw InputError("manta cfd: --dt and --max-steps need --motion");
    }
    const std::array<const std::optional<double>*, 3> given{&in.elevator, &in.aileron, &in.rudder};
    deflection_naming.who = "manta cfd";
    deflection_naming.names = {"--elevator-deg", "--aileron-deg", "--rudder-deg"};
    deflection_naming.unit = "";
    deflection_naming.config =
        in.config.empty() && cfg.companion.empty()
            ? std::string("the default configuration (no --config, no mesh companion)")
        : in.config.empty()     ? "the mesh companion " + cfg.companion.string()
        : cfg.companion.empty() ? in.config.string()
                                : fmt::format("{} with the mesh companion {}", in.config.string(),
                                              cfg.companion.string());
    for (std::size_t k = 0; k < given.size(); ++k) {
        if (!*given[k]) continue;
        if (unsteady)
            throw InputError(fmt::format(
                "manta cfd: {} {:.6g} is not taken with --motion; the control surfaces deflect "
                "by the motion file's mode columns (mode_{}) there",
                deflection_naming.names[k], **given[k] / deg, deflection_modes[k]));
        deflection[k] = **given[k];
    }
    // A deflection of a mode no surface has, or one not finite: refused before the mesh is read.
    (void)surface_deflections(cfg.control_surfaces, deflection, deflection_naming);
    // Body rates: the command line over the configuration's flow.p_hat, q_hat, r_hat.
    const std::array<std::optional<double>, 3> given_rates{in.p_hat ? in.p_hat : cfg.p_hat,
                                                           in.q_hat ? in.q_hat : cfg.q_hat,
                                                           in.r_hat ? in.r_hat : cfg.r_hat};
    for (std::size_t k = 0; k < rates.size(); ++k) {
        if (!given_rates[k]) continue;
        if (!std::isfinite(*given_rates[k]))
            throw InputError(fmt::format("manta cfd: {} {}: expected a finite rate",
                                         rate_options[k], *given_rates[k]));
        rates[k] = *given_rates[k];
    }
    if (unsteady && rotates(rates))
        throw InputError(fmt::format(
            "manta cfd: --p-hat {:g}, --q-hat {:g}, --r-hat {:g} (or flow.p_hat, q_hat, r_hat) "
            "are not taken with --motion; the body's rates come from the motion {} there",
            rates[0], rates[1], rates[2], in.motion.string()));

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
            orient_mesh(r.mesh, cfg);
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
    fingerprint = mesh_fingerprint(local.mesh, local.global_node, local.n_owned, comm);
    mesh_fingerprint_text = fingerprint;
    if (!unsteady && deflects(deflection)) {
        // The fingerprint is the undeflected mesh's and the deflections': a warm start
        // (--initial) may come from another deflection, a resumed run not.
        deflect();
        fingerprint += deflection_fingerprint(deflection);
    }
    if (!unsteady && rotates(rates)) {
        // The frame turning with the body (rotating_frame.hpp, as EulerSource::evaluate); the
        // fingerprint takes the rates as it takes the deflections.
        place_rotating_frame();
        fingerprint += rate_fingerprint(rates);
    }
    if (unsteady) {
        // The deformation's set-up needs the whole mesh: rank 0 moves the global mesh and every
        // process takes its nodes' coordinates (`coordinates`).
        std::exception_ptr motion_error;
        if (root) {
            try {
                const mesh::Mesh& whole = comm.size() == 1 ? local.mesh : *global;
                mesh_motion = place_mesh_motion(
                    whole, motion, setup.reference, in.motion.string(), cfg.control_surfaces,
                    motion_deformation(whole, setup.roles, cfg.mesh_motion, cfg.rigid_radius,
                                       cfg.fixed_radius));
            } catch (...) {
                motion_error = std::current_exception();
            }
        }
        parallel::rethrow_root_error(motion_error, comm);
        usolver = std::make_unique<UnsteadySolver>(domain, comm, setup, cfg.unsteady);
        usolver->set_moving_mesh(
            {&local.mesh, &dual,
             [this](double, long step, Eigen::Matrix3Xd& x) { coordinates(step, x); }});
        unsteady_restart = in.out / "restart_unsteady.bin";
        if (std::filesystem::exists(unsteady_restart) && !in.restart) resume_unsteady();
        return;
    }
    solver = std::make_unique<SteadySolver>(domain, comm, setup);
    if (frame.active()) solver->set_rotating_frame(frame);
    restart_file = in.out / "restart.bin";
    resume_or_warm_start();
}

void CfdCase::Impl::place_rotating_frame() {
    const ReferenceValues& ref = setup.reference;
    frame = body_rate_frame(rates, setup.flow.mach, ref.span, ref.chord, ref.moment_point);
    // A symmetry plane mirrors the flow: every process checks the plane nodes of its part, and
    // rank 0 names the first crossing of the lowest rank with one (the node in the file's
    // numbering); every process throws that error.
    constexpr std::size_t w = 6;  // found, marker, global node, normal
    std::vector<double> found(w * static_cast<std::size_t>(comm.size()), 0.0);
    if (const auto c = symmetry_crossing(frame, setup.roles, dual)) {
        double* f = found.data() + w * static_cast<std::size_t>(comm.rank());
        f[0] = 1.0;
        f[1] = static_cast<double>(c->marker);
        f[2] = static_cast<double>(local.global_node[static_cast<std::size_t>(c->node)]);
        for (int k = 0; k < 3; ++k) f[3 + k] = c->normal[k];
    }
    if (comm.size() > 1) comm.sum(std::span<double>(found));
    std::exception_ptr err;
    if (root) {
        for (std::size_t at = 0; at < found.size(); at += w) {
            if (found[at] == 0.0) continue;
            const auto marker = static_cast<std::size_t>(found[at + 1]);
            const auto g = static_cast<std::size_t>(found[at + 2]);
            const long long node = g < file_node.size() ? static_cast<long long>(file_node[g])
                                                        : static_cast<long long>(g);
            err = std::make_exception_ptr(InputError(symmetry_crossing_message(
                "manta cfd", {"--p-hat", "--q-hat", "--r-hat"}, rates, in.mesh.string(),
                local.mesh.markers()[marker], Vec3(found[at + 3], found[at + 4], found[at + 5]),
                node)));
            break;
        }
    }
    parallel::rethrow_root_error(err, comm);
}

void CfdCase::Impl::deflect() {
    const auto t0 = clock::now();
    std::exception_ptr err;
    if (root) {
        try {
            mesh::Mesh& whole = comm.size() == 1 ? local.mesh : *global;
            const std::unique_ptr<meshmotion::MeshMotion> motion =
                deflection_motion(whole, setup.roles, setup.reference.moment_point,
                                  cfg.control_surfaces, deflection_naming.config);
            const std::span<const mesh::Index> numbers(file_node);
            if (comm.size() == 1) {
                deflect_mesh(local.mesh, dual, motion.get(), cfg.control_surfaces, deflection,
                             deflection_naming, numbers);
            } else {
                mesh::DualMetrics whole_dual = mesh::compute_dual_metrics(whole);
                deflect_mesh(whole, whole_dual, motion.get(), cfg.control_surfaces, deflection,
                             deflection_naming, numbers);
            }
        } catch (...) {
            err = std::current_exception();
        }
    }
    parallel::rethrow_root_error(err, comm);
    if (comm.size() > 1) {
        // Rank 0's deformed coordinates to every process, which takes its nodes'.
        const auto n = static_cast<std::size_t>(local.n_global_nodes);
        std::vector<double> xg(3 * n, 0.0);
        if (root) std::copy(global->coordinates().begin(), global->coordinates().end(), xg.begin());
        comm.sum(std::span<double>(xg));
        std::vector<double> x(3 * static_cast<std::size_t>(local.mesh.n_nodes()));
        for (std::size_t i = 0; i < local.global_node.size(); ++i) {
            const auto g = static_cast<std::size_t>(local.global_node[i]);
            for (std::size_t k = 0; k < 3; ++k) x[3 * i + k] = xg[3 * g + k];
        }
        local.mesh.set_coordinates(x);
        mesh::update_dual_metrics(local.mesh, dual);
    }
    deflection_s = seconds_since(t0);
}

void CfdCase::Impl::resume_or_warm_start() {
    // Continue from this folder's restart file, or warm-start from another run's.
    if (std::filesystem::exists(restart_file) && !in.restart) {
        const RestartData r = read_restart(restart_file, local.n_global_nodes);
        if (r.fingerprint != fingerprint && mesh_part(r.fingerprint) == mesh_fingerprint_text)
            throw InputError(fmt::format(
                "{}: this restart file belongs to another {} ({}; this run: {}); run with "
                "--restart to start over, or point --initial at it from a new --out folder",
                restart_file.string(),
                fingerprint_values(r.fingerprint, deflection_key) ==
                        fingerprint_values(fingerprint, deflection_key)
                    ? "rotation rate"
                    : "control deflection",
                condition_words(r.fingerprint), condition_words(fingerprint)));
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
            // A history of an earlier version has fewer columns at the end (max_res_*): its
            // rows get empty cells there, under the present header.
            const std::string now = history_header();
            std::string pad;
            if (line != now && now.starts_with(line))
                pad.assign(
                    static_cast<std::size_t>(std::count(
                        now.begin() + static_cast<std::ptrdiff_t>(line.size()), now.end(), ',')),
                    ',');
            while (std::getline(hin, line)) {
                if (std::stoi(line.substr(0, line.find(','))) >= resumed_from) break;
                history.push_back(line + pad);
            }
        }
    } else if (!in.initial.empty()) {
        const RestartData r = read_restart(in.initial, local.n_global_nodes);
        // A solution of another control deflection or rotation rate on the same mesh may start
        // this one.
        if (mesh_part(r.fingerprint) != mesh_fingerprint_text)
            throw InputError(
                fmt::format("{}: the initial solution was computed on another mesh "
                            "({}; this mesh: {})",
                            in.initial.string(), mesh_part(r.fingerprint), mesh_fingerprint_text));
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
const std::array<double, 3>& CfdCase::deflections() const noexcept {
    return impl_->deflection;
}
const BodyRates& CfdCase::rates() const noexcept {
    return impl_->rates;
}
int CfdCase::resumed_from() const noexcept {
    return impl_->resumed_from;
}
std::int64_t CfdCase::n_nodes() const noexcept {
    return impl_->local.n_global_nodes;
}
const SteadySolver& CfdCase::solver() const {
    if (!impl_->solver)
        throw InputError("CfdCase::solver: a time-accurate case has no steady solver");
    return *impl_->solver;
}
bool CfdCase::unsteady() const noexcept {
    return impl_->unsteady;
}
double CfdCase::dt() const noexcept {
    return impl_->dt;
}
int CfdCase::n_steps() const noexcept {
    return impl_->n_steps;
}

CaseResult CfdCase::Impl::run_unsteady(const Progress& progress) {
    UnsteadySolver& s = *usolver;
    const auto t_run = clock::now();
    const int first = s.steps();
    if (rows.empty()) rows.push_back(coefficient_row(0, nullptr));
    const int last = in.max_steps ? std::min(n_steps, *in.max_steps) : n_steps;
    const mesh::Mesh& m = local.mesh;
    std::vector<std::pair<double, std::string>> surface_files, volume_files;
    const int every = cfg.output_every;
    auto write_fields = [&](int step) {
        // Gathered to rank 0 in the global numbering, on the mesh at this step's coordinates.
        const int P = comm.size();
        std::vector<double> prim = primitive_state(s.state(), setup);
        std::vector<double> cp = pressure_coefficient(s.state(), setup);
        std::vector<double> machs = mach_number(s.state(), setup);
        if (P > 1) {
            prim = parallel::gather_owned(local, prim, 5, comm);
            cp = parallel::gather_owned(local, cp, 1, comm);
            machs = parallel::gather_owned(local, machs, 1, comm);
            const std::vector<double> xg = parallel::gather_owned(local, m.coordinates(), 3, comm);
            if (root) global->set_coordinates(xg);
        }
        if (!root) return;
        const mesh::Mesh& om = P == 1 ? m : *global;
        const auto n = static_cast<std::size_t>(om.n_nodes());
        std::vector<double> rho(n), velocity(3 * n), p(n);
        for (std::size_t i = 0; i < n; ++i) {
            rho[i] = prim[5 * i];
            for (int k = 0; k < 3; ++k) velocity[3 * i + k] = prim[5 * i + 1 + k];
            p[i] = prim[5 * i + 4];
        }
        const std::vector<mesh::VtuField> fields{{"density", rho},
                                                 {"Velocity", velocity, 3},
                                                 {"pressure", p},
                                                 {"Cp", cp},
                                                 {"Mach", machs}};
        const std::string tag = fmt::format("{:06d}", step);
        if (cfg.output.surface)
            mesh::write_vtu_surface(in.out / ("surface_" + tag + ".vtu"), om, fields);
        if (cfg.output.volume)
            mesh::write_vtu_volume(in.out / ("flow_" + tag + ".vtu"), om, fields);
    };
    auto write_pvd = [&](int upto) {
        surface_files.clear();
        volume_files.clear();
        if (every <= 0) return;
        for (int k = 0; k <= upto; k += every) {
            const std::string tag = fmt::format("{:06d}", k);
            surface_files.emplace_back(step_time(k), "surface_" + tag + ".vtu");
            volume_files.emplace_back(step_time(k), "flow_" + tag + ".vtu");
        }
        if (!root) return;
        if (cfg.output.surface)
            core::write_file_atomic(in.out / "surface.pvd", pvd_text(surface_files));
        if (cfg.output.volume) core::write_file_atomic(in.out / "flow.pvd", pvd_text(volume_files));
    };
    if (every > 0 && first == 0) {
        write_fields(0);
        write_pvd(0);
    }
    double last_checkpoint = 0.0;
    const double interval = cfg.output.checkpoint_interval_s;
    TimeStepRecord rec;
    for (int k = first + 1; k <= last; ++k) {
        const auto step_wall0 = clock::now();
        const std::clock_t step_cpu0 = std::clock();
        rec = s.advance();
        step_wall_s.push_back(seconds_since(step_wall0));
        step_cpu_s.push_back(static_cast<double>(std::clock() - step_cpu0) / CLOCKS_PER_SEC);
        rows.push_back(coefficient_row(k, &rec));
        inner_per_step.push_back(rec.inner_iterations);
        if (!rec.converged) ++unconverged_steps;
        if (every > 0 && k % every == 0) {
            write_fields(k);
            write_pvd(k);
        }
        const double wall = comm.max(seconds_since(t_run));  // the same decision everywhere
        if (k == last || interval == 0.0 || wall - last_checkpoint >= interval) {
            last_checkpoint = wall;
            write_unsteady_restart();
        }
        if (root && progress) {
            CaseProgress p;
            p.unsteady = true;
            p.step = k;
            p.n_steps = n_steps;
            p.time = step_time(k);
            p.end_time = motion.t.back();
            p.iteration = rec.inner_iterations;
            p.drop = rec.residual_drop;
            p.target = cfg.unsteady.inner_drop;
            p.CL = rec.forces.CL;
            p.CD = rec.forces.CD;
            p.wall_s = wall;
            p.seconds_left = wall / (k - first) * (last - k);
            progress(p);
        }
    }
    if (first >= last) write_unsteady_restart();
    const double solve_s = seconds_since(t_run);

    CaseResult result;
    SolveOutcome& oc = result.outcome;
    oc.converged = unconverged_steps == 0;
    oc.wall_s = solve_s;
    oc.forces = s.forces();
    for (const int it : inner_per_step) oc.iterations += it;
    oc.reason = last < n_steps ? fmt::format("stopped after step {} of {}", last, n_steps)
                               : fmt::format("{} physical steps", n_steps);
    if (unconverged_steps > 0)
        oc.reason += fmt::format(", {} with the inner iterations at their cap", unconverged_steps);
    const double memory = comm.sum(peak_rss_bytes());
    if (!root) return result;
    nlohmann::json j;
    j["manta_version"] = core::version();
    j["mesh"] = in.mesh.string();
    j["motion"] = in.motion.string();
    if (!cfg.companion.empty()) j["companion"] = cfg.companion.string();
    j["nodes"] = local.n_global_nodes;
    j["processes"] = comm.size();
    j["flow"] = {{"mach", setup.flow.mach}, {"v0", v0}, {"gamma", setup.flow.gamma}};
    j["reference"] = {{"area", s.reference_area()},
                      {"chord", setup.reference.chord},
                      {"span", setup.reference.span},
                      {"moment_point",
                       {setup.reference.moment_point.x(), setup.reference.moment_point.y(),
                        setup.reference.moment_point.z()}},
                      {"half_model", setup.reference.half_model}};
    j["dt"] = dt;
    j["dt_solver"] = cfg.unsteady.dt;
    j["order"] = cfg.unsteady.order;
    j["steps"] = last;
    j["n_steps"] = n_steps;
    j["time"] = step_time(last);
    j["coefficients"] = to_json(oc.forces);
    j["converged"] = oc.converged;
    j["reason"] = oc.reason;
    j["unconverged_steps"] = unconverged_steps;
    j["inner_iterations"] = oc.iterations;
    j["inner_iterations_per_step"] =
        inner_per_step.empty() ? 0.0 : static_cast<double>(oc.iterations) / inner_per_step.size();
    j["resumed_from"] = resumed_from;
    j["solve_time_s"] = solve_s;
    j["seconds_per_step"] = last > first ? solve_s / (last - first) : 0.0;
    j["mesh_time_s"] = read_s;
    j["deformation_setup_s"] = mesh_motion ? mesh_motion->setup_seconds() : 0.0;
    {
        auto median = [](std::vector<double> v) {
            if (v.empty()) return 0.0;
            std::sort(v.begin(), v.end());
            const std::size_t h = v.size() / 2;
            return v.size() % 2 ? v[h] : 0.5 * (v[h - 1] + v[h]);
        };
        j["mesh_motion"] = {
            {"mode", cfg.mesh_motion == meshmotion::BodyMotion::deforming ? "deforming" : "rigid"},
            {"coordinate_calls", motion_wall_s.size()},
            {"median_wall_s", median(motion_wall_s)},
            {"median_cpu_s", median(motion_cpu_s)},
            {"median_step_wall_s", median(step_wall_s)},
            {"median_step_cpu_s", median(step_cpu_s)}};
        if (mesh_motion && cfg.mesh_motion == meshmotion::BodyMotion::deforming) {
            const meshmotion::BodyMotionInfo& b = mesh_motion->body_info();
            j["mesh_motion"]["rigid_radius"] = b.rigid_radius;
            j["mesh_motion"]["fixed_radius"] = b.fixed_radius;
            j["mesh_motion"]["wall_nodes"] = b.n_wall_nodes;
            j["mesh_motion"]["sliding_nodes"] = b.n_sliding_nodes;
            j["mesh_motion"]["blended_nodes"] = b.n_blended_nodes;
            j["mesh_motion"]["checked_cells"] = mesh_motion->n_checked_cells();
            j["mesh_motion"]["memory_bytes"] = mesh_motion->memory_bytes();
        }
    }
    j["wall_time_s"] = seconds_since(t_start);
    j["peak_memory_bytes"] = memory;
    j["motion_fingerprint"] = motion_fingerprint;
    core::write_file_atomic(in.out / "summary.json", j.dump(2) + "\n");
    result.summary = std::move(j);
    return result;
}

CaseResult CfdCase::run(const Progress& progress) {
    Impl& c = *impl_;
    if (c.unsteady) return c.run_unsteady(progress);
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
    if (!c.cfg.companion.empty()) j["companion"] = c.cfg.companion.string();
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
                        setup.reference.moment_point.z()}},
                      {"half_model", setup.reference.half_model}};
    j["deflections_deg"] = {{"elevator", c.deflection[0] / deg},
                            {"aileron", c.deflection[1] / deg},
                            {"rudder", c.deflection[2] / deg}};
    j["rates"] = {{"p_hat", c.rates[0]}, {"q_hat", c.rates[1]}, {"r_hat", c.rates[2]}};
    if (deflects(c.deflection)) {
        // Each control surface's own deflection (gain times its mode's).
        const std::vector<double> delta =
            surface_deflections(c.cfg.control_surfaces, c.deflection, c.deflection_naming);
        nlohmann::json surfaces = nlohmann::json::array();
        for (std::size_t k = 0; k < delta.size(); ++k)
            surfaces.push_back({{"marker", c.cfg.control_surfaces[k].marker},
                                {"mode", c.cfg.control_surfaces[k].mode},
                                {"gain", c.cfg.control_surfaces[k].gain},
                                {"deflection_deg", delta[k] / deg}});
        j["control_surfaces"] = std::move(surfaces);
        j["deflection_time_s"] = c.deflection_s;
    }
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
