#pragma once
/// @file transcription.hpp
/// Private: the LGL transcription of a Model on a Mesh as an NLP in the form IPOPT takes
/// (variables, bounds, constraints, sparse first and second derivatives, scaling).
///
/// Variables: X (state at each distinct mesh point; adjacent segments share their common
/// point), U (control at each collocation point, per segment), p, t0, tf, free interior breaks.
/// Rows: defects D_k X_k - (h_k/2) f (segment k, node i, state r), path constraints at each
/// collocation point, events, interior events (by junction), the ordering of free breaks, the
/// ties of breaks to phase breaks, integral constraints (the LGL quadrature of the integrands),
/// control rates (2/h_k) D_k U_k at every node of each control with rate bounds, and the
/// continuity of those controls at the breaks.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "manta/optimal/lgl.hpp"
#include "manta/optimal/model.hpp"
#include "manta/optimal/solve.hpp"

namespace manta::optimal::detail {

/// IPOPT's "infinite" bound.
inline constexpr double kNlpInf = 1e20;

class Transcription {
public:
    Transcription(const Model& model, const Mesh& mesh);

    // ---- sizes -------------------------------------------------------------------------------
    [[nodiscard]] int n_vars() const { return n_vars_; }
    [[nodiscard]] int n_rows() const { return n_rows_; }
    [[nodiscard]] int nnz_jacobian() const { return static_cast<int>(jac_row_.size()); }
    [[nodiscard]] int nnz_hessian() const { return static_cast<int>(hess_row_.size()); }
    [[nodiscard]] int n_segments() const { return static_cast<int>(seg_.size()); }
    [[nodiscard]] int n_points() const { return n_points_; }

    // ---- columns of the ends (multi-phase linkage) --------------------------------------------
    [[nodiscard]] const Model& model() const { return model_; }
    [[nodiscard]] int initial_state_col(int r) const { return x_col(0, r); }
    [[nodiscard]] int final_state_col(int r) const { return x_col(n_mesh_points_ - 1, r); }
    [[nodiscard]] int parameter_col(int j) const { return p_col(j); }
    [[nodiscard]] int initial_time_col() const { return t0_col(); }
    [[nodiscard]] int final_time_col() const { return tf_col(); }

    // ---- problem data ------------------------------------------------------------------------
    void bounds(double* x_l, double* x_u, double* g_l, double* g_u) const;
    /// Initial point from a guess (clipped into the bounds).
    void initial_point(const Guess& guess, double* z) const;
    /// Variable scales (typical magnitudes), constraint scales and objective scale.
    void scaling(const double* z0, Eigen::VectorXd& var_scale, Eigen::VectorXd& row_scale,
                 double& obj_scale);
    /// Reference scaling (Variable::ref0, ref): per variable the offset ref0 and the span
    /// ref - ref0 of the affine map z = ref0 + (ref - ref0) y; span 0 where the variable has no
    /// reference (magnitude scaling). False when no variable has one.
    [[nodiscard]] bool reference_scaling(Eigen::VectorXd& offset, Eigen::VectorXd& span) const;
    void jacobian_structure(int* rows, int* cols) const;
    void hessian_structure(int* rows, int* cols) const;

    // ---- evaluation --------------------------------------------------------------------------
    /// The NLP's objective (minimised: the negative of the user's when maximising).
    [[nodiscard]] double objective(const double* z);
    /// True when the problem is maximised (objective() is the negative of the user's).
    [[nodiscard]] bool maximising() const { return sign_ < 0.0; }
    /// The objective with the user's sign.
    [[nodiscard]] double user_objective(const double* z);
    void gradient(const double* z, double* grad);
    void constraints(const double* z, double* g);
    void jacobian(const double* z, double* values);
    void hessian(const double* z, double obj_factor, const double* lambda, double* values);

    // ---- results -----------------------------------------------------------------------------
    /// Fill states, controls, costates, times and the violation report of `sol` from z and the
    /// constraint multipliers (lambda may be null: no costates).
    void extract(const double* z, const double* lambda, int n_report, Solution& sol);

private:
    struct Segment {
        int n = 0;             // LGL points
        int state_offset = 0;  // first mesh point (index into X)
        int point_offset = 0;  // first collocation point (index into U, node caches)
        int defect_row = 0;    // first defect row
        LglRule rule;
        bool seed_lo = false;
        bool seed_hi = false;
        // control rates: time columns (t0, tf, [s_lo], [s_hi]), their Hessian entries (lower,
        // ntv x ntv, -1 above), and per rate-bounded control the entries (U_l, time v)
        std::vector<int> time_cols;
        std::vector<int> time_hess;
        std::vector<std::vector<int>> rate_u_hess;
    };
    /// 2/h of segment k and its derivatives over the segment's time columns (t0, tf, [s_lo],
    /// [s_hi]): g, dg (ntv), d2g (ntv x ntv, full).
    void rate_factor(int k, const double* z, double& g, std::vector<double>& dg,
                     std::vector<double>& d2g) const;

