#pragma once
/// @file solver.hpp
/// The steady Euler solver: implicit backward Euler in pseudo-time with local time steps, a
/// ramped and adaptive CFL number, the first-order Jacobian in 5x5 blocks solved by FGMRES with
/// block ILU(0), divergence detection with automatic CFL back-off, convergence to a residual
/// drop and to settled force coefficients, forces and moments on the walls (docs/euler.md).
/// The step itself is `PseudoTimeStep`, with hooks for the dual-time solver's extra terms and
/// a stopping rule of the caller's; `SteadySolver` runs it with none and `steady_stop`.
///
/// One `SteadySolver` works on one partition-local mesh (the whole mesh in a serial run); with
/// several MPI processes every process runs the same iteration on its part, and reductions and
/// halo exchanges go through the communicator and halo of the `Domain`.

#include <array>
#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "manta/core/frames.hpp"
#include "manta/euler/block_matrix.hpp"
#include "manta/euler/gas.hpp"
#include "manta/euler/rotating_frame.hpp"
#include "manta/euler/spatial.hpp"
#include "manta/parallel/communicator.hpp"

namespace manta::euler {

/// Free-stream conditions of a steady case.
struct FlowCondition {
    double mach = 0.5;   ///< free-stream Mach number
    double alpha = 0.0;  ///< angle of attack [rad]
    double beta = 0.0;   ///< sideslip [rad], positive wind from the right
    double gamma = 1.4;  ///< ratio of specific heats
    /// InputError with a one-line message for a non-physical condition (Mach outside
    /// (0, 10], |alpha| or |beta| above 90 deg, gamma outside (1, 2]).
    void validate() const;
};

/// Reference values of the force and moment coefficients.
struct ReferenceValues {
    /// Reference area [m^2]; 0: the wall area projected on the plane normal to z (the lift
    /// direction at zero incidence): the sum of the positive z components of the wall nodes'
    /// dual boundary faces, as SU2 does for REF_AREA = 0.
    double area = 0.0;
    double chord = 1.0;          ///< length of the pitching moment [m]
    double span = 1.0;           ///< length of the rolling and yawing moments [m]
    Vec3 moment_point{0, 0, 0};  ///< moment reference point in the mesh axes [m]
    /// The mesh is the half (y >= 0) of an aircraft symmetric about the plane y = 0, on a
    /// symmetry plane there (`manta mesh --model half`): the coefficients are the whole
    /// aircraft's, the half and its mirror image together. The side force and the rolling and
    /// yawing moments of the two halves cancel (CFy = CY = CMx = CMz = 0); `area` is half the
    /// aircraft's, so the half's lift, drag and pitching moment over q * area are the whole
    /// aircraft's. Needs the moment point on the plane and zero sideslip.
    bool half_model = false;
};

/// Force and moment coefficients on the walls, pressure only (p - p_inf).
struct ForceCoefficients {
    double CL = 0, CD = 0, CY = 0;     ///< wind axes: lift, drag, side force (toward +y)
    double CFx = 0, CFy = 0, CFz = 0;  ///< mesh axes (x downstream, y right, z up)
    double CMx = 0, CMy = 0, CMz = 0;  ///< mesh axes, about the moment point; x and z on the span,
                                       ///< y on the chord
    double area = 0;                   ///< the reference area used [m^2]
    /// Body axes (x forward, y right, z down; Cl roll, Cm pitch, Cn yaw) from the mesh axes.
    [[nodiscard]] double Cl() const { return core::body_from_geometry(Vec3(CMx, CMy, CMz)).x(); }
    [[nodiscard]] double Cm() const { return core::body_from_geometry(Vec3(CMx, CMy, CMz)).y(); }
    [[nodiscard]] double Cn() const { return core::body_from_geometry(Vec3(CMx, CMy, CMz)).z(); }
};

/// Preconditioner of the implicit step's linear solve (block_matrix.hpp).
enum class PreconditionerKind {
    ilu0,  ///< block ILU(0)
    sgs,   ///< block symmetric Gauss-Seidel
};

/// Settings of the pseudo-time iteration.
struct SolverSettings {
    double cfl_initial = 5.0;  ///< CFL number of the first iteration
    double cfl_max = 1e4;      ///< largest CFL number
    double cfl_growth = 1.5;   ///< factor per iteration while the residual falls
    double cfl_cut = 0.5;      ///< factor when the residual grows by more than `cfl_cut_trigger`
    double cfl_cut_trigger = 1.5;
    int max_iterations = 1000;
    double residual_drop = 6.0;  ///< orders of magnitude below the peak density residual
    /// Largest change of CL, CD and CY over the last `coefficient_window` iterations
    /// (absolute) for the coefficients to count as settled.
    double coefficient_tolerance = 1e-5;
    int coefficient_window = 10;
    /// Orders of residual drop after which the limiter is frozen (0: never). Without freezing,
    /// the limiter's switching stalls second-order solutions with shocks a few orders down.
    double freeze_limiter_drop = 3.0;
    /// Iterations without a 0.1-order gain in the density residual after which the limiter is
    /// frozen (0: never).
    int freeze_limiter_stall = 20;
    /// Iterations run first-order before switching to the chosen order.
    int first_order_iterations = 0;
    KrylovOptions linear{10, 10, 0.05};
    /// Preconditioner of the linear solves: block ILU(0) (fewer iterations) or block symmetric
    /// Gauss-Seidel (no factor stored: about 1.4 kB less per node).
    PreconditionerKind preconditioner = PreconditionerKind::sgs;
    /// Blocks of the preconditioner (`solver.preconditioner_blocks`): 0, one per process
    /// (block Jacobi across processes, the default); N >= 1, the N parts of the METIS
    /// partition an N-process run distributes, also on one process, so that 1 and N processes
    /// precondition alike and give the same history to round-off growth (docs/parallel.md).
    /// N needs 1 or N processes.
    int preconditioner_blocks = 0;
    int max_backoffs = 6;  ///< divergence recoveries before giving up
    /// InputError naming the setting for a value out of range.
    void validate() const;
};

/// A complete steady case: conditions, boundary roles, reference values and numerics.
struct CaseSetup {
    FlowCondition flow;
    std::vector<BoundaryKind> roles;  ///< one per mesh marker, in the mesh's marker order
    ReferenceValues reference;
    SpatialOptions spatial;
    SolverSettings solver;
};

/// One iteration's record (the history CSV row).
struct IterationRecord {
    int iteration = 0;
    double wall_s = 0;                       ///< since the start of this run
    std::array<double, 5> log10_residual{};  ///< log10 of the RMS residual per equation
    double cfl = 0;
    int linear_iterations = 0;
    double linear_residual = 0;  ///< relative residual of the linear solve
    /// The largest |R_rho| of a node (the density row of the residual whose RMS is
    /// `log10_residual[0]`) and where that node is (mesh coordinates, at this iteration's
    /// position on a moving mesh): a residual that stalls or grows at one place (a sliver, a
    /// slot, a sharp edge of the geometry) shows there.
    double max_residual = 0;
    std::array<double, 3> max_residual_at{};
    ForceCoefficients forces;
};

/// How a run ended.
struct SolveOutcome {
    bool converged = false;
    std::string reason;        ///< why it stopped, one line
    int iterations = 0;        ///< total, restarts included
    double residual_drop = 0;  ///< orders below the peak at the end
    double wall_s = 0;
    int backoffs = 0;
    ForceCoefficients forces;
};

/// Everything of the iteration besides the solution that decides later iterations: a run resumed
/// from it (with the solution, the back-off state and, when frozen, the limiter; `SteadySolver`)
/// continues exactly as the uninterrupted run would, bit for bit.
struct IterationState {
    int iteration = 0;
    double cfl = 0;
    double peak_log10_residual = -1e300;
    bool limiter_frozen = false;
    /// Lowest density residual (log10) so far; divergence and back-off test against it.
    double best_log10_residual = std::numeric_limits<double>::infinity();
    /// The last iteration's density residual (log10) for the CFL control; NaN: none yet.
    double previous_log10_residual = std::numeric_limits<double>::quiet_NaN();
    double cfl_cap = 0;   ///< current upper bound of the CFL number (solver.cfl_max at the start)
    double cfl_good = 0;  ///< CFL number of the last state saved for back-off
    /// Stall detection of the limiter freeze: the lowest residual of the stall counter and the
    /// iteration it was reached; the iteration of the lowest residual so far.
    double stall_best = std::numeric_limits<double>::infinity();
    int stall_since = 0;
    int cycle_since = 0;
    int backoffs = 0;  ///< CFL back-offs so far
    /// The last `coefficient_window` iterations' CL, CD, CY (oldest first).
    std::vector<std::array<double, 3>> window;
};

/// Extra terms of the pseudo-time system, for dual time stepping: a step drives
///
///   R*(U) = R(U) + D U - S
///
/// to zero instead of R(U), with D a scalar per node (3 V / (2 dt) for the second-order backward
/// difference) and S a 5-vector per node (the older time levels' part). D U enters the residual
/// and D the diagonal of the implicit matrix. Without them a step is the steady solver's, bit
/// for bit.
struct StepTerms {
    /// D, one value per local node (the owned ones are read); empty: none.
    std::span<const double> diagonal;
    /// S, 5 x n_local (the owned columns are read); null: none.
    const NodeStates* source = nullptr;
    /// Solve with the matrix and preconditioner of the last step that assembled them instead of
    /// assembling new ones (a chord iteration: the dual-time solver's `jacobian_interval`). Taken
    /// only while they are current: after a back-off, `update_geometry` or `set_grid_fluxes` the
    /// next step assembles whatever this says.
    bool reuse_matrix = false;
};

/// What a stopping rule sees: the state at the start of a step, before its update.
struct StepStatus {
    int iteration = 0;
    std::array<double, 5> log10_residual{};  ///< log10 RMS of R* per equation
    double drop = 0;           ///< orders of the density residual below its peak (0: first order)
    bool first_order = false;  ///< a first-order start iteration
    bool at_roundoff = false;  ///< density residual at round-off level
    /// CL, CD, CY each within `coefficient_tolerance` over the last `coefficient_window` steps.
    bool settled = false;
    ForceCoefficients forces;  ///< of the state
};

/// A stopping rule's answer.
struct StopDecision {
    bool stop = false;
    bool converged = false;
    std::string reason;  ///< one line, when stopping
};

/// Called once per step, after the residual and before the update.
using StopRule = std::function<StopDecision(const StepStatus&)>;

/// How a step ended.
enum class StepResult {
    updated,     ///< the state was updated and the iteration counter went up
    backed_off,  ///< divergence: the last sound state restored, the CFL number cut, nothing else
    stopped,     ///< the rule stopped it before the update: state and iteration state unchanged
};

/// One step's result.
struct StepOutcome {
    StepResult result = StepResult::updated;
    IterationRecord record;  ///< updated or stopped; wall_s is left 0 (the caller's clock)
    StepStatus status;       ///< updated or stopped
    StopDecision decision;   ///< stopped
};

/// One implicit backward-Euler step in pseudo-time, shared by the steady and the dual-time
/// solvers (docs/euler.md#the-pseudo-time-step): residual (plus `StepTerms`), divergence test and
/// CFL back-off, the stopping rule, limiter freezing, CFL control, the first-order Jacobian
/// (plus the terms' diagonal) solved by FGMRES, and the update scaled for positivity. It owns the
/// spatial operator, the matrix, the preconditioner and the work arrays; the caller owns the
/// state U and the `IterationState`, which hold everything that decides later steps (so a
/// checkpoint of them, the back-off state and the frozen limiter resumes bit for bit).
class PseudoTimeStep {
public:
    /// Validates `setup` (flow, solver, spatial options; the number of roles; a reference area).
    /// InputError when invalid.
    PseudoTimeStep(const Domain& domain, const parallel::Communicator& comm,
                   const CaseSetup& setup);

