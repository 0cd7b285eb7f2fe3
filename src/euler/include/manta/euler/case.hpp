#pragma once
/// @file case.hpp
/// The CFD case driver (docs/euler.md#the-case-driver): everything `manta cfd` does besides
/// reading its arguments and printing. It reads the configuration and the mesh, renumbers the
/// nodes, distributes the mesh over the MPI processes, locks the run folder, resumes from the
/// folder's restart file or warm-starts from another run's, solves with a progress callback and
/// atomic checkpoints, and writes history.csv, surface.csv, surface.vtu, flow.vtu, restart.bin
/// and summary.json (docs/formats.md#cfd-run-folder). The parts other drivers share (the set-up
/// from a configuration, the renumbered mesh, the forces as JSON) are free functions here;
/// `EulerSource` is built from them.
///
/// With a motion file (`CaseInputs::motion`) the run is time-accurate instead: the mesh moves
/// along the motion (meshmotion::MeshMotion, with the configuration's control surfaces), the
/// `UnsteadySolver` advances one physical step after the other, and the run folder gets
/// coefficients.csv (one row per step), summary.json, the surface and volume solution every
/// `unsteady.output_every` steps as .pvd time series, and restart_unsteady.bin
/// (docs/formats.md#unsteady-cfd-run-folder).

#include <array>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "manta/aero/motion.hpp"
#include "manta/aero/source.hpp"
#include "manta/euler/config.hpp"
#include "manta/euler/solver.hpp"
#include "manta/euler/unsteady.hpp"
#include "manta/mesh/mesh.hpp"
#include "manta/meshmotion/mesh_motion.hpp"
#include "manta/parallel/communicator.hpp"

