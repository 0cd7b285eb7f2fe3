#pragma once
/// @file source.hpp
/// The Euler solver as an `aero::AeroSource` (docs/euler.md#as-an-aero-source): steady
/// evaluations at (alpha, beta, Mach) on one mesh, each started from the nearest converged
/// solution computed before (a warm start), so a table campaign pays the full convergence cost
/// once.
///
/// The mesh axes are taken as x downstream (aft), y toward the right wing, z up; body-axis
/// coefficients are x forward, y right, z down (aero/types.hpp), so CX = -CFx, CZ = -CFz,
/// Cl = -CMx, Cm = CMy, Cn = -CMz. Control deflections deform the mesh by the configuration's
/// control surfaces (meshmotion::MeshMotion::deformed); rotation rates p_hat, q_hat, r_hat solve
/// in the frame turning with the body (rotating_frame.hpp); docs/euler.md, "Control deflections"
/// and "Rotation rates".
///
/// Along a motion (`start_unsteady`, docs/euler.md#as-an-unsteady-source) the source runs the
/// time-accurate solver of `manta cfd --motion` on its own copy of the mesh (unsteady_source.cpp),
/// with the configuration's control surfaces and `unsteady:` settings (the mesh motion rigid or
/// deforming, as `unsteady.mesh_motion` says).

#include <array>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "manta/aero/source.hpp"
#include "manta/euler/solver.hpp"
#include "manta/euler/unsteady.hpp"
#include "manta/mesh/dual.hpp"
#include "manta/mesh/mesh.hpp"
#include "manta/meshmotion/mesh_motion.hpp"

namespace manta::euler {

/// Statistics of the evaluations so far.
struct EulerSourceStats {
    int evaluations = 0;
    int warm_starts = 0;
    int iterations = 0;    ///< summed over the evaluations
    int cold_retries = 0;  ///< warm starts that failed and were solved again from free stream
};

/// How a run along a motion starts (`EulerSource::set_unsteady_start`).
enum class UnsteadyStart {
    /// The steady solution at the motion's first instant (default): the mesh placed and deformed
    /// as at t0, the free stream the reference point's air-relative velocity there.
    steady,
    free_stream,  ///< the uniform free stream, as `manta cfd --motion`
};

class EulerSource final : public aero::AeroSource {
public:
    /// `setup`: roles (one per marker of `mesh`), reference values, numerics and solver
    /// settings; its flow condition is replaced by each query's. `label` names the mesh in the
    /// fingerprint and messages. InputError if the setup does not fit the mesh.
    /// `control_surfaces`: the configuration's `control_surfaces:` (their modes elevator,
    /// aileron and rudder are the query's deflections); `config_label` names the configuration
    /// in messages. InputError from meshmotion::MeshMotion for a surface that does not fit the
    /// mesh.
    EulerSource(mesh::Mesh mesh, CaseSetup setup, std::string label,
                std::vector<meshmotion::ControlSurfaceSpec> control_surfaces = {},
                std::string config_label = "the CFD configuration");
    /// The source of a mesh file and a `manta cfd` configuration file (empty: the defaults),
    /// set up as `manta cfd` sets up a case (case.hpp: `read_case_mesh`, `case_setup`,
    /// `resolve_roles`, and the mesh's companion file where the configuration is silent:
    /// config.hpp `apply_mesh_companion`), labelled with the mesh file's name. InputError,
    /// ConfigError or IoError naming the file.
    [[nodiscard]] static std::unique_ptr<EulerSource> from_files(
        const std::filesystem::path& mesh, const std::filesystem::path& config);

    [[nodiscard]] std::string name() const override { return "euler"; }
    [[nodiscard]] std::string fingerprint() const override { return fingerprint_; }
    /// Converged steady coefficients at q (serial solve). Deflections q.elevator, q.aileron,
    /// q.rudder [rad] deform a copy of the mesh (each control surface by gain times its mode's
    /// deflection); rates p_hat = p b / (2 V), q_hat = q c / (2 V), r_hat = r b / (2 V) (body
    /// axes; b, c: the reference span and chord; about the moment point) solve in the rotating
    /// frame, quasi-steadily. Thread-safe: several evaluations may run at once, each with its own
    /// solver and, when deflected, its own coordinates and metrics; the warm start takes the
    /// nearest converged solution in (alpha, beta, Mach, rates, deflections). InputError for
    /// alpha_dot_hat or beta_dot_hat (they need a time-accurate solution), for a rotation not
    /// about the normal of every symmetry plane (a half model with the plane y = 0 takes q_hat
    /// only: the plane mirrors the flow), for a deflection of a mode no control surface has,
    /// and for a deflection that inverts a dual cell.
    /// ConvergenceError if the solve diverges or stops at its iteration limit short of the
    /// residual drop.
    [[nodiscard]] aero::SourceResult evaluate(
        const aero::AeroQuery<double>& q, const aero::FlowConditions& conditions) const override;