    /// The iteration state of a fresh start (CFL numbers from the settings).
    [[nodiscard]] IterationState initial_state() const;
    /// Before a run of steps: the limiter frozen or released to match `it.limiter_frozen`, the
    /// CFL cap set if unset.
    void begin(IterationState& it);
    /// One step on U (5 x n_local, ghosts current) with the iteration state `it`. The rule is
    /// asked after the residual; on `stopped` neither U nor `it` change. ConvergenceError after
    /// `max_backoffs` back-offs.
    StepOutcome step(NodeStates& U, IterationState& it, const StopRule& stop,
                     const StepTerms& terms = {});

    /// Moving meshes (spatial.hpp): after Mesh::set_coordinates and mesh::update_dual_metrics of
    /// the domain's mesh and metrics, refresh the operators' cached geometry. The reference area
    /// and the round-off level stay those of the construction.
    void update_geometry();
    /// Moving meshes: the grid fluxes of every dual face for the operators
    /// (`SpatialOperator::set_grid_fluxes`; null: a fixed mesh, bit for bit).
    void set_grid_fluxes(const mesh::DualFaceValues* g,
                         const Eigen::Matrix3Xd* node_velocities = nullptr);

    /// log10 of the RMS density residual of R*(U) = R(U) + D U - S (after strong wall tangency),
    /// as `step` computes it, without a step (U 5 x n_local, ghosts current). Overwrites the
    /// residual that `residual()` returns.
    [[nodiscard]] double log10_density_residual(const NodeStates& U, const StepTerms& terms = {});

