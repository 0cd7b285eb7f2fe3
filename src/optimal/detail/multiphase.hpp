#pragma once
/// @file multiphase.hpp
/// Private: the NLP of a multi-phase problem. Variables: those of each phase's Transcription,
/// phase after phase. Rows: each phase's rows, phase after phase, then per link (phase a to b):
/// the time row t0_b - tf_a (when time_continuity and not both fixed), the linkage rows
/// (continuity: of the states not fixed on both sides) l(x_a(tf_a), x_b(t0_b), p [, times]),
/// and on the first link into a phase b >= 1 its parameter rows p^b - p^0; then the parameter
/// rows of the phases no link enters. The objective is the phases' objectives plus the
/// cross-phase Mayer term. The Hessian is the phases' blocks side by side plus the linkage
/// functions' and the cross-phase Mayer term's entries (added to an entry that exists at the
/// same position).

#include <Eigen/Core>
#include <memory>
#include <utility>
#include <vector>

#include "manta/optimal/multiphase.hpp"
#include "transcription.hpp"

namespace manta::optimal::detail {

class MultiTranscription {
public:
    explicit MultiTranscription(const MultiPhaseProblem& problem);

    [[nodiscard]] int n_vars() const { return n_vars_; }
    [[nodiscard]] int n_rows() const { return n_rows_; }
    [[nodiscard]] int nnz_jacobian() const { return static_cast<int>(jac_row_.size()); }
    [[nodiscard]] int nnz_hessian() const { return static_cast<int>(hess_row_.size()); }

    void bounds(double* x_l, double* x_u, double* g_l, double* g_u) const;
    /// Initial point from the phases' guesses (each clipped into its phase's bounds).
    void initial_point(double* z) const;
    void scaling(const double* z0, Eigen::VectorXd& var_scale, Eigen::VectorXd& row_scale,
                 double& obj_scale);
    [[nodiscard]] bool reference_scaling(Eigen::VectorXd& offset, Eigen::VectorXd& span) const;
    void jacobian_structure(int* rows, int* cols) const;
    void hessian_structure(int* rows, int* cols) const;

    [[nodiscard]] double objective(const double* z);
    [[nodiscard]] bool maximising() const { return maximise_; }
    [[nodiscard]] double user_objective(const double* z);
    void gradient(const double* z, double* grad);
    void constraints(const double* z, double* g);
    void jacobian(const double* z, double* values);
    void hessian(const double* z, double obj_factor, const double* lambda, double* values);

    /// Fill the phases' solutions, the link values and the violations (status, iterations and
    /// times are the caller's).
    void extract(const double* z, const double* lambda, int n_report, MultiPhaseSolution& sol);

private:
    struct LinkRows {
        int from = 0;                         // phase a
        int to = 1;                           // phase b
        int time_row = -1;                    // t0_b - tf_a (-1: none)
        int first_row = 0;                    // linkage rows
        int n = 0;                            // their number
        int param_row = -1;                   // p^b - p^0 (np rows; -1: none)
        std::shared_ptr<const LinkModel> fn;  // null: continuity
        std::vector<int> states;  // continuity: the states with a row (not fixed on both sides)
        // x_f^a, x_0^b, p^0 (global), then t0_a, tf_a, t0_b, tf_b when fn->uses_times()
        std::vector<int> cols;
        int jac_start = 0;            // linkage rows' entries: n x cols (function) or 2 per row
        std::vector<int> hess_index;  // cols x cols (lower) -> entry, function links only
        std::vector<Constraint> constraints;  // names and bounds of the linkage rows
    };
    void link_values(const LinkRows& L, const double* z, std::vector<double>& out,
                     std::vector<double>* jac) const;
    /// The cross-phase Mayer term, the user's sign (0 without one).
    [[nodiscard]] double mayer_value(const double* z) const;

    const MultiPhaseProblem& problem_;
    std::vector<std::unique_ptr<Transcription>> tr_;
    std::vector<int> var_off_, row_off_, jac_off_, hess_off_;
    std::vector<LinkRows> links_;
    std::vector<std::pair<int, int>> untied_;  // (phase, first row): ties of phases no link enters
    int untied_jac_start_ = 0;                 // their Jacobian entries (2 per row)
    std::shared_ptr<const CrossPhaseMayer> mayer_;
    double mayer_sign_ = 1.0;            // -1 when maximised
    std::vector<int> mayer_cols_;        // per listed phase x0, xf, t0, tf; then p^0 (global)
    std::vector<int> mayer_n_states_;    // states of each listed phase
    std::vector<int> mayer_hess_index_;  // cols x cols (lower) -> entry
    int np_ = 0;
    int n_vars_ = 0, n_rows_ = 0;
    bool maximise_ = false;
    std::vector<int> jac_row_, jac_col_, hess_row_, hess_col_;
    Eigen::VectorXd row_scale_;
    mutable std::vector<double> work_;
};

}  // namespace manta::optimal::detail
