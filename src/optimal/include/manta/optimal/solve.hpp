#pragma once
/// @file solve.hpp
/// Legendre–Gauss–Lobatto transcription of a `Model` into a nonlinear program, solved by IPOPT
/// (docs/optimal-control.md): mesh (hp segments), initial guesses, solver options, the
/// solution with costates and interpolation, the a-posteriori re-simulation and the failure
/// report.

#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "manta/optimal/model.hpp"
#include "manta/optimal/problem.hpp"

namespace manta::optimal {

/// The collocation mesh: K segments of [t0, tf], each with its own number of LGL points;
/// adjacent segments share the state at their common point (state continuity), while the
/// controls may jump there.
struct Mesh {
    std::vector<int> nodes;      ///< LGL points per segment (>= 2 each)
    std::vector<double> breaks;  ///< K+1 fractions of [t0, tf]: 0 = b_0 < ... < b_K = 1
    bool free_breaks = false;    ///< interior breaks are decision variables (start at `breaks`)
    double min_segment_fraction = 1e-3;  ///< least segment length (fraction) with free breaks
    /// With free breaks: when not empty, only these interior breaks (indices 1..K-1, increasing)
    /// move freely (the junctions of phases); every other interior break keeps its fraction of
    /// the interval between its neighbouring free breaks or ends, so the segments of a phase
    /// stretch together and none can shrink or grow alone.
    std::vector<int> phase_breaks;

    /// K equal segments of n points each.
    [[nodiscard]] static Mesh uniform(int segments, int nodes_per_segment);
    [[nodiscard]] int n_segments() const { return static_cast<int>(nodes.size()); }
    /// Check sizes and ordering; throws InputError.
    void validate() const;
};

class Solution;

/// A guessed value of a state, control or parameter by name: `start` at t0, `end` at tf
/// (a parameter takes `start`).
struct NamedValue {
    std::string name;  ///< a state, control or parameter of the problem
    double start = 0.0;
    double end = 0.0;
};

/// A starting point for the NLP: state and control time histories, parameters and times.
/// Linear between boundary values, interpolated from a time history (e.g. a simulation), or a
/// previous solution interpolated with its Lagrange polynomials. The guess is stretched
/// linearly onto the problem's [t0, tf] when the two differ.
class Guess {
public:
    /// States and controls varying linearly from (x0, u0) at t0 to (xf, uf) at tf.
    [[nodiscard]] static Guess linear(double t0, double tf, const Eigen::VectorXd& x0,
                                      const Eigen::VectorXd& xf, const Eigen::VectorXd& u0,
                                      const Eigen::VectorXd& uf,
                                      const Eigen::VectorXd& parameters = {});
    /// Linear by name: each listed state, control or parameter from `start` at t0 to `end` at
    /// tf; a state not listed starts (ends) at its initial (final) value where that is fixed,
    /// else at 0 moved into its bounds, and so do controls and parameters (from their bounds).
    /// InputError for an unknown or repeated name, or a value outside the variable's bounds
    /// (naming the variable, the value and the bounds).
    [[nodiscard]] static Guess linear(const ProblemInfo& info, double t0, double tf,
                                      const std::vector<NamedValue>& values);
    /// Piecewise-linear interpolation of samples: `time` strictly increasing (>= 2 samples),
    /// `states` (samples x nx), `controls` (samples x nu).
    [[nodiscard]] static Guess from_history(std::vector<double> time, Eigen::MatrixXd states,
                                            Eigen::MatrixXd controls,
                                            const Eigen::VectorXd& parameters = {});
    /// A previous solution, interpolated with the Lagrange polynomial of each segment.
    [[nodiscard]] static Guess from_solution(const Solution& previous);

