/// @file nlp.cpp
/// The IPOPT adapter (the only file that sees IPOPT) and `solve`.

#include <fmt/format.h>
#include <time.h>
#include <coin/IpIpoptApplication.hpp>
#include <coin/IpSolveStatistics.hpp>
#include <coin/IpTNLP.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <limits>
#include <utility>
#include <vector>

#include "detail/multiphase.hpp"
#include "detail/transcription.hpp"
#include "manta/core/error.hpp"
#include "manta/optimal/multiphase.hpp"
#include "manta/optimal/solve.hpp"

namespace manta::optimal {

namespace {

using Ipopt::Index;
using Ipopt::Number;

double process_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

bool all_finite(const double* v, int n) {
    for (int i = 0; i < n; ++i) {
        if (!std::isfinite(v[i])) return false;
    }
    return true;
}

/// IPOPT's view of the transcription. With reference scaling (Variable::ref0, ref) IPOPT's
/// variables are y = (z - ref0) / (ref - ref0) for those variables (IPOPT's own scaling only
/// multiplies, so the offset is applied here), z for the others: z = offset + span y with
/// span 1, offset 0 where there is no reference; derivatives follow by the chain rule.
/// Tr: detail::Transcription (one phase) or detail::MultiTranscription; z0: its starting point.
template <class Tr>
class Nlp final : public Ipopt::TNLP {
public:
    Nlp(Tr& tr, std::vector<double> z0, const SolverOptions& options)
        : tr_(tr), options_(options), z0_(std::move(z0)) {
        tr_.scaling(z0_.data(), var_scale_, row_scale_, obj_scale_);
        gl_.resize(tr.n_rows());
        gu_.resize(tr.n_rows());
        xl_.resize(tr.n_vars());
        xu_.resize(tr.n_vars());
        tr_.bounds(xl_.data(), xu_.data(), gl_.data(), gu_.data());
        g_work_.resize(tr.n_rows());
        affine_ = tr_.reference_scaling(offset_, span_);
        if (affine_) {
            const int n = tr.n_vars();
            for (int c = 0; c < n; ++c) {
                if (span_(c) == 0.0) {
                    span_(c) = 1.0;  // identity: magnitude scaling by IPOPT
                    continue;
                }
                var_scale_(c) = 1.0;  // y is of order 1 already
                auto to_y = [&](double b) {
                    return std::abs(b) >= detail::kNlpInf ? b : (b - offset_(c)) / span_(c);
                };
                double lo = to_y(xl_[c]), hi = to_y(xu_[c]);
                if (span_(c) < 0.0) {
                    lo = xu_[c] >= detail::kNlpInf ? -detail::kNlpInf : to_y(xu_[c]);
                    hi = xl_[c] <= -detail::kNlpInf ? detail::kNlpInf : to_y(xl_[c]);
                }
                xl_[c] = lo;
                xu_[c] = hi;
            }
            y0_.assign(z0_.size(), 0.0);
            for (int c = 0; c < n; ++c) y0_[c] = (z0_[c] - offset_(c)) / span_(c);
            jac_cols_.resize(tr.nnz_jacobian());
            std::vector<int> rows(tr.nnz_jacobian());
            tr_.jacobian_structure(rows.data(), jac_cols_.data());
            hess_rows_.resize(tr.nnz_hessian());
            hess_cols_.resize(tr.nnz_hessian());
            tr_.hessian_structure(hess_rows_.data(), hess_cols_.data());
            z_work_.resize(z0_.size());
        }
    }

    /// The transcription's variables z of IPOPT's x.
    const double* to_z(const double* x) {
        if (!affine_) return x;
        for (std::size_t c = 0; c < z_work_.size(); ++c) z_work_[c] = offset_(c) + span_(c) * x[c];
        return z_work_.data();
    }

    bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag,
                      IndexStyleEnum& index_style) override {
        n = tr_.n_vars();
        m = tr_.n_rows();
        nnz_jac_g = tr_.nnz_jacobian();
        nnz_h_lag = tr_.nnz_hessian();
        index_style = C_STYLE;
        return true;
    }

    bool get_bounds_info(Index n, Number* x_l, Number* x_u, Index m, Number* g_l,
                         Number* g_u) override {
        std::copy(xl_.begin(), xl_.begin() + n, x_l);
        std::copy(xu_.begin(), xu_.begin() + n, x_u);
        std::copy(gl_.begin(), gl_.begin() + m, g_l);
        std::copy(gu_.begin(), gu_.begin() + m, g_u);
        return true;
    }

