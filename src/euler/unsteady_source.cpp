/// @file unsteady_source.cpp
/// `EulerSource::start_unsteady` (source.hpp, docs/euler.md#as-an-unsteady-source): the
/// time-accurate run of `manta cfd --motion` (case.hpp: `motion_stepping`, `place_mesh_motion`,
/// `motion_sample`) as an aero::UnsteadyRun, serial, on the source's own copy of the mesh, started
/// from the steady solution at the motion's first instant, saved and restored as one binary file.
/// The mesh moves as the configuration's `unsteady.mesh_motion` says (rigid, or deforming with
/// its radii), as in `manta cfd --motion`; the mode is part of the saved run's fingerprint.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

#include "detail/binary_io.hpp"
#include "manta/core/error.hpp"
#include "manta/core/frames.hpp"
#include "manta/core/io.hpp"
#include "manta/euler/case.hpp"
#include "manta/euler/deflection.hpp"
#include "manta/euler/gas.hpp"
#include "manta/euler/source.hpp"
#include "manta/euler/surface_snapshot.hpp"
#include "manta/euler/unsteady.hpp"

namespace manta::euler {

namespace {

constexpr double rad_to_deg = 57.29577951308232;
constexpr char run_magic[9] = "MANTAES1";
constexpr const char* motion_label = "euler source: motion";
constexpr std::array<const char*, 3> mode_names{"elevator", "aileron", "rudder"};
/// The fingerprint's last part: the mesh motion (a saved run of another one is refused by name).
constexpr const char* mesh_motion_key = " | mesh_motion=";

/// "rigid", or "deforming (rigid_radius R m, fixed_radius F m)" (0: the defaults).
std::string mesh_motion_words(const meshmotion::DeformationOptions& o) {
    if (o.body == meshmotion::BodyMotion::rigid) return "rigid";
    auto radius = [](double r) {
        return r > 0.0 ? core::format_exact(r) + " m" : std::string("default");
    };
    return fmt::format("deforming (rigid_radius {}, fixed_radius {})", radius(o.rigid_radius),
                       radius(o.fixed_radius));
}

}  // namespace

namespace detail {
/// What `write_surface_snapshot` finds a run by (the run class itself is private to the source).
class WallSnapshotWriter {
public:
    virtual ~WallSnapshotWriter() = default;
    virtual void write_surface(const std::filesystem::path& file) const = 0;
};
}  // namespace detail

class EulerSource::Run final : public aero::UnsteadyRun, public detail::WallSnapshotWriter {
public:
    Run(const EulerSource& source, const aero::Motion& motion,
        const aero::UnsteadySettings& settings)
        : src_(source), mesh_(source.mesh_), dual_(source.dual_), motion_(motion) {
        // The case's order of set-up (case.cpp, CfdCase::Impl::prepare), so that a run started
        // from the free stream gives `manta cfd --motion`'s coefficients bit for bit.
        const std::optional<double> mach =
            source.unsteady_mach_ ? source.unsteady_mach_ : motion_.metadata.mach;
        if (!mach)
            throw InputError(
                fmt::format("euler source: no Mach number for the motion; give flow.mach in the "
                            "configuration ({}) or '# mach:' in the motion",
                            source.config_label_));
        setup_ = source.setup_;
        setup_.flow.mach = *mach;
        setup_.flow.alpha = 0.0;
        setup_.flow.beta = 0.0;
        setup_.flow.validate();
        st_ = motion_stepping(motion_, motion_label, setup_.flow.mach,
                              settings.dt > 0.0 ? std::optional<double>(settings.dt) : std::nullopt,
                              source.unsteady_inner_, source.surfaces_, "euler source: time step",
                              "the motion");
        // The mesh motion of `manta cfd --motion` (case.cpp): the configuration's
        // unsteady.mesh_motion and radii, the wall markers moving with the body in the deforming
        // mode, the symmetry planes sliding (there, and under control surfaces that touch them).
        const meshmotion::DeformationOptions options =
            motion_deformation(mesh_, setup_.roles, source.unsteady_body_,
                               source.unsteady_rigid_radius_, source.unsteady_fixed_radius_);
        mesh_motion_ = place_mesh_motion(mesh_, motion_, setup_.reference, motion_label,
                                         source.surfaces_, options);
        const Domain domain{&mesh_, &dual_, mesh_.n_nodes(), &halo_};
        solver_ = std::make_unique<UnsteadySolver>(domain, comm_, setup_, st_.time);
        solver_->set_moving_mesh({&mesh_, &dual_, [this](double, long step, Eigen::Matrix3Xd& x) {
                                      mesh_motion_->coordinates_at(step_time(step), x, step);
                                  }});
        start_ = source.unsteady_start_;
        const UnsteadySettings& t = st_.time;
        fingerprint_ = fmt::format(
            "{} | {} | mach={} start={} order={} max_inner={} inner_drop={} window={} tol={}",
            source.fingerprint_, st_.fingerprint, core::format_exact(setup_.flow.mach),
            start_ == UnsteadyStart::steady ? "steady" : "free_stream", t.order, t.max_inner,
            t.inner_drop, t.coefficient_window, t.coefficient_tolerance);
        // Only when set: the saved runs of earlier versions keep their fingerprint.
        if (t.cfl_max > 0.0) fingerprint_ += fmt::format(" cfl_max={}", t.cfl_max);
        if (t.cfl_growth > 0.0) fingerprint_ += fmt::format(" cfl_growth={}", t.cfl_growth);
        if (t.freeze_limiter_inner > 0)
            fingerprint_ += fmt::format(" freeze_limiter_inner={}", t.freeze_limiter_inner);
        mesh_motion_text_ = mesh_motion_words(options);
        fingerprint_ += mesh_motion_key + mesh_motion_text_;
    }

