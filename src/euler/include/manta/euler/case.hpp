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

#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "manta/euler/config.hpp"
#include "manta/euler/solver.hpp"
#include "manta/mesh/mesh.hpp"
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
    /// mesh). Every process throws rank 0's error.
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