    bool get_scaling_parameters(Number& obj_scaling, bool& use_x_scaling, Index n,
                                Number* x_scaling, bool& use_g_scaling, Index m,
                                Number* g_scaling) override {
        obj_scaling = 1.0 / obj_scale_;
        use_x_scaling = true;
        use_g_scaling = true;
        for (Index i = 0; i < n; ++i) x_scaling[i] = 1.0 / var_scale_(i);
        for (Index j = 0; j < m; ++j) g_scaling[j] = 1.0 / row_scale_(j);
        return true;
    }

    bool get_starting_point(Index n, bool init_x, Number* x, bool /*init_z*/, Number* /*z_L*/,
                            Number* /*z_U*/, Index /*m*/, bool /*init_lambda*/,
                            Number* /*lambda*/) override {
        if (init_x) {
            const std::vector<double>& start = affine_ ? y0_ : z0_;
            std::copy(start.begin(), start.begin() + n, x);
        }
        return true;
    }

    bool eval_f(Index /*n*/, const Number* x, bool /*new_x*/, Number& obj_value) override {
        return guarded([&] {
            obj_value = tr_.objective(to_z(x));
            return std::isfinite(obj_value);
        });
    }
    bool eval_grad_f(Index n, const Number* x, bool /*new_x*/, Number* grad_f) override {
        return guarded([&] {
            tr_.gradient(to_z(x), grad_f);
            if (affine_) {
                for (Index c = 0; c < n; ++c) grad_f[c] *= span_(c);
            }
            return all_finite(grad_f, n);
        });
    }
    bool eval_g(Index /*n*/, const Number* x, bool /*new_x*/, Index m, Number* g) override {
        return guarded([&] {
            tr_.constraints(to_z(x), g);
            return all_finite(g, m);
        });
    }
    bool eval_jac_g(Index n, const Number* x, bool /*new_x*/, Index /*m*/, Index nele_jac,
                    Index* iRow, Index* jCol, Number* values) override {
        if (values == nullptr) {
            tr_.jacobian_structure(iRow, jCol);
            return true;
        }
        return guarded([&] {
            const double* z = to_z(x);
            tr_.jacobian(z, values);
            if (affine_) {
                for (Index k = 0; k < nele_jac; ++k) values[k] *= span_(jac_cols_[k]);
            }
            // IPOPT evaluates the Jacobian at accepted iterates only: remember the point
            last_x_.assign(z, z + n);
            return all_finite(values, nele_jac);
        });
    }
    bool eval_h(Index /*n*/, const Number* x, bool /*new_x*/, Number obj_factor, Index /*m*/,
                const Number* lambda, bool /*new_lambda*/, Index nele_hess, Index* iRow,
                Index* jCol, Number* values) override {
        if (values == nullptr) {
            tr_.hessian_structure(iRow, jCol);
            return true;
        }
        return guarded([&] {
            tr_.hessian(to_z(x), obj_factor, lambda, values);
            if (affine_) {
                for (Index k = 0; k < nele_hess; ++k)
                    values[k] *= span_(hess_rows_[k]) * span_(hess_cols_[k]);
            }
            return all_finite(values, nele_hess);
        });
    }

    bool intermediate_callback(Ipopt::AlgorithmMode mode, Index iter, Number obj_value,
                               Number inf_pr, Number inf_du, Number mu, Number /*d_norm*/,
                               Number /*regularization_size*/, Number /*alpha_du*/, Number alpha_pr,
                               Index /*ls_trials*/, const Ipopt::IpoptData* /*ip_data*/,
                               Ipopt::IpoptCalculatedQuantities* /*ip_cq*/) override {
        if (error_) return false;
        iterations_ = iter;
        if (!last_x_.empty()) {
            const double v = scaled_violation(last_x_.data());
            const double obj = tr_.objective(last_x_.data());
            if (best_x_.empty() || v < best_violation_ ||
                (v == best_violation_ && obj < best_objective_)) {
                best_x_ = last_x_;
                best_violation_ = v;
                best_objective_ = obj;
            }
        }
        if (options_.progress) {
            IterationInfo info;
            info.iteration = iter;
            info.objective = tr_.maximising() ? -obj_value : obj_value;
            info.infeasibility = inf_pr;
            info.dual_infeasibility = inf_du;
            info.mu = mu;
            info.step = alpha_pr;
            info.restoration = mode == Ipopt::RestorationPhaseMode;
            if (!options_.progress(info)) return false;
        }
        return true;
    }