    [[nodiscard]] const aero::UnsteadySample& current() const override {
        start();
        return sample_;
    }
    const aero::UnsteadySample& step() override {
        start();
        if (finished())
            throw InputError(fmt::format(
                "euler source: step {} is past the motion's end ({} steps of {} s to t = {} s)",
                solver_->steps() + 1, st_.n_steps, st_.dt, motion_.t.back()));
        const TimeStepRecord rec = solver_->advance();
        sample_ = sample(solver_->steps(), rec.forces);
        sample_.iterations = rec.inner_iterations;
        sample_.converged = rec.converged;
        return sample_;
    }
    [[nodiscard]] bool finished() const override { return solver_->steps() >= st_.n_steps; }
    [[nodiscard]] int n_steps() const override { return st_.n_steps; }
    [[nodiscard]] double dt() const override { return st_.dt; }

    void save(const std::filesystem::path& file) const override {
        start();
        const TimeLevels l = solver_->time_levels();
        const NodeStates& U = solver_->state();
        detail::BinOut b;
        b.buf.append(run_magic, 8);
        b.put_string(fingerprint_);
        b.put(static_cast<std::int32_t>(l.steps));
        b.put(l.cfl);
        b.put_doubles(U.data(), static_cast<std::size_t>(U.size()));
        b.put_doubles(l.U_prev.data(), static_cast<std::size_t>(l.U_prev.size()));
        b.put_doubles(l.x.data(), static_cast<std::size_t>(l.x.size()));
        b.put_doubles(l.x_prev.data(), static_cast<std::size_t>(l.x_prev.size()));
        b.put_doubles(l.swept_prev.edges.data(), l.swept_prev.edges.size());
        b.put(static_cast<std::uint64_t>(l.swept_prev.boundary.size()));
        for (const auto& v : l.swept_prev.boundary) b.put_doubles(v.data(), v.size());
        const aero::UnsteadySample& s = sample_;
        const double values[13] = {s.t,       s.body.CX, s.body.CY, s.body.CZ, s.body.Cl,
                                   s.body.Cm, s.body.Cn, s.wind.CL, s.wind.CD, s.wind.CY,
                                   s.alpha,   s.beta,    s.airspeed};
        b.put(static_cast<std::int32_t>(s.index));
        b.put_doubles(values, 13);
        core::write_file_atomic(file, b.buf);
    }

