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
/// cap on the inner iterations. The mesh does not move yet (grid fluxes zero; the moving mesh
/// adds its swept volumes, ADR 0003 item 4).
///
/// Time is in the solver's units (gas.hpp): the mesh's length unit divided by the free-stream
/// speed of sound.

#include <functional>

#include "manta/euler/solver.hpp"

namespace manta::euler {

/// Settings of the physical time stepping and of the inner iterations.
struct UnsteadySettings {
    double dt = 0.0;          ///< physical time step (solver units: mesh length unit / c_inf), > 0
    int order = 2;            ///< 1: backward Euler; 2: second-order backward differences
    int max_inner = 50;       ///< cap on the inner iterations of a physical step
    double inner_drop = 3.0;  ///< orders of the density residual below the step's peak
    int coefficient_window = 3;  ///< inner iterations over which CL, CD, CY must have settled
    double coefficient_tolerance = 1e-6;  ///< largest change of CL, CD, CY over the window
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
    /// Called after every inner iteration; return false to stop the step there.
    using Monitor = std::function<bool(const IterationRecord&)>;
    /// Advance one physical step. ConvergenceError if its inner iterations diverge after
    /// `max_backoffs` back-offs.
    TimeStepRecord advance(const Monitor& inner = {});

    [[nodiscard]] const NodeStates& state() const noexcept { return U_; }
    [[nodiscard]] double time() const noexcept { return time_; }
    [[nodiscard]] int steps() const noexcept { return steps_; }
    [[nodiscard]] ForceCoefficients forces() const { return step_.forces(U_); }
    [[nodiscard]] const UnsteadySettings& time_settings() const noexcept { return time_settings_; }
    [[nodiscard]] const CaseSetup& setup() const noexcept { return step_.setup(); }

private:
    UnsteadySettings time_settings_;
    PseudoTimeStep step_;
    NodeStates U_;       ///< U^(n+1) during a step, U^n between steps
    NodeStates U_prev_;  ///< U^(n-1) between steps (empty before the first)
    std::vector<double> D_;
    NodeStates S_;
    double cfl_ = 0;  ///< the last step's final CFL number, the next step's first
    double time_ = 0;
    int steps_ = 0;
};

}  // namespace manta::euler