    void finalize_solution(Ipopt::SolverReturn status, Index n, const Number* x,
                           const Number* /*z_L*/, const Number* /*z_U*/, Index m,
                           const Number* /*g*/, const Number* lambda, Number obj_value,
                           const Ipopt::IpoptData* /*ip_data*/,
                           Ipopt::IpoptCalculatedQuantities* /*ip_cq*/) override {
        solver_return_ = static_cast<int>(status);
        const double* z = to_z(x);
        final_x_.assign(z, z + n);
        final_lambda_.assign(lambda, lambda + m);
        final_objective_ = obj_value;
    }

    /// Largest scaled distance of the constraints from their bounds at z.
    double scaled_violation(const double* z) {
        tr_.constraints(z, g_work_.data());
        double v = 0.0;
        for (int r = 0; r < tr_.n_rows(); ++r) {
            const double a = std::max({gl_[r] - g_work_[r], g_work_[r] - gu_[r], 0.0});
            if (std::isnan(g_work_[r])) return std::numeric_limits<double>::infinity();
            v = std::max(v, a / row_scale_(r));
        }
        return v;
    }

    std::exception_ptr error_;
    std::vector<double> final_x_, final_lambda_, best_x_;
    double final_objective_ = 0.0;
    double best_violation_ = std::numeric_limits<double>::infinity();
    double best_objective_ = 0.0;
    int solver_return_ = 0;
    int iterations_ = 0;

private:
    template <class F>
    bool guarded(F&& f) {
        try {
            return f();
        } catch (...) {
            if (!error_) error_ = std::current_exception();
            return false;
        }
    }