    [[nodiscard]] int x_col(int mesh_point, int r) const { return mesh_point * nx_ + r; }
    [[nodiscard]] int u_col(int point, int j) const { return u0_ + point * nu_ + j; }
    [[nodiscard]] int p_col(int j) const { return p0_ + j; }
    [[nodiscard]] int t0_col() const { return t0_; }
    [[nodiscard]] int tf_col() const { return t0_ + 1; }
    [[nodiscard]] int break_col(int k) const { return b0_ + k - 1; }  // k = 1..K-1
    [[nodiscard]] double break_value(const double* z, int k) const;
    [[nodiscard]] NodePlacement placement(int k, int i, const double* z) const;
    /// Local variable columns of collocation point (k, i).
    [[nodiscard]] std::vector<int> node_columns(int k, int i) const;
    [[nodiscard]] std::vector<int> boundary_columns() const;
    /// Interior variable columns of junction j (the break column is -1 when it is fixed).
    [[nodiscard]] std::vector<int> interior_columns(int j) const;
    /// Interior variable values of junction j (x, p, t0, tf, break fraction).
    void gather_interior(int j, const double* z, std::vector<double>& v) const;
    void gather(const std::vector<int>& cols, const double* z, std::vector<double>& v) const;
    void update(const double* z, bool need_jacobian);
    /// Add the interior events' part of the Hessian of the Lagrangian.
    void interior_hessian(const double* z, const double* lambda, double* values);
    [[nodiscard]] double node_time(int k, int i, const double* z) const;

    const Model& model_;
    Mesh mesh_;
    int nx_ = 0, nu_ = 0, np_ = 0, ng_ = 0, ne_ = 0;
    bool lagrange_ = false, mayer_ = false;
    std::vector<Segment> seg_;
    int n_mesh_points_ = 0;  // distinct state points
    int n_points_ = 0;       // collocation points (sum of segment nodes)
    int u0_ = 0, p0_ = 0, t0_ = 0, b0_ = 0;
    int n_vars_ = 0;
    int path_row_ = 0, event_row_ = 0, interior_row_ = 0, order_row_ = 0, n_rows_ = 0;
    /// A break tied to its neighbouring free breaks a and c (0 and K: the ends, fixed):
    /// b_k = (1 - w) b_a + w b_c (Mesh::phase_breaks).
    struct Tie {
        int k = 0, a = 0, c = 0;
        double w = 0.0;
        int jac_start = 0;
    };
    std::vector<Tie> ties_;
    int tie_row_ = 0;
    int ni_ = 0;  // interior events

    // integral constraints: rows [integral_row_, +nq), each over the union of all node columns
    int nq_ = 0, integral_row_ = 0, integral_out_ = 0, integral_jac_start_ = 0;
    std::vector<int> integral_cols_;              // union of node columns, increasing
    std::vector<std::vector<int>> integral_pos_;  // per point: local column -> position
    // control rates: rows rate_row_ + c * n_points_ + pt for rate-bounded control c
    std::vector<int> rate_controls_;  // control indices with rate bounds
    int rate_row_ = 0;
    std::vector<int> rate_jac_start_;  // per rate row
    // their continuity at breaks: rows continuity_row_ + c * (K - 1) + (k - 1), U_{k-1,last} -
    // U_{k,0}
    int continuity_row_ = 0, continuity_jac_start_ = 0;
    double sign_ = 1.0;  // -1 when maximising

    /// The interior events of one mesh junction.
    struct Junction {
        int index = 0;                 // mesh break index
        int first_row = 0;             // first of its consecutive rows
        int n = 0;                     // events there
        std::vector<int> events;       // indices into ProblemInfo::interior_events
        std::vector<int> cols;         // interior columns (-1: fixed break)
        int jac_start = 0;             // first Jacobian entry (n x used columns)
        std::vector<int> hess_index;   // nv*nv -> entry (-1: upper or unused)
        std::vector<double> out, jac;  // cache (jac over all nv columns)
    };
    std::vector<Junction> junctions_;

    // sparsity
    std::vector<int> jac_row_, jac_col_;
    std::vector<int> defect_jac_start_;  // per defect row: first entry (D part, then node part)
    std::vector<int> path_jac_start_;    // per path row
    int event_jac_start_ = 0;
    int order_jac_start_ = 0;
    std::vector<int> hess_row_, hess_col_;
    std::vector<std::vector<int>> node_hess_index_;  // per point: nv*nv -> entry (-1: upper)
    std::vector<int> boundary_hess_index_;

    // node data
    std::vector<std::vector<int>> node_cols_;
    std::vector<int> boundary_cols_;
    int n_node_out_ = 0, n_boundary_out_ = 0;

    // caches
    std::vector<double> z_cache_;
    bool values_ok_ = false, jacobian_ok_ = false;
    std::vector<std::vector<double>> node_out_, node_jac_;
    std::vector<double> boundary_out_, boundary_jac_;
    std::vector<double> work_v_;

    // scales (for the violation report)
    Eigen::VectorXd row_scale_;
};

}  // namespace manta::optimal::detail