    [[nodiscard]] double initial_time() const { return t0_; }
    [[nodiscard]] double final_time() const { return tf_; }
    [[nodiscard]] const Eigen::VectorXd& parameters() const { return p_; }
    /// States and controls of the guess at time t in [initial_time(), final_time()].
    void at(double t, Eigen::VectorXd& x, Eigen::VectorXd& u) const;

private:
    friend void validate_guess(const ProblemInfo& info, const Guess& guess);
    double t0_ = 0.0;
    double tf_ = 1.0;
    Eigen::VectorXd p_;
    std::vector<double> time_;
    Eigen::MatrixXd x_;
    Eigen::MatrixXd u_;
    std::shared_ptr<const Solution> solution_;
};

/// Hessian of the Lagrangian given to IPOPT.
enum class HessianMode {
    exact,          ///< second-order forward AD per node (Newton steps)
    limited_memory  ///< IPOPT's L-BFGS approximation (first derivatives only)
};

/// One IPOPT iteration, for progress display.
struct IterationInfo {
    int iteration = 0;                ///< IPOPT iteration counter
    double objective = 0.0;           ///< unscaled objective
    double infeasibility = 0.0;       ///< IPOPT's primal infeasibility (inf_pr)
    double dual_infeasibility = 0.0;  ///< IPOPT's dual infeasibility (inf_du)
    double mu = 0.0;                  ///< barrier parameter
    double step = 0.0;                ///< primal step length
    bool restoration = false;         ///< in the feasibility-restoration phase
};

/// Options of `solve`.
struct SolverOptions {
    HessianMode hessian = HessianMode::exact;  ///< exact or limited-memory
    double tolerance = 1e-8;                   ///< IPOPT `tol` (scaled NLP error)
    double constraint_tolerance = 1e-8;        ///< IPOPT `constr_viol_tol` (unscaled)
    int max_iterations = 3000;                 ///< IPOPT `max_iter`
    double max_cpu_time = 1e6;                 ///< IPOPT `max_cpu_time` [s]
    int print_level = 0;                   ///< IPOPT console output (0: quiet, 5: IPOPT's default)
    std::string linear_solver = "mumps";   ///< IPOPT `linear_solver`
    std::string mu_strategy = "adaptive";  ///< IPOPT `mu_strategy` (adaptive or monotone)
    double mu_init = 0.1;  ///< IPOPT `mu_init` (initial barrier parameter, monotone strategy)
    /// Further IPOPT options by name, applied last (value parsed as an integer, else a number,
    /// else taken as text), e.g. {"mumps_mem_percent", "100"}. InputError for an unknown option.
    std::vector<std::pair<std::string, std::string>> ipopt_options;
    bool automatic_scaling = true;  ///< scale variables/constraints from bounds and scales
    /// Reject a guess outside the bounds (validate_guess) instead of moving it into them.
    bool reject_guess_outside_bounds = false;
    /// Called once per IPOPT iteration; return false to stop the solver.
    std::function<bool(const IterationInfo&)> progress;
    /// Re-simulate the controls a posteriori (Solution::resimulation).
    bool resimulate = true;
    double resimulation_tolerance = 1e-10;  ///< relative and absolute tolerance of the integrator
    /// A converged solution whose re-simulation departs from it by more than this (the
    /// resimulation's max_scaled_error: |x_sim - x| / scale at some node) is reported as
    /// `solved_unresolved`: the mesh does not resolve the optimum (0 or less: never).
    double resolution_limit = 0.1;
    /// When not empty: on failure the best iterate is written there as CSV.
    std::filesystem::path failure_csv;
    int n_reported_violations = 10;  ///< how many of the most violated constraints to keep
};

/// Outcome of the NLP solver.
enum class SolveStatus {
    solved,             ///< converged to the requested tolerance
    solved_acceptable,  ///< converged to IPOPT's acceptable tolerance
    /// IPOPT converged, but the controls integrated a posteriori depart from the collocated
    /// states by more than `SolverOptions::resolution_limit`: the optimum is not resolved by
    /// the mesh (too few nodes where a control jumps or chatters); refine and solve again from
    /// this solution, or check the model for a control it cannot follow.
    solved_unresolved,
    infeasible,       ///< IPOPT detected (local) infeasibility
    iteration_limit,  ///< max iterations or CPU time reached
    stopped,          ///< stopped by the progress callback
    failed            ///< any other IPOPT failure (restoration failure, NaN, ...)
};

/// A constraint and how far it is from its bounds.
struct Violation {
    std::string name;     ///< "defect h_ft", path or event name, "segment order"
    std::string kind;     ///< "defect", "path", "event", "interior event", "mesh"
    int segment = -1;     ///< segment of a node constraint (-1 for events)
    int node = -1;        ///< node within its segment (-1 for events)
    double time = 0.0;    ///< time of the node (tf for events)
    double value = 0.0;   ///< constraint value
    double lower = 0.0;   ///< lower bound
    double upper = 0.0;   ///< upper bound
    double amount = 0.0;  ///< distance to [lower, upper] (unscaled)
    double scaled = 0.0;  ///< amount divided by the constraint's scale (ranking)
};

/// A-posteriori check: the solution's controls (Lagrange-interpolated, clamped to their bounds)
/// integrated from x(t0) by an adaptive Dormand–Prince method, compared at every node.
struct Resimulation {
    bool done = false;              ///< false when the integration failed
    std::string message;            ///< why it failed, if it did
    double max_scaled_error = 0.0;  ///< max over nodes and states of |x_sim - x| / scale
    Eigen::VectorXd max_abs_error;  ///< per state, max over nodes of |x_sim - x|
    Eigen::VectorXd final_state;    ///< integrated x(tf)
};

/// States, controls and costates on one segment's LGL points.
struct SegmentSolution {
    Eigen::VectorXd tau;       ///< LGL points in [-1, 1]
    Eigen::VectorXd weights;   ///< LGL weights
    Eigen::VectorXd bary;      ///< barycentric weights
    Eigen::VectorXd time;      ///< node times
    Eigen::MatrixXd states;    ///< nodes x nx
    Eigen::MatrixXd controls;  ///< nodes x nu
    Eigen::MatrixXd costates;  ///< nodes x nx, lambda = -(defect multiplier) / weight
    Eigen::MatrixXd path;      ///< nodes x ng, path-constraint values
};

/// Result of `solve`: on success the optimum, on failure the best iterate (least
/// infeasibility) with the report of its most violated constraints.
class Solution {
public:
    ProblemInfo info;  ///< names and bounds of the problem
    SolveStatus status = SolveStatus::failed;
    int ipopt_status = 0;        ///< IPOPT ApplicationReturnStatus / SolverReturn code
    std::string status_text;     ///< IPOPT's status in words
    int iterations = 0;          ///< IPOPT iterations
    double cpu_time = 0.0;       ///< process CPU time of the solve [s]
    double wall_time = 0.0;      ///< wall-clock time of the solve [s]
    double objective = 0.0;      ///< objective value
    double initial_time = 0.0;   ///< t0
    double final_time = 0.0;     ///< tf
    Eigen::VectorXd parameters;  ///< p
    std::vector<double> breaks;  ///< segment boundary times (K+1)
    std::vector<SegmentSolution> segments;
    Eigen::VectorXd integrals;   ///< values of the integral constraints (ProblemInfo::integrals)
    double max_violation = 0.0;  ///< largest unscaled constraint violation
    double max_scaled_violation = 0.0;  ///< largest scaled constraint violation
    std::vector<Violation> violations;  ///< the most violated constraints, worst first
    Resimulation resimulation;          ///< a-posteriori check (when requested)
    int n_variables = 0;                ///< NLP size
    int n_constraints = 0;              ///< NLP constraints
    int n_jacobian_nonzeros = 0;        ///< constraint Jacobian nonzeros
    int n_hessian_nonzeros = 0;         ///< Hessian nonzeros (lower triangle; 0 with L-BFGS)