    /// Whether a control surface of the configuration is driven by `mode` ("elevator").
    [[nodiscard]] bool has_control(const std::string& mode) const;
    /// True: `start_unsteady` runs the time-accurate solver.
    [[nodiscard]] bool unsteady() const override { return true; }
    /// The time-accurate run of `manta cfd --motion` along `motion` (serial), started as
    /// `set_unsteady_start` says, with the control surfaces of the constructor. Mach number from
    /// `set_unsteady_settings`' (the configuration's flow.mach) or the motion's `# mach:` (both
    /// given and different: InputError), entry speed from `# v0:` (none: InputError); time step
    /// `settings.dt` when > 0, else the motion's sample spacing, which must divide the motion
    /// (InputError otherwise). Samples on rho airspeed^2 / 2; no profile drag
    /// (`settings.conditions` is not read). The run keeps a reference to this source (for its
    /// warm-start cache): the source must outlive it.
    [[nodiscard]] std::unique_ptr<aero::UnsteadyRun> start_unsteady(
        const aero::Motion& motion, const aero::UnsteadySettings& settings) const override;
    /// The configuration's flow.mach (none: the motion's) and `unsteady:` settings, for
    /// `start_unsteady` (`from_files` sets them; the defaults otherwise).
    void set_unsteady_settings(std::optional<double> mach, const UnsteadySettings& inner) {
        unsteady_mach_ = mach;
        unsteady_inner_ = inner;
    }
    void set_unsteady_start(UnsteadyStart s) { unsteady_start_ = s; }
    /// Progress of an unsteady run's steady start (minutes on an aircraft mesh): called after
    /// each of its iterations with the iteration, the residual's drop below its peak [orders],
    /// the drop it must reach and the wall time since the start's beginning [s].
    using StartProgress =
        std::function<void(int iteration, double drop, double target_drop, double wall_s)>;
    void set_start_progress(StartProgress p) { start_progress_ = std::move(p); }
    /// The configuration's `unsteady.mesh_motion`, `unsteady.rigid_radius` and
    /// `unsteady.fixed_radius` [m] (0: meshmotion::DeformationOptions' defaults), for
    /// `start_unsteady` (`from_files` sets them; rigid otherwise). As `manta cfd --motion`: in the
    /// deforming mode the wall markers move with the body, the far field stays and the symmetry
    /// planes slide (docs/mesh-motion.md, "Deforming body motion").
    void set_unsteady_mesh_motion(meshmotion::BodyMotion body, double rigid_radius = 0.0,
                                  double fixed_radius = 0.0) {
        unsteady_body_ = body;
        unsteady_rigid_radius_ = rigid_radius;
        unsteady_fixed_radius_ = fixed_radius;
    }
    /// Nodes of the mesh.
    [[nodiscard]] mesh::Index n_nodes() const { return mesh_.n_nodes(); }

    [[nodiscard]] EulerSourceStats stats() const;
    /// Converged solutions kept for warm starts (default 16; the oldest is dropped).
    void set_cache_size(std::size_t n) { cache_size_ = n; }

private:
    class Run;  // unsteady_source.cpp
    /// `evaluate`'s end: the outcome's coefficients (ConvergenceError naming the query if it did
    /// not converge), the statistics and the cache updated with `solver`'s state.
    aero::SourceResult finish(const aero::AeroQuery<double>& q, const std::array<double, 3>& rates,
                              const std::array<double, 3>& deflection, const SolveOutcome& oc,
                              const SteadySolver& solver, bool warm) const;
    struct Cached {
        double mach, alpha, beta;
        std::array<double, 3> rates;       ///< p_hat, q_hat, r_hat
        std::array<double, 3> deflection;  ///< elevator, aileron, rudder [rad]
        double peak_log10_residual;  ///< of the run that computed it (the warm start's reference)
        NodeStates U;
    };
    mesh::Mesh mesh_;
    mesh::DualMetrics dual_;
    parallel::SerialHalo halo_;
    parallel::SerialCommunicator comm_;
    CaseSetup setup_;
    std::vector<meshmotion::ControlSurfaceSpec> surfaces_;
    std::unique_ptr<meshmotion::MeshMotion> motion_;  ///< null without control surfaces
    std::string config_label_;
    std::string label_;  ///< the mesh, for messages
    std::string fingerprint_;
    std::optional<double> unsteady_mach_;
    UnsteadySettings unsteady_inner_;
    UnsteadyStart unsteady_start_ = UnsteadyStart::steady;
    meshmotion::BodyMotion unsteady_body_ = meshmotion::BodyMotion::rigid;
    double unsteady_rigid_radius_ = 0.0, unsteady_fixed_radius_ = 0.0;  ///< [m]
    std::size_t cache_size_ = 16;
    StartProgress start_progress_;
    mutable std::mutex mutex_;
    mutable std::vector<Cached> cache_;
    mutable EulerSourceStats stats_;
};

}  // namespace manta::euler
