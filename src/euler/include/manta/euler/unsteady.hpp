#pragma once
/// @file unsteady.hpp
/// The time-accurate Euler solver by dual time stepping (docs/euler.md#dual-time-stepping,
/// docs/adr/0003-moving-meshes.md item 5) on a fixed mesh: backward differences of first or
/// second order in physical time (the first step always first order), each physical step's
/// implicit equation
///
///   R(U) + V (3 U - 4 U^n + U^(n-1)) / (2 dt) = 0     (BDF2; BDF1: R(U) + V (U - U^n) / dt = 0)
///
/// solved by inner iterations of `PseudoTimeStep` with the extra diagonal D = 3 V / (2 dt) and
/// source S = V (4 U^n - U^(n-1)) / (2 dt), to a residual drop and settled coefficients with a
/// cap on the inner iterations.
///
/// On a moving mesh (`set_moving_mesh`) each step moves the coordinates to t^(n+1), updates the
/// dual metrics and the operators' geometry, and solves the ALE form
///
///   R(U) + (3 V^(n+1) U - 4 V^n U^n + V^(n-1) U^(n-1)) / (2 dt) = 0
///
/// with the grid fluxes g = (3/2 S(n->n+1) - 1/2 S(n-1->n)) / dt of the faces' exact swept
/// volumes S (BDF1: V^(n+1) U - V^n U^n over dt, g = S(n->n+1) / dt), so that the discrete
/// geometric conservation law (3 V^(n+1) - 4 V^n + V^(n-1)) / (2 dt) = sum of g holds to
/// round-off (ADR 0003 item 4, docs/euler.md#dual-time-stepping-on-moving-meshes).
///
/// Time is in the solver's units (gas.hpp): the mesh's length unit divided by the free-stream
/// speed of sound.

#include <Eigen/Core>
#include <functional>

#include "manta/euler/solver.hpp"
#include "manta/mesh/dual.hpp"

namespace manta::euler {

/// Settings of the physical time stepping and of the inner iterations.
struct UnsteadySettings {
    double dt = 0.0;          ///< physical time step (solver units: mesh length unit / c_inf), > 0
    int order = 2;            ///< 1: backward Euler; 2: second-order backward differences
    int max_inner = 50;       ///< cap on the inner iterations of a physical step
    double inner_drop = 3.0;  ///< orders of the density residual below the step's peak
    int coefficient_window = 3;  ///< inner iterations over which CL, CD, CY must have settled
    double coefficient_tolerance = 1e-5;  ///< largest change of CL, CD, CY over the window
    /// Start the inner iterations of a second-order step from U^n + (U^n - U^(n-1)) (linear
    /// extrapolation; U^n where that is not physical) instead of U^n. The residual drop counts
    /// from R*(U^n) either way, so the stopping rule asks for the same residual level.
    bool extrapolate = true;
    /// Assemble the Jacobian and the preconditioner at every k-th inner iteration of a step (the
    /// first included) and reuse them in between; 1: every inner iteration.
    int jacobian_interval = 3;
    /// The inner iterations' largest CFL number and its growth per iteration; 0: the steady
    /// solver's (`solver.cfl_max`, `solver.cfl_growth`). A step's inner iterations correct a
    /// state already near the new one, so they bear larger pseudo-time steps than a steady solve
    /// from the free stream, whose cap a configuration may have lowered for that start.
    double cfl_max = 0.0;
    double cfl_growth = 0.0;
    /// Freeze the limiter after this many inner iterations of each step (the limiter of the
    /// step's last state before then, released again at the next step); 0: the steady solver's
    /// rules (`solver.freeze_limiter_drop`, `solver.freeze_limiter_stall`). On the coarse
    /// Ranger the limiter of hundreds of nodes switched by more than 0.05 at every inner
    /// iteration, and the residual stalled 2-2.7 orders down.
    int freeze_limiter_inner = 0;
    /// InputError naming the setting for a value out of range.
    void validate() const;
};

/// One physical step (a row of the per-step coefficients).
struct TimeStepRecord {
    int step = 0;     ///< 1 for the first step
    double time = 0;  ///< at the end of the step
    int inner_iterations = 0;
    double residual_drop = 0;  ///< orders below the step's peak at the end of its inner iterations
    bool converged = false;    ///< false: the inner iterations stopped at their cap
    int backoffs = 0;          ///< CFL back-offs in the step
    ForceCoefficients forces;  ///< of the new state
    /// Moving mesh: the step's defect of the discrete geometric conservation law,
    /// max_i |c1 V_i^(n+1) + c0 V_i^n + cm V_i^(n-1) - dt sum_faces g| over the largest dual
    /// volume (BDF2 c = 3/2, -2, 1/2; BDF1 1, -1, 0); 0 on a fixed mesh.
    double gcl_defect = 0;
};

/// Coordinates of the local mesh's nodes (3 x n_local, owned then ghosts, the mesh's axes and
/// length unit) at time t (solver units); `step` is the index of the time level (n + 1 for the
/// step from n), for messages. Resize `x` only when its size is wrong.
using CoordinatesAt = std::function<void(double t, long step, Eigen::Matrix3Xd& x)>;

/// The mesh a moving-mesh solver moves: the domain's own mesh and metrics, writable.
struct MovingMesh {
    mesh::Mesh* mesh = nullptr;
    mesh::DualMetrics* dual = nullptr;
    CoordinatesAt coordinates;
};

/// Everything of the time stepping besides U^n that decides later steps: a solver given it back
/// (`restore`) continues as the uninterrupted one, bit for bit (checkpoints).
struct TimeLevels {
    int steps = 0;                    ///< physical steps taken (n)
    double cfl = 0;                   ///< the next step's first CFL number
    NodeStates U_prev;                ///< U^(n-1) (empty before the first step)
    Eigen::Matrix3Xd x;               ///< moving mesh: coordinates at t^n (empty on a fixed mesh)
    Eigen::Matrix3Xd x_prev;          ///< at t^(n-1) (empty before the first step)
    mesh::DualFaceValues swept_prev;  ///< S(n-1 -> n) (empty before the first step)
};

/// The dual-time solver on one (partition-local) mesh.
class UnsteadySolver {
public:
    /// `setup`: as for `SteadySolver` (its solver settings steer the inner iterations: CFL
    /// numbers, linear solver, back-offs, limiter freezing); `time`: the time stepping.
    /// InputError if either is invalid. The state starts as the free stream at time 0.
    UnsteadySolver(const Domain& domain, const parallel::Communicator& comm, const CaseSetup& setup,
                   const UnsteadySettings& time);