    /// Wall forces of U.
    [[nodiscard]] ForceCoefficients forces(const NodeStates& U) const;
    /// The reference area used (the configured one, or the projected wall area).
    [[nodiscard]] double reference_area() const noexcept { return area_; }
    /// Copy the owned values of U onto its ghosts.
    void exchange(NodeStates& U) const;
    /// The last step's residual R* (5 x n_local, owned columns; after strong wall tangency).
    [[nodiscard]] const NodeStates& residual() const noexcept { return R_; }

    /// The state the next back-off returns to (5 per local node).
    [[nodiscard]] const std::vector<float>& backoff_state() const noexcept { return U_good_; }
    /// Replace it (5 values per local node); InputError on a size mismatch.
    void set_backoff_state(std::vector<float> U);
    void set_backoff_state(const NodeStates& U);
    /// The second-order operator's limiter (5 per local node); empty without a limiter.
    [[nodiscard]] std::vector<double> limiter_values() const;
    void set_frozen_limiter(std::span<const double> phi);
    void freeze_limiter(bool frozen) noexcept { op_.freeze_limiter(frozen); }

    [[nodiscard]] const CaseSetup& setup() const noexcept { return setup_; }
    [[nodiscard]] const Vec5& free_stream_primitive() const noexcept { return W_inf_; }
    [[nodiscard]] const Domain& domain() const noexcept { return domain_; }
    [[nodiscard]] const parallel::Communicator& communicator() const noexcept { return comm_; }
    /// Bytes of the step's arrays (operator, matrix, preconditioner, Krylov space, residual,
    /// back-off state, work vectors).
    [[nodiscard]] std::size_t memory_bytes() const noexcept;

private:
    [[nodiscard]] std::array<double, 5> rms_residual() const;
    /// R* of U into R_ and the spectral radii into lambda_ (with `op`).
    void evaluate(SpatialOperator& op, const NodeStates& U, const StepTerms& terms);