    /// True when IPOPT converged: solved, solved_acceptable and solved_unresolved (the last is
    /// a converged NLP whose answer the mesh does not resolve: see `resolved`).
    [[nodiscard]] bool converged() const {
        return status == SolveStatus::solved || status == SolveStatus::solved_acceptable ||
               status == SolveStatus::solved_unresolved;
    }
    /// True for solved and solved_acceptable: converged, and the re-simulation (when done)
    /// within the resolution limit.
    [[nodiscard]] bool resolved() const {
        return status == SolveStatus::solved || status == SolveStatus::solved_acceptable;
    }
    /// State at time t by the Lagrange polynomial of the segment holding t.
    [[nodiscard]] Eigen::VectorXd state(double t) const;
    /// Control at time t by the Lagrange polynomial of the segment holding t (right-continuous
    /// at breaks).
    [[nodiscard]] Eigen::VectorXd control(double t) const;
    /// Costate estimate at time t by the Lagrange polynomial of the segment holding t.
    [[nodiscard]] Eigen::VectorXd costate(double t) const;
    /// All nodes in time order (interface points appear once per segment).
    [[nodiscard]] int n_nodes() const;

    // ---- by name (InputError for a name the problem does not have) ---------------------------
    /// State or control of that name at time t (Lagrange polynomial, as state(t)/control(t)).
    [[nodiscard]] double state(double t, std::string_view name) const;
    [[nodiscard]] double control(double t, std::string_view name) const;
    /// x(t0) and x(tf) of the named state.
    [[nodiscard]] double initial_state(std::string_view name) const;
    [[nodiscard]] double final_state(std::string_view name) const;
    /// Static parameter by name.
    [[nodiscard]] double parameter(std::string_view name) const;
    /// Value of the named integral constraint.
    [[nodiscard]] double integral(std::string_view name) const;
    /// Node values of a state or control (the segments' nodes in time order, interface points
    /// once per segment, as `node_times`).
    [[nodiscard]] std::vector<double> history(std::string_view name) const;
    /// Times of all nodes in order (interface points once per segment).
    [[nodiscard]] std::vector<double> node_times() const;

private:
    [[nodiscard]] int segment_of(double t) const;
    [[nodiscard]] Eigen::VectorXd interpolate(double t, int which) const;
};

/// Solve the optimal-control problem of `model` on `mesh` from `guess`. Never throws on
/// solver failure: the returned Solution carries the status, the best iterate and the report.
/// Throws InputError for an inconsistent mesh or guess.
[[nodiscard]] Solution solve(const Model& model, const Mesh& mesh, const Guess& guess,
                             const SolverOptions& options = {});

/// Re-simulate the controls of `solution` (see Resimulation) with the given tolerance.
[[nodiscard]] Resimulation resimulate(const Model& model, const Solution& solution,
                                      double tolerance = 1e-10);

/// Text of the failure report: IPOPT status, the most violated constraints by name (node,
/// time, value, bounds), and where the best iterate was written (`csv`, if not empty).
[[nodiscard]] std::string failure_report(const Solution& solution,
                                         const std::filesystem::path& csv = {});

/// Write the solution as CSV: t, segment, node, states, controls, costates (lambda_<state>),
/// path constraints. Throws IoError.
void write_csv(const Solution& solution, const std::filesystem::path& file);

/// The solution's outcome by name, as text: problem, status, objective (the user's sign; "max"
/// when maximised), t0, tf, parameters, x(t0) and x(tf) of every state, integral constraints.
[[nodiscard]] std::string summary(const Solution& solution);
/// The same as a JSON object: {"problem", "status", "converged", "resolved", "sense",
/// "objective", "initial_time", "final_time", "iterations", "parameters": {name: value},
/// "initial_states": {name: value}, "final_states": {name: value}, "integrals": {name: value},
/// "nodes": {"t": [...], "<state or control>": [...]}}.
[[nodiscard]] std::string to_json(const Solution& solution);

/// Check a guess against the problem's bounds: the states and controls at the guess's samples
/// (its nodes for a previous solution), the parameters, t0 and tf. InputError naming the first
/// variable outside its bounds, the value, the time and the bounds.
void validate_guess(const ProblemInfo& info, const Guess& guess);

/// Largest discrepancies between the NLP's analytic (AD) derivatives and central finite
/// differences at the guess's starting point, perturbed by a seeded random fraction of each
/// variable's scale. Errors are |analytic - fd| / (1 + |fd|) on scaled variables; the dense
/// finite-difference Jacobian is compared with the sparse one everywhere, so a missing sparsity
/// entry shows up as an error.
struct DerivativeCheck {
    double gradient_error = 0.0;  ///< objective gradient
    double jacobian_error = 0.0;  ///< constraint Jacobian (dense comparison)
    double hessian_error = 0.0;   ///< Hessian of the Lagrangian, random multipliers
    int worst_row = -1;           ///< Jacobian row of the largest error
    int worst_col = -1;           ///< Jacobian column of the largest error
    int n_variables = 0;          ///< NLP size
};
/// Check the derivatives of the transcription of `model` on `mesh` (see DerivativeCheck).
[[nodiscard]] DerivativeCheck check_derivatives(const Model& model, const Mesh& mesh,
                                                const Guess& guess, double perturbation = 0.01,
                                                unsigned seed = 1);

/// hp refinement at control discontinuities: from a converged solution, a mesh whose breaks sit
/// where a control jumps by more than `threshold` times its range between neighbouring nodes
/// (at the time the jump crosses its mid value), free breaks. Jumps closer than about one node
/// spacing are merged (a run of them, as a chattering control on a singular arc gives, becomes
/// one break, or two at its ends); a new break within one node spacing of an existing one is
/// dropped. Existing breaks are kept. Never coarser than the solution: each segment gets at
/// least `nodes_per_segment` points and at least the points per unit time of every segment of
/// the solution it overlaps. Re-solve with Guess::from_solution(solution). Error-driven
/// refinement: refine.hpp.
[[nodiscard]] Mesh refine_at_control_jumps(const Solution& solution, int nodes_per_segment,
                                           double threshold = 0.25);

/// Name of a status ("solved", "infeasible", ...).
[[nodiscard]] std::string to_string(SolveStatus status);

}  // namespace manta::optimal