namespace manta::euler {

/// What a case is run from: files and overrides of the configuration (`manta cfd`'s options).
struct CaseInputs {
    std::filesystem::path mesh;         ///< mesh file (docs/mesh.md)
    std::filesystem::path config;       ///< configuration file; empty: the defaults
    std::filesystem::path out;          ///< run folder
    std::filesystem::path initial;      ///< start from this restart file (empty: the free stream)
    std::optional<double> mach;         ///< overrides flow.mach
    std::optional<double> alpha;        ///< [rad], overrides flow.alpha_deg
    std::optional<double> beta;         ///< [rad], overrides flow.beta_deg
    std::optional<int> max_iterations;  ///< overrides solver.max_iterations
    std::optional<int> order;           ///< overrides numerics.order
    bool restart = false;               ///< start over, ignoring the run folder's restart file
    /// Steady runs: control deflections [rad] of the modes elevator, aileron and rudder
    /// (deflection.hpp): each control surface of the configuration or the mesh companion turns by
    /// gain times its mode's deflection and the mesh deforms with it before the solve. Not
    /// taken with a motion (its mode columns deflect the surfaces there).
    std::optional<double> elevator, aileron, rudder;
    /// Steady runs: non-dimensional body rates p_hat = p b / (2 V), q_hat = q c / (2 V),
    /// r_hat = r b / (2 V) (body axes, about the reference moment point; override flow.p_hat,
    /// q_hat, r_hat): the steady solution in the frame turning with the body (rotating_frame.hpp,
    /// as `EulerSource::evaluate`). Not taken with a motion.
    std::optional<double> p_hat, q_hat, r_hat;
    /// Motion file (docs/formats.md#motion-file): a time-accurate run along it.
    std::filesystem::path motion;
    std::optional<double> dt;      ///< physical time step [s]; default the motion's spacing
    std::optional<int> max_steps;  ///< stop after this many physical steps in all
};

/// One iteration's progress, for a progress line.
struct CaseProgress {
    int iteration = 0;
    double log10_residual = 0;  ///< density
    double drop = 0;            ///< orders below the peak
    double target = 0;          ///< solver.residual_drop
    double CL = 0, CD = 0, cfl = 0;
    double wall_s = 0;  ///< since the start of the solve
    /// From the recent rate of residual drop; none while unknown or once the target is reached.
    /// Time-accurate runs: from the mean time per physical step of this run.
    std::optional<double> seconds_left;
    /// Time-accurate runs (then `iteration` is the step's inner iterations): the physical step
    /// done, their number, its time and the motion's end [s].
    bool unsteady = false;
    int step = 0, n_steps = 0;
    double time = 0, end_time = 0;
};

/// A finished run.
struct CaseResult {
    SolveOutcome outcome;
    /// summary.json's content on rank 0 (null on the other processes).
    nlohmann::json summary;
};

/// The steady set-up of a configuration: gamma, reference values, numerics, solver settings,
/// and the flow condition where the configuration gives it (alpha and beta default to 0, Mach is
/// left at its default when not given). Roles are not set (`resolve_roles` needs the mesh).
[[nodiscard]] CaseSetup case_setup(const CfdConfig& config);

/// A mesh as the solver uses it: nodes in reverse Cuthill-McKee order, and each node's number in
/// the file.
struct CaseMesh {
    mesh::Mesh mesh;
    std::vector<mesh::Index> file_node;  ///< new -> file numbering
};
/// Read a mesh file (any format of docs/mesh.md) and renumber its nodes. InputError or IoError
/// naming the file.
[[nodiscard]] CaseMesh read_case_mesh(const std::filesystem::path& file);

/// Turn a mesh as the configuration's `mesh.up` says: "y" (a 2-D mesh's slab in the x-y plane)
/// turns it by +90 deg about x, (x, y, z) -> (x, -z, y); "z" leaves it.
void orient_mesh(mesh::Mesh& mesh, const CfdConfig& config);

/// The physical time stepping of a run along a motion (`manta cfd --motion`,
/// `EulerSource::start_unsteady`).
struct MotionStepping {
    double v0 = 0;            ///< the motion's entry speed [m/s] (`# v0:`)
    double dt = 0;            ///< physical time step [s], exactly duration / n_steps
    int n_steps = 0;          ///< steps from the motion's start to its end
    double time_unit = 1;     ///< seconds per solver time unit (1 m / c_inf)
    UnsteadySettings time;    ///< the inner settings with `dt` in solver units, validated
    std::string fingerprint;  ///< of the motion, dt, n_steps and the control surfaces
};
/// The time stepping along `motion` (named `source` in messages) at the flow's Mach number `mach`
/// with the inner settings `inner` (its dt is replaced) and the control surfaces `surfaces`.
/// `dt`: the physical time step [s] (none: the motion's sample spacing, which must then be
/// even); `dt_what` names it in messages ("manta cfd: --dt"), `motion_what` the motion there
/// (empty: "the motion " + source). InputError (one line) when the
/// motion's `# mach:` differs from `mach`, when it has no `# v0:`, when the samples are uneven
/// without `dt`, and when the time step does not divide the motion's duration.
[[nodiscard]] MotionStepping motion_stepping(
    const aero::Motion& motion, const std::string& source, double mach, std::optional<double> dt,
    const UnsteadySettings& inner, const std::vector<meshmotion::ControlSurfaceSpec>& surfaces,
    const std::string& dt_what = "manta cfd: --dt", const std::string& motion_what = {});

/// The mesh's motion along `motion` about the reference values' moment point, with the control
/// surfaces `surfaces` and the deformation `options` (the body's motion rigid or deforming),
/// every sample of the motion checked (meshmotion::MeshMotion::check_motion). InputError (one
/// line) as MeshMotion's constructor and check.
[[nodiscard]] std::unique_ptr<meshmotion::MeshMotion> place_mesh_motion(
    const mesh::Mesh& mesh, const aero::Motion& motion, const ReferenceValues& reference,
    const std::string& source, const std::vector<meshmotion::ControlSurfaceSpec>& surfaces,
    const meshmotion::DeformationOptions& options = {});

/// One instant of a run along a motion: the wall forces `f` (the solver's coefficients, on the
/// free stream's dynamic pressure, mesh-like axes of the flow frame, moments about the fixed
/// point `reference.moment_point`) as body-axis CX CY CZ and Cl Cm Cn about the moving reference
/// point and wind-axis CL CD CY, and alpha, beta and airspeed of the reference point's
/// air-relative velocity at time t. The coefficients stay on rho v0^2 / 2 (coefficients.csv of
/// `manta cfd --motion`); `index` is left 0.
[[nodiscard]] aero::UnsteadySample motion_sample(const aero::Motion& motion, double t, double v0,
                                                 const ForceCoefficients& f,
                                                 const ReferenceValues& reference);

/// The coefficients as summary.json writes them (CL CD CY, CFx CFy CFz, CMx CMy CMz, Cl Cm Cn).
[[nodiscard]] nlohmann::json to_json(const ForceCoefficients& f);

/// A `manta cfd` case on the processes of `comm` (collective: every process constructs it and
/// calls `run`).
class CfdCase {
public:
    /// Read the configuration, take the flow condition (InputError when no Mach number is
    /// given), lock the run folder (rank 0; IoError when another process holds it), read and
    /// renumber the mesh (rank 0), distribute it, set up the solver and resume from the run
    /// folder's restart file (InputError when it belongs to another mesh or flow condition)
    /// unless `restart`, or warm-start from `initial` (InputError when computed on another
    /// mesh). With control deflections (`CaseInputs::elevator`, ...) rank 0 deforms the whole
    /// mesh by the configuration's control surfaces (deflection.hpp; InputError naming the
    /// option and value for a mode no surface has, a value that is not finite, a fold) and
    /// every process takes its nodes' deformed coordinates; the restart file of another
    /// deflection is refused (InputError). With body rates (`CaseInputs::p_hat`, ... or the
    /// configuration's flow.p_hat, ...) the solver turns with the body (rotating_frame.hpp:
    /// `body_rate_frame`, InputError naming the plane and node for a rotation through a symmetry
    /// plane, as EulerSource); the rates are part of the restart fingerprint (a restart file of
    /// other rates is refused, a warm start from one taken). Every process throws rank 0's error.
    CfdCase(CaseInputs inputs, const parallel::Communicator& comm);
    ~CfdCase();
    CfdCase(const CfdCase&) = delete;
    CfdCase& operator=(const CfdCase&) = delete;