    const Domain domain_;
    const parallel::Communicator& comm_;
    CaseSetup setup_;
    Vec5 W_inf_;
    double area_ = 0;
    SpatialOperator op_;
    std::unique_ptr<SpatialOperator> op_first_;  ///< only with first-order start iterations
    NodeStates R_;
    std::vector<float> U_good_;  ///< last state known to be sound, for CFL back-off (a recovery
                                 ///< point: single precision is enough)
    BlockMatrix J_;
    std::unique_ptr<Preconditioner> precond_;
    Fgmres krylov_;
    std::vector<double> lambda_;
    std::vector<double> dU_;
    bool matrix_current_ = false;  ///< J_ and precond_ assembled since the last change of geometry
    std::int64_t n_global_nodes_ = 0;
    double log10_roundoff_ = -300.0;  ///< density residual at round-off level
};

/// The steady solver's stopping rule: converged when the density residual is
/// `residual_drop` orders below its peak (or at round-off level) and the coefficients have
/// settled, outside the first-order start iterations; stopped at `max_iterations`.
[[nodiscard]] StopDecision steady_stop(const SolverSettings& s, const StepStatus& st);

/// The steady solver on one (partition-local) mesh.
class SteadySolver {
public:
    /// Set up the operator, the matrix pattern and the reference area. InputError if `setup`
    /// is invalid or has the wrong number of roles. The solution starts as the free stream.
    SteadySolver(const Domain& domain, const parallel::Communicator& comm, const CaseSetup& setup);

    /// Called after every iteration on every process (progress, history, checkpoints); return
    /// false to stop.
    using Monitor = std::function<bool(const IterationRecord&)>;

    /// Iterate to convergence (or the iteration limit): `PseudoTimeStep` with the rule
    /// `steady_stop` and no extra terms, or, in a rotating frame, the frame's source (evaluated
    /// at the current state every step). ConvergenceError if the iteration diverges after
    /// `max_backoffs` CFL back-offs.
    SolveOutcome solve(const Monitor& monitor = {});

    /// Solve in a frame rotating with the mesh (rotating_frame.hpp, docs/euler.md#rotation-rates):
    /// the grid fluxes of the rotation on every dual face (and the node grid velocities for the
    /// strong tangency targets) given to the operator, and the frame's source added to the
    /// residual explicitly (not in the implicit matrix). A frame with omega = 0 restores the
    /// fixed mesh, bit for bit.
    void set_rotating_frame(const RotatingFrame& frame);
    [[nodiscard]] const RotatingFrame& rotating_frame() const noexcept { return frame_; }