    void restore(const std::filesystem::path& file) override {
        const std::string name = file.string();
        const std::string buf = core::read_file(file);
        if (buf.size() < 8 || buf.compare(0, 8, run_magic) != 0)
            throw InputError(fmt::format(
                "{}: not a saved Euler-source run (no {} header); expected a file written by "
                "its save",
                name, std::string(run_magic, 8)));
        detail::BinIn b{buf, 8, name, "saved Euler-source run",
                        "expected a file written by the same source's save"};
        const std::string fp = b.get_string();
        const std::size_t at = fp.rfind(mesh_motion_key);
        const std::size_t here = fingerprint_.rfind(mesh_motion_key);
        if (fp != fingerprint_ && at != std::string::npos &&
            fp.compare(0, at, fingerprint_, 0, here) == 0)
            throw InputError(fmt::format(
                "{}: a run of unsteady.mesh_motion {}; this run's configuration has {}; expected "
                "a saved run of the same mesh motion (or start this one over)",
                name, fp.substr(at + std::string_view(mesh_motion_key).size()), mesh_motion_text_));
        if (fp != fingerprint_)
            throw InputError(fmt::format(
                "{}: a run of another mesh, configuration, motion or time step ({}); this run: "
                "{}",
                name, fp, fingerprint_));
        const Index n = mesh_.n_nodes();
        TimeLevels l;
        l.steps = b.get<std::int32_t>();
        l.cfl = b.get<double>();
        auto sized = [&](std::vector<double> v, Index rows, const char* what, bool may_be_empty) {
            const auto want = static_cast<std::size_t>(rows * n);
            if (v.size() != want && !(may_be_empty && v.empty()))
                throw InputError(
                    fmt::format("{}: {} has {} values; expected {} ({} per node of {})", name, what,
                                v.size(), want, rows, n));
            return v;
        };
        const std::vector<double> U = sized(b.get_doubles(), 5, "the state", false);
        const std::vector<double> U_prev = sized(b.get_doubles(), 5, "U^(n-1)", true);
        const std::vector<double> x = sized(b.get_doubles(), 3, "the coordinates", false);
        const std::vector<double> x_prev =
            sized(b.get_doubles(), 3, "the previous coordinates", true);
        l.U_prev =
            Eigen::Map<const NodeStates>(U_prev.data(), 5, static_cast<Index>(U_prev.size() / 5));
        l.x = Eigen::Map<const Eigen::Matrix3Xd>(x.data(), 3, n);
        l.x_prev = Eigen::Map<const Eigen::Matrix3Xd>(x_prev.data(), 3,
                                                      static_cast<Index>(x_prev.size() / 3));
        l.swept_prev.edges = b.get_doubles();
        const auto nb = b.get<std::uint64_t>();
        if (nb > static_cast<std::uint64_t>(dual_.boundary.size()))
            throw InputError(
                fmt::format("{}: swept volumes of {} boundary markers; the mesh has {}", name, nb,
                            dual_.boundary.size()));
        for (std::uint64_t k = 0; k < nb; ++k) l.swept_prev.boundary.push_back(b.get_doubles());
        const bool swept_empty = l.swept_prev.edges.empty() && l.swept_prev.boundary.empty();
        if (l.steps < 0 || l.steps > st_.n_steps || (l.steps > 0) != (l.x_prev.cols() > 0) ||
            (l.x_prev.cols() > 0 && (swept_empty || !l.swept_prev.fits(dual_))))
            throw InputError(fmt::format(
                "{}: inconsistent saved run (step {} of {}, {} previous levels); expected a file "
                "written by the same source's save",
                name, l.steps, st_.n_steps, l.x_prev.cols() > 0 ? 1 : 0));
        aero::UnsteadySample s;
        s.index = b.get<std::int32_t>();
        const std::vector<double> v = b.get_doubles();
        if (v.size() != 13 || s.index != l.steps || b.pos != buf.size())
            throw InputError(fmt::format(
                "{}: corrupt saved run (the sample of step {} at step {}, {} trailing bytes); "
                "expected a file written by the same source's save",
                name, s.index, l.steps, buf.size() - std::min(buf.size(), b.pos)));
        s.t = v[0];
        s.body = {v[1], v[2], v[3], v[4], v[5], v[6]};
        s.wind = {v[7], v[8], v[9]};
        s.alpha = v[10];
        s.beta = v[11];
        s.airspeed = v[12];
        solver_->restore(Eigen::Map<const NodeStates>(U.data(), 5, n), l);
        sample_ = s;
        started_ = true;
    }

