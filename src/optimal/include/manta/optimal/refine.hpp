#pragma once
/// @file refine.hpp
/// Error-driven ph mesh refinement (docs/optimal-control.md#error-driven-mesh-refinement), after
/// M. A. Patterson, W. W. Hager, A. V. Rao, "A ph mesh refinement method for optimal control",
/// Optimal Control Applications and Methods 36(4), 2015, 398-421 (the method of GPOPS-II),
/// without its coarsening step: the refined mesh never has fewer points per unit time than the
/// mesh it refines.
///
/// Per segment k with N_k LGL points the relative error e_k is estimated on M_k = N_k + 1 (or
/// more) LGL points of the segment: the solution's state and control polynomials are evaluated
/// there, the dynamics at those values are integrated from the segment's first point with the
/// integration matrix of the M_k points, and e_k is the largest difference between the
/// integrated and the interpolated state, over the points and the states, state i divided by
/// 1 + max |x_i| over the segment's points. A segment with e_k > tolerance gets the predicted
/// degree increase P_k = ceil(log(e_k / tolerance) / log(N_k)); when N_k + P_k <= max_nodes its
/// degree is raised to N_k + P_k points, otherwise it is split into
/// B_k = max(ceil((N_k + P_k) / min_nodes), 2) equal segments of min_nodes points (B_k min_nodes >=
/// N_k + P_k > N_k: no coarsening). Interior-event junctions and phase breaks keep their place in
/// time; their indices in the refined mesh are mapped.

#include <string>
#include <vector>

#include "manta/optimal/model.hpp"
#include "manta/optimal/solve.hpp"