    /// Set the state at the current time level (a steady solution, say); the next step is
    /// first order. InputError on a size mismatch or a non-physical state (naming the node).
    void set_state(const NodeStates& U);
    /// Move the mesh along `m.coordinates` from now on: the mesh is placed at the current time
    /// (t = start + steps * dt), its metrics and the operators' geometry updated, and the next
    /// step is first order. InputError unless `m.mesh` and `m.dual` are the domain's and the
    /// callback is set.
    void set_moving_mesh(MovingMesh m);
    [[nodiscard]] bool moving() const noexcept { return static_cast<bool>(moving_.coordinates); }
    /// The time of level 0 (default 0); set before the first step.
    void set_start_time(double t0);
    /// The time levels for a checkpoint, and their restoration (with `set_state(U^n)` first;
    /// restores the mesh to the coordinates at t^n). InputError on sizes that do not fit.
    [[nodiscard]] TimeLevels time_levels() const;
    void restore(const NodeStates& U, const TimeLevels& levels);
    /// Called after every inner iteration; return false to stop the step there.
    using Monitor = std::function<bool(const IterationRecord&)>;
    /// Advance one physical step. ConvergenceError if its inner iterations diverge after
    /// `max_backoffs` back-offs.
    TimeStepRecord advance(const Monitor& inner = {});

    [[nodiscard]] const NodeStates& state() const noexcept { return U_; }
    [[nodiscard]] double time() const noexcept { return t0_ + steps_ * time_settings_.dt; }
    /// The last step's inner residual R* (owned columns).
    [[nodiscard]] const NodeStates& residual() const noexcept { return step_.residual(); }
    /// The second-order operator's limiter (5 per local node, as last evaluated or frozen);
    /// empty without a limiter.
    [[nodiscard]] std::vector<double> limiter_values() const { return step_.limiter_values(); }
    [[nodiscard]] int steps() const noexcept { return steps_; }
    [[nodiscard]] ForceCoefficients forces() const { return step_.forces(U_); }
    [[nodiscard]] const UnsteadySettings& time_settings() const noexcept { return time_settings_; }
    [[nodiscard]] const CaseSetup& setup() const noexcept { return step_.setup(); }
    /// The reference area used (the configured one, or the projected wall area at the start).
    [[nodiscard]] double reference_area() const noexcept { return step_.reference_area(); }

private:
    UnsteadySettings time_settings_;
    PseudoTimeStep step_;
    NodeStates U_;       ///< U^(n+1) during a step, U^n between steps
    NodeStates U_prev_;  ///< U^(n-1) between steps (empty before the first)
    std::vector<double> D_;
    NodeStates S_;
    double cfl_ = 0;  ///< the last step's final CFL number, the next step's first
    double t0_ = 0;
    int steps_ = 0;
    // Moving mesh.
    void place_mesh(const Eigen::Matrix3Xd& x);
    MovingMesh moving_;
    Eigen::Matrix3Xd x_, x_prev_, x_next_;  ///< coordinates at t^n, t^(n-1), t^(n+1)
    std::vector<double> V_, V_prev_;        ///< dual volumes at t^n, t^(n-1)
    mesh::DualFaceValues swept_prev_, swept_, g_;
    Eigen::Matrix3Xd velocities_;  ///< grid velocities of the nodes (the scheme's difference)
};

}  // namespace manta::euler