    Tr& tr_;
    const SolverOptions& options_;
    std::vector<double> z0_, xl_, xu_, gl_, gu_, g_work_, last_x_;
    Eigen::VectorXd var_scale_, row_scale_;
    double obj_scale_ = 1.0;
    // reference scaling (see the class comment)
    bool affine_ = false;
    Eigen::VectorXd offset_, span_;
    std::vector<double> y0_, z_work_;
    std::vector<int> jac_cols_, hess_rows_, hess_cols_;
};

std::string status_text(Ipopt::ApplicationReturnStatus s) {
    switch (s) {
        case Ipopt::Solve_Succeeded:
            return "Solve_Succeeded: optimal solution found";
        case Ipopt::Solved_To_Acceptable_Level:
            return "Solved_To_Acceptable_Level: solved to the acceptable (looser) tolerance";
        case Ipopt::Infeasible_Problem_Detected:
            return "Infeasible_Problem_Detected: converged to a point of local infeasibility";
        case Ipopt::Search_Direction_Becomes_Too_Small:
            return "Search_Direction_Becomes_Too_Small";
        case Ipopt::Diverging_Iterates:
            return "Diverging_Iterates: iterates are unbounded";
        case Ipopt::User_Requested_Stop:
            return "User_Requested_Stop: stopped by the caller";
        case Ipopt::Feasible_Point_Found:
            return "Feasible_Point_Found";
        case Ipopt::Maximum_Iterations_Exceeded:
            return "Maximum_Iterations_Exceeded: iteration limit reached";
        case Ipopt::Restoration_Failed:
            return "Restoration_Failed: the feasibility restoration phase failed";
        case Ipopt::Error_In_Step_Computation:
            return "Error_In_Step_Computation";
        case Ipopt::Maximum_CpuTime_Exceeded:
            return "Maximum_CpuTime_Exceeded";
        case Ipopt::Not_Enough_Degrees_Of_Freedom:
            return "Not_Enough_Degrees_Of_Freedom: more equality constraints than variables";
        case Ipopt::Invalid_Problem_Definition:
            return "Invalid_Problem_Definition";
        case Ipopt::Invalid_Option:
            return "Invalid_Option";
        case Ipopt::Invalid_Number_Detected:
            return "Invalid_Number_Detected: NaN or Inf in a function or derivative";
        case Ipopt::Unrecoverable_Exception:
            return "Unrecoverable_Exception";
        case Ipopt::NonIpopt_Exception_Thrown:
            return "NonIpopt_Exception_Thrown";
        case Ipopt::Insufficient_Memory:
            return "Insufficient_Memory";
        case Ipopt::Internal_Error:
            return "Internal_Error";
    }
    return "IPOPT status " + std::to_string(static_cast<int>(s));
}

SolveStatus map_status(Ipopt::ApplicationReturnStatus s) {
    switch (s) {
        case Ipopt::Solve_Succeeded:
            return SolveStatus::solved;
        case Ipopt::Solved_To_Acceptable_Level:
            return SolveStatus::solved_acceptable;
        case Ipopt::Infeasible_Problem_Detected:
            return SolveStatus::infeasible;
        case Ipopt::Maximum_Iterations_Exceeded:
        case Ipopt::Maximum_CpuTime_Exceeded:
            return SolveStatus::iteration_limit;
        case Ipopt::User_Requested_Stop:
            return SolveStatus::stopped;
        default:
            return SolveStatus::failed;
    }
}

/// IPOPT's outcome on one NLP: the point to report (the final iterate, or on failure the least
/// infeasible accepted one, without multipliers) and the status.
struct IpoptRun {
    Ipopt::ApplicationReturnStatus status = Ipopt::Internal_Error;
    int iterations = 0;
    std::vector<double> z, lambda;  // lambda empty: none
};

/// Run IPOPT on the NLP `tr` from z0 with the options (throws the first exception of a
/// callback, InputError for an IPOPT option it rejects).
template <class Tr>
IpoptRun run_ipopt(Tr& tr, std::vector<double> z0, const SolverOptions& options) {
    Ipopt::SmartPtr<Nlp<Tr>> nlp = new Nlp<Tr>(tr, std::move(z0), options);

    Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
    auto opt = app->Options();
    opt->SetIntegerValue("print_level", options.print_level);
    opt->SetStringValue("sb", "yes");
    opt->SetNumericValue("tol", options.tolerance);
    opt->SetNumericValue("constr_viol_tol", options.constraint_tolerance);
    opt->SetIntegerValue("max_iter", options.max_iterations);
    opt->SetNumericValue("max_cpu_time", options.max_cpu_time);
    opt->SetStringValue("hessian_approximation",
                        options.hessian == HessianMode::exact ? "exact" : "limited-memory");
    opt->SetStringValue("nlp_scaling_method",
                        options.automatic_scaling ? "user-scaling" : "gradient-based");
    opt->SetStringValue("linear_solver", options.linear_solver);
    opt->SetStringValue("mu_strategy", options.mu_strategy);
    opt->SetNumericValue("mu_init", options.mu_init);
    for (const auto& [key, value] : options.ipopt_options) {
        bool ok = false;
        char* end = nullptr;
        const long i = std::strtol(value.c_str(), &end, 10);
        if (!value.empty() && *end == '\0') {
            ok = opt->SetIntegerValue(key, static_cast<Ipopt::Index>(i));
        } else {
            const double d = std::strtod(value.c_str(), &end);
            ok = (!value.empty() && *end == '\0') ? opt->SetNumericValue(key, d)
                                                  : opt->SetStringValue(key, value);
        }
        if (!ok) {
            throw InputError("IPOPT option '" + key + "' = '" + value +
                             "' was not accepted; expected an IPOPT option name and a valid value");
        }
    }
    Ipopt::ApplicationReturnStatus st = app->Initialize("");
    if (st != Ipopt::Solve_Succeeded) {
        throw NumericalError("IPOPT could not be initialised: " + status_text(st));
    }
    st = app->OptimizeTNLP(Ipopt::GetRawPtr(nlp));
    if (nlp->error_) std::rethrow_exception(nlp->error_);

    IpoptRun run;
    run.status = st;
    run.iterations =
        Ipopt::IsValid(app->Statistics()) ? app->Statistics()->IterationCount() : nlp->iterations_;
    const bool have_final = static_cast<int>(nlp->final_x_.size()) == tr.n_vars();
    const double* z = have_final ? nlp->final_x_.data() : nullptr;
    const double* lambda = have_final ? nlp->final_lambda_.data() : nullptr;
    const SolveStatus mapped = map_status(st);
    const bool converged =
        mapped == SolveStatus::solved || mapped == SolveStatus::solved_acceptable;
    if (!converged && !nlp->best_x_.empty()) {
        // on failure report the least infeasible accepted iterate
        const double final_v = have_final ? nlp->scaled_violation(z) : kInf;
        if (nlp->best_violation_ < final_v) {
            z = nlp->best_x_.data();
            lambda = nullptr;
        }
    }
    if (z == nullptr) {
        throw NumericalError("IPOPT returned no iterate: " + status_text(st));
    }
    run.z.assign(z, z + tr.n_vars());
    if (lambda != nullptr) run.lambda.assign(lambda, lambda + tr.n_rows());
    return run;
}

}  // namespace