    /// Conservative state of every local node (owned, then ghosts).
    [[nodiscard]] const NodeStates& state() const noexcept { return U_; }
    /// Replace the owned nodes' state (ghosts are exchanged here). InputError on a size mismatch
    /// or a non-physical state (naming the node).
    void set_state(const NodeStates& U);
    /// Start from U (a converged solution nearby) with the residual drop counted from
    /// `peak_log10_residual`, the peak of the run that computed it, so that the warm-started
    /// run converges to the same residual level (`manta cfd --initial`, `EulerSource`).
    void warm_start(const NodeStates& U, double peak_log10_residual);
    /// The iteration state kept in checkpoints. `solve` stops without changing it (a converged
    /// or finished state solved again stops at once with the same outcome), so a checkpoint
    /// taken in the monitor or after `solve` resumes exactly.
    [[nodiscard]] const IterationState& iteration_state() const noexcept { return it_; }
    /// Replace the iteration state; the limiter is frozen or released to match
    /// `s.limiter_frozen` (give the frozen values with `set_frozen_limiter` after this).
    void set_iteration_state(const IterationState& s);
    /// The state the next CFL back-off returns to (conservative, 5 per local node); `set_state`
    /// sets it to the new state.
    [[nodiscard]] const std::vector<float>& backoff_state() const noexcept {
        return step_.backoff_state();
    }
    /// Replace the back-off state (5 values per local node, ghosts included). InputError on a
    /// size mismatch.
    void set_backoff_state(std::vector<float> U) { step_.set_backoff_state(std::move(U)); }
    /// The limiter values of the second-order operator (5 per local node), the frozen ones when
    /// `iteration_state().limiter_frozen`; empty without a limiter.
    [[nodiscard]] std::vector<double> limiter_values() const { return step_.limiter_values(); }
    /// Set the frozen limiter values (5 per local node, ghosts included) after a resume.
    /// InputError on a size mismatch or values outside [0, 1].
    void set_frozen_limiter(std::span<const double> phi) { step_.set_frozen_limiter(phi); }

    /// Wall forces of the current state.
    [[nodiscard]] ForceCoefficients forces() const { return step_.forces(U_); }
    /// Pressure coefficient (p - p_inf) / (rho_inf V_inf^2 / 2) of every local node.
    [[nodiscard]] std::vector<double> pressure_coefficient() const;
    /// Primitive state (rho, u, v, w, p) of every local node, node-major.
    [[nodiscard]] std::vector<double> primitive_state() const;
    /// Local Mach number of every local node.
    [[nodiscard]] std::vector<double> mach_number() const;

    [[nodiscard]] const CaseSetup& setup() const noexcept { return step_.setup(); }
    [[nodiscard]] const Vec5& free_stream_primitive() const noexcept {
        return step_.free_stream_primitive();
    }
    /// The reference area used (the configured one, or the projected wall area).
    [[nodiscard]] double reference_area() const noexcept { return step_.reference_area(); }
    /// Bytes held by the solver's arrays on this process (mesh and metrics not included).
    [[nodiscard]] std::size_t memory_bytes() const noexcept;

private:
    PseudoTimeStep step_;
    NodeStates U_;
    IterationState it_;
    RotatingFrame frame_;
    mesh::DualFaceValues frame_g_;  ///< the rotation's grid fluxes
    Eigen::Matrix3Xd frame_v_;      ///< the rotation's node velocities
    NodeStates frame_S_;            ///< the rotation's source (StepTerms::source)
};

/// InputError unless U has `n_local` columns and positive, finite density and pressure at every
/// owned node (naming the first node that has not).
void check_state(const NodeStates& U, Index n_local, Index n_owned, double gamma);

/// Pressure coefficient, primitive state (node-major) and local Mach number of every column of
/// U (shared by the steady and the dual-time solvers).
[[nodiscard]] std::vector<double> pressure_coefficient(const NodeStates& U, const CaseSetup& s);
[[nodiscard]] std::vector<double> primitive_state(const NodeStates& U, const CaseSetup& s);
[[nodiscard]] std::vector<double> mach_number(const NodeStates& U, const CaseSetup& s);

/// Default role of a marker from its name (case-insensitive): names containing "far", "inlet",
/// "outlet", "inflow" or "outflow" are far field; "sym" symmetry; "wall", "wing", "airfoil",
/// "aerofoil", "body", "fuselage", "tail", "fin", "nacelle", "blade" slip walls. Returns false
/// for any other name (the caller asks for an explicit role).
[[nodiscard]] bool default_role(const std::string& marker, BoundaryKind& role);

/// "farfield", "wall" or "symmetry".
[[nodiscard]] const char* name(BoundaryKind k) noexcept;

}  // namespace manta::euler