    /// The wall at the current instant (surface_snapshot.hpp): Cp of the state on
    /// rho airspeed^2 / 2 (the solver's is on the entry speed's); the wall's geometry (the
    /// source's mesh at rest) beside it once.
    void write_surface(const std::filesystem::path& file) const override {
        start();
        if (!wall_) wall_ = wall_surface(src_.mesh_, setup_.roles, file.string());
        const std::filesystem::path geometry = file.parent_path() / "wall.csv";
        if (!std::filesystem::exists(geometry))
            write_wall_geometry(geometry, src_.mesh_, *wall_,
                                {{"coordinates", "the mesh at rest (geometry axes) [m]"}});
        const aero::UnsteadySample& s = sample_;
        std::vector<double> cp = pressure_coefficient(solver_->state(), setup_);
        const double q = (st_.v0 / s.airspeed) * (st_.v0 / s.airspeed);
        for (double& c : cp) c *= q;
        const aero::MotionState ms = motion_.at(s.t);
        std::vector<std::pair<std::string, std::string>> header{
            {"wall", "wall.csv"},
            {"t", core::format_exact(s.t)},
            {"step", std::to_string(s.index)},
            {"mach", core::format_exact(setup_.flow.mach)},
            {"airspeed", core::format_exact(s.airspeed)},
            {"alpha", core::format_exact(s.alpha)},
            {"beta", core::format_exact(s.beta)}};
        for (const char* m : mode_names) {
            const int k = motion_.find_mode(m);
            header.emplace_back(
                m, core::format_exact(k >= 0 ? ms.modes[static_cast<std::size_t>(k)] : 0.0));
        }
        header.emplace_back("cp_reference", "rho airspeed^2 / 2");
        write_wall_cp(file, *wall_, cp, header);
    }

private:
    [[nodiscard]] double step_time(long step) const { return motion_.t.front() + step * st_.dt; }

    /// The sample of step k from the solver's coefficients: the case's numbers
    /// (`motion_sample`, on rho v0^2 / 2) turned to rho airspeed^2 / 2, as aero::UnsteadySample
    /// says.
    [[nodiscard]] aero::UnsteadySample sample(int k, const ForceCoefficients& f) const {
        aero::UnsteadySample s = motion_sample(motion_, step_time(k), st_.v0, f, setup_.reference);
        s.index = k;
        const double q = (st_.v0 / s.airspeed) * (st_.v0 / s.airspeed);
        for (double* c : {&s.body.CX, &s.body.CY, &s.body.CZ, &s.body.Cl, &s.body.Cm, &s.body.Cn,
                          &s.wind.CL, &s.wind.CD, &s.wind.CY})
            *c *= q;
        return s;
    }

    /// The start, once (lazily: a run restored from a file never computes it).
    void start() const {
        if (started_) return;
        const int iterations = start_ == UnsteadyStart::steady ? steady_start() : 0;
        sample_ = sample(0, solver_->forces());
        sample_.iterations = iterations;
        started_ = true;
    }