Solution solve(const Model& model, const Mesh& mesh, const Guess& guess,
               const SolverOptions& options) {
    const double cpu0 = process_cpu_seconds();
    const auto wall0 = std::chrono::steady_clock::now();

    if (options.reject_guess_outside_bounds) validate_guess(model.info(), guess);
    detail::Transcription tr(model, mesh);
    std::vector<double> z0(static_cast<std::size_t>(tr.n_vars()));
    tr.initial_point(guess, z0.data());
    const IpoptRun run = run_ipopt(tr, std::move(z0), options);
    const Ipopt::ApplicationReturnStatus st = run.status;

    Solution sol;
    sol.status = map_status(st);
    sol.ipopt_status = static_cast<int>(st);
    sol.status_text = status_text(st);
    sol.iterations = run.iterations;
    sol.n_variables = tr.n_vars();
    sol.n_constraints = tr.n_rows();
    sol.n_jacobian_nonzeros = tr.nnz_jacobian();
    sol.n_hessian_nonzeros = options.hessian == HessianMode::exact ? tr.nnz_hessian() : 0;

    const double* z = run.z.data();
    const double* lambda = run.lambda.empty() ? nullptr : run.lambda.data();
    tr.extract(z, lambda, options.n_reported_violations, sol);
    sol.objective = tr.user_objective(z);
    sol.cpu_time = process_cpu_seconds() - cpu0;
    sol.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    if (options.resimulate) {
        sol.resimulation = resimulate(model, sol, options.resimulation_tolerance);
        const Resimulation& rs = sol.resimulation;
        if (sol.converged() && rs.done && options.resolution_limit > 0.0 &&
            rs.max_scaled_error > options.resolution_limit) {
            sol.status = SolveStatus::solved_unresolved;
            sol.status_text = fmt::format(
                "{}, but not resolved: the re-simulated controls depart from the collocated "
                "states by {:.3g} (scaled, limit {:g}); refine the mesh (more nodes or segments "
                "where the controls jump) and solve again from this solution",
                sol.status_text, rs.max_scaled_error, options.resolution_limit);
        }
    }
    if (!sol.converged() && !options.failure_csv.empty()) write_csv(sol, options.failure_csv);
    return sol;
}

MultiPhaseSolution solve(const MultiPhaseProblem& problem, const SolverOptions& options) {
    const double cpu0 = process_cpu_seconds();
    const auto wall0 = std::chrono::steady_clock::now();

    detail::MultiTranscription tr(problem);
    if (options.reject_guess_outside_bounds) {
        for (const auto& ph : problem.phases) validate_guess(ph.model->info(), ph.guess);
    }
    std::vector<double> z0(static_cast<std::size_t>(tr.n_vars()));
    tr.initial_point(z0.data());
    const IpoptRun run = run_ipopt(tr, std::move(z0), options);

    MultiPhaseSolution sol;
    sol.status = map_status(run.status);
    sol.ipopt_status = static_cast<int>(run.status);
    sol.status_text = status_text(run.status);
    sol.iterations = run.iterations;
    tr.extract(run.z.data(), run.lambda.empty() ? nullptr : run.lambda.data(),
               options.n_reported_violations, sol);
    if (options.hessian != HessianMode::exact) sol.n_hessian_nonzeros = 0;
    sol.objective = tr.user_objective(run.z.data());
    for (auto& ph : sol.phases) {
        ph.status = sol.status;
        ph.ipopt_status = sol.ipopt_status;
        ph.status_text = sol.status_text;
        ph.iterations = sol.iterations;
    }
    sol.cpu_time = process_cpu_seconds() - cpu0;
    sol.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    if (options.resimulate) {
        int worst = -1;
        double worst_error = 0.0;
        for (std::size_t k = 0; k < sol.phases.size(); ++k) {
            Solution& ph = sol.phases[k];
            ph.resimulation =
                resimulate(*problem.phases[k].model, ph, options.resimulation_tolerance);
            if (ph.resimulation.done && ph.resimulation.max_scaled_error > worst_error) {
                worst_error = ph.resimulation.max_scaled_error;
                worst = static_cast<int>(k);
            }
        }
        if (sol.converged() && options.resolution_limit > 0.0 &&
            worst_error > options.resolution_limit) {
            sol.status = SolveStatus::solved_unresolved;
            sol.status_text = fmt::format(
                "{}, but not resolved: in phase {} the re-simulated controls depart from the "
                "collocated states by {:.3g} (scaled, limit {:g}); refine that phase's mesh and "
                "solve again",
                sol.status_text, worst, worst_error, options.resolution_limit);
            for (auto& ph : sol.phases) {
                ph.status = sol.status;
                ph.status_text = sol.status_text;
            }
        }
    }
    if (!sol.converged() && !options.failure_csv.empty()) write_csv(sol, options.failure_csv);
    return sol;
}

}  // namespace manta::optimal