namespace manta::optimal {

/// Options of the error-driven refinement (`solve_adaptive`, `refine_mesh`).
struct RefinementOptions {
    double tolerance = 1e-6;     ///< target relative error per segment (see the file comment)
    int min_nodes = 4;           ///< N_min: LGL points of each segment created by a split
    int max_nodes = 12;          ///< N_max: most LGL points a segment reaches by degree increase
    int max_passes = 10;         ///< most solves (the first, on the user's mesh, included)
    int max_total_nodes = 2000;  ///< a refined mesh with more LGL points (sum) is not solved
    int extra_points = 1;  ///< M_k - N_k: error-estimate points beyond the segment's own (>= 1)
    /// Also split a segment where its control jumps (control_jumps), with a free break there,
    /// whatever its error estimate: the error estimate measures how well the collocated states
    /// obey the dynamics, not whether a switch is in the right place (a bang-bang control on
    /// fixed breaks converges to a consistent but late switch). Not in Patterson, Hager & Rao's
    /// method; after the idea of Agamawi, Hager & Rao (AIAA 2020-0378, 2020) of free mesh points
    /// at detected switches. The tolerance is met only when no segment has a jump inside.
    bool breaks_at_jumps = true;
    double jump_threshold = 0.25;  ///< a jump: a step between nodes above this times the range
    /// Throws InputError naming the option for values out of range.
    void validate() const;
};

/// One solve of `solve_adaptive` and the errors of its solution.
struct RefinementPass {
    int pass = 0;                              ///< 1 for the user's mesh
    Mesh mesh;                                 ///< the mesh solved (breaks as given to the solver)
    double max_error = 0.0;                    ///< max over segments of segment_errors
    std::vector<double> segment_errors;        ///< relative error estimate e_k per segment
    int iterations = 0;                        ///< IPOPT iterations of this solve
    double cpu_s = 0.0;                        ///< process CPU time of this solve [s]
    SolveStatus status = SolveStatus::failed;  ///< the solve's status
    double objective = 0.0;                    ///< its objective
    double final_time = 0.0;                   ///< its t_f
    int total_nodes = 0;                       ///< sum of the mesh's LGL points
};

/// Why `solve_adaptive` stopped.
enum class RefinementStatus {
    tolerance_met,  ///< every segment's error estimate at or below the tolerance
    pass_limit,     ///< max_passes solves done, the tolerance not met
    node_limit,     ///< the next mesh would have more than max_total_nodes points
    solve_failed    ///< a solve (and its retry) did not converge; the last converged solution
};
/// Name of a refinement status ("tolerance_met", ...).
[[nodiscard]] std::string to_string(RefinementStatus status);

/// Result of `solve_adaptive`.
struct AdaptiveSolution {
    Solution solution;                   ///< the last converged solution (else the last one)
    Mesh mesh;                           ///< the mesh of `solution`
    std::vector<RefinementPass> passes;  ///< one per solve, in order
    RefinementStatus status = RefinementStatus::solve_failed;
    std::string status_text;  ///< why it stopped, in words
    /// Interior-event junctions of `mesh` in the order of the user's
    /// ProblemInfo::interior_events (the user's indices refer to the first mesh).
    std::vector<int> interior_junctions;
};

/// Fractions of [t0, tf] where a control of `solution` jumps: a step between neighbouring nodes
/// larger than `threshold` times the control's range (its bounds, else its span on the
/// solution), placed where the step crosses its mid value; jumps closer than about one node
/// spacing are merged (a run of them, as a chattering control gives, becomes one break, or two at
/// its ends when it spans more than three spacings). Sorted.
[[nodiscard]] std::vector<double> control_jumps(const Solution& solution, double threshold = 0.25);

/// Relative error estimate of every segment of `solution` (see the file comment), with
/// M_k = N_k + extra_points estimate points (extra_points >= 1). Degenerate segments (zero
/// length) have error 0. Throws InputError for an empty solution or a model of another size.
[[nodiscard]] std::vector<double> segment_errors(const Model& model, const Solution& solution,
                                                 int extra_points = 1);

/// A mesh refined from `solution` (solved on `mesh`) by the ph rule with the given segment
/// errors. Breaks are the solution's (free breaks where the solver moved them); each old
/// segment becomes one segment of more points or several equal ones; with breaks_at_jumps a
/// segment with a control jump inside (more than one node spacing from its ends) is instead cut
/// at its jumps by free breaks, each piece keeping the segment's points per unit time (at least
/// min_nodes). With free breaks the old
/// phase breaks (all old interior breaks when `mesh.phase_breaks` is empty) stay free and the new
/// ones are tied. `old_index` (may be null) receives, per break of the new mesh, the index of the
/// same break in `mesh`, or -1 for a new one.
[[nodiscard]] Mesh refine_mesh(const Solution& solution, const Mesh& mesh,
                               const std::vector<double>& errors, const RefinementOptions& options,
                               std::vector<int>* old_index = nullptr);

/// Solve on `mesh`, estimate the segment errors, refine (refine_mesh) and solve again from the
/// previous solution (Guess::from_solution) until every error is at most the tolerance, or
/// max_passes solves were made, or the next mesh exceeds max_total_nodes, or a solve fails.
/// When the solve on a refined mesh fails, the refinement of the last converged pass is made
/// once more with min_nodes = max_nodes (fewer pieces of higher degree, and so for the rest of
/// the run) and solved (a pass of its own); a second failure in a row stops.
/// Interior events stay at their junctions: the model is wrapped so that the problem's
/// `interior(j, ...)` still receives the junction index of the first mesh. Throws InputError
/// for bad options, mesh or guess.
[[nodiscard]] AdaptiveSolution solve_adaptive(const Model& model, const Mesh& mesh,
                                              const Guess& guess,
                                              const SolverOptions& solver_options = {},
                                              const RefinementOptions& refinement_options = {});

/// The passes as a table: pass, segments, LGL points, points per segment, max error, IPOPT
/// iterations, CPU, status, objective; then the stop reason.
[[nodiscard]] std::string refinement_report(const AdaptiveSolution& result);

/// Integration matrix of the N-point LGL rule: (I f)_j is the integral from -1 to tau_j of the
/// polynomial of degree N - 1 through (tau_l, f_l). Throws InputError for N < 2.
[[nodiscard]] Eigen::MatrixXd lgl_integration_matrix(int n_points);

}  // namespace manta::optimal