    /// The steady solution at t0 on the mesh as placed and deformed there (set_moving_mesh put
    /// it there), in the frame moving with the reference point: the free stream is the air's
    /// velocity relative to it, (v0, 0, 0) - its velocity in the flow frame (the rotation rates
    /// at t0 are left out). Warm-started from the source's nearest converged steady solution,
    /// turned with the mesh. Then Galilean-shifted back into the flow frame, whose free stream is
    /// the unsteady solver's.
    /// Returns the steady solution's iterations.
    int steady_start() const {
        const double t0 = step_time(0);
        const aero::MotionState ms = motion_.at(t0);
        const meshmotion::RigidPose pose =
            meshmotion::rigid_pose(ms, setup_.reference.moment_point);
        const double mach = setup_.flow.mach, v0 = st_.v0;
        const Eigen::Vector3d rel = Eigen::Vector3d(v0, 0.0, 0.0) - pose.velocity;
        const Eigen::Vector3d d = rel / rel.norm();
        CaseSetup s = setup_;
        s.flow.mach = mach * rel.norm() / v0;
        s.flow.alpha = std::atan2(d.z(), d.x());
        s.flow.beta = std::asin(std::clamp(-d.y(), -1.0, 1.0));
        // A half model takes no sideslip (the replay refuses a trajectory with any,
        // replay::check_euler_setup); what the pose's round-off leaves (1e-26 rad from a
        // longitudinal simulation) is none.
        if (s.reference.half_model && std::abs(s.flow.beta) < 1e-9) s.flow.beta = 0.0;
        s.reference.area = solver_->reference_area();
        const Domain domain{&mesh_, &dual_, mesh_.n_nodes(), &halo_};
        SteadySolver steady(domain, comm_, s);

        // The nearest cached solution to the body's alpha, beta and deflections at t0 with no
        // rates (the source's metric: degrees, Mach / 0.05, rates / 0.01), its momentum turned
        // by the pose's rotation.
        const Eigen::Matrix3d C = core::dcm_body_from_earth(ms.euler);
        const Eigen::Vector3d vb =
            C * Eigen::Vector3d(v0 + ms.velocity[0], ms.velocity[1], ms.velocity[2]);
        const double alpha_b = std::atan2(vb.z(), vb.x()), beta_b = std::asin(vb.y() / vb.norm());
        {
            std::lock_guard lock(src_.mutex_);
            const Cached* best = nullptr;
            double best_d = std::numeric_limits<double>::infinity();
            std::array<double, 3> deflection{};
            for (std::size_t k = 0; k < 3; ++k) {
                const int m = motion_.find_mode(mode_names[k]);
                if (m >= 0) deflection[k] = ms.modes[static_cast<std::size_t>(m)];
            }
            for (const Cached& c : src_.cache_) {
                double dist = std::pow((c.alpha - alpha_b) * rad_to_deg, 2) +
                              std::pow((c.beta - beta_b) * rad_to_deg, 2) +
                              std::pow((c.mach - s.flow.mach) / 0.05, 2);
                for (std::size_t k = 0; k < 3; ++k)
                    dist += std::pow(c.rates[k] / 0.01, 2) +
                            std::pow((c.deflection[k] - deflection[k]) * rad_to_deg, 2);
                if (dist < best_d) {
                    best_d = dist;
                    best = &c;
                }
            }
            if (best) {
                NodeStates U = best->U;
                for (Index i = 0; i < U.cols(); ++i)
                    U.block<3, 1>(1, i) = pose.rotation * U.block<3, 1>(1, i);
                steady.warm_start(U, best->peak_log10_residual);
            }
        }
        SteadySolver::Monitor monitor;
        if (src_.start_progress_) {
            const double target = s.solver.residual_drop;
            double peak = -std::numeric_limits<double>::infinity();
            monitor = [this, target, peak](const IterationRecord& r) mutable {
                peak = std::max(peak, r.log10_residual[0]);
                src_.start_progress_(r.iteration, peak - r.log10_residual[0], target, r.wall_s);
                return true;
            };
        }
        const SolveOutcome oc = steady.solve(monitor);
        if (!oc.converged)
            throw ConvergenceError(fmt::format(
                "euler source: the steady start at t = {} s (M {:g}, alpha {:.4g} deg, beta "
                "{:.4g} deg) did not converge: {}; expected convergence (raise solver."
                "max_iterations or lower solver.residual_drop in the configuration, or start "
                "from the free stream)",
                t0, s.flow.mach, alpha_b * rad_to_deg, beta_b * rad_to_deg, oc.reason));
        // Into the flow frame: velocity + the reference point's (solver units, c_inf).
        NodeStates U = steady.state();
        const Eigen::Vector3d vg = pose.velocity * (mach / v0);
        if (vg.squaredNorm() > 0.0)
            for (Index i = 0; i < U.cols(); ++i) {
                const double rho = U(0, i);
                const Eigen::Vector3d m = U.block<3, 1>(1, i);
                U(4, i) += m.dot(vg) + 0.5 * rho * vg.squaredNorm();
                U.block<3, 1>(1, i) = m + rho * vg;
            }
        solver_->set_state(U);
        return oc.iterations;
    }

    const EulerSource& src_;
    mutable mesh::Mesh mesh_;
    mutable mesh::DualMetrics dual_;
    parallel::SerialHalo halo_;
    parallel::SerialCommunicator comm_;
    aero::Motion motion_;
    CaseSetup setup_;
    MotionStepping st_;
    std::unique_ptr<meshmotion::MeshMotion> mesh_motion_;
    std::unique_ptr<UnsteadySolver> solver_;
    UnsteadyStart start_ = UnsteadyStart::steady;
    std::string fingerprint_;
    std::string mesh_motion_text_;  ///< the mesh motion in words (the fingerprint's last part)
    mutable bool started_ = false;
    mutable aero::UnsteadySample sample_;
    mutable std::optional<WallSurface> wall_;  ///< the wall of the snapshots, once
};

bool write_surface_snapshot(const aero::UnsteadyRun& run, const std::filesystem::path& file) {
    const auto* r = dynamic_cast<const detail::WallSnapshotWriter*>(&run);
    if (!r) return false;
    r->write_surface(file);
    return true;
}

std::unique_ptr<aero::UnsteadyRun> EulerSource::start_unsteady(
    const aero::Motion& motion, const aero::UnsteadySettings& settings) const {
    return std::make_unique<Run>(*this, motion, settings);
}

}  // namespace manta::euler