    /// Called on rank 0 after every iteration.
    using Progress = std::function<void(const CaseProgress&)>;
    /// Solve (restart.bin and history.csv every `output.checkpoint_interval_s` and at the end),
    /// write the surface and volume outputs and summary.json. ConvergenceError when the
    /// iteration diverges after its back-offs (the last checkpoint stays).
    CaseResult run(const Progress& progress = {});

    [[nodiscard]] const CaseSetup& setup() const noexcept;
    [[nodiscard]] const CfdConfig& config() const noexcept;
    /// The iteration the run resumed from (-1: not resumed).
    [[nodiscard]] int resumed_from() const noexcept;
    /// Steady runs: the control deflections the mesh was deformed by [rad] (elevator, aileron,
    /// rudder; zeros when none).
    [[nodiscard]] const std::array<double, 3>& deflections() const noexcept;
    /// Steady runs: the body rates p_hat, q_hat, r_hat of the rotating frame (zeros when none).
    [[nodiscard]] const BodyRates& rates() const noexcept;
    /// Nodes of the whole mesh.
    [[nodiscard]] std::int64_t n_nodes() const noexcept;
    /// The steady solver (partition-local); a time-accurate case has none (InputError).
    [[nodiscard]] const SteadySolver& solver() const;
    /// Whether the case is time-accurate (a motion was given).
    [[nodiscard]] bool unsteady() const noexcept;
    /// Time-accurate cases: the physical time step [s] and the number of steps.
    [[nodiscard]] double dt() const noexcept;
    [[nodiscard]] int n_steps() const noexcept;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace manta::euler
