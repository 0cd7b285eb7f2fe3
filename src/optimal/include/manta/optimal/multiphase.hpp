#pragma once
/// @file multiphase.hpp
/// Multi-phase optimal control (docs/optimal-control.md, "Multiple phases"): N phases, each a
/// single-phase problem of its own (a `Model`: dynamics, path constraints, bounds, events, Mayer
/// and Lagrange cost, its own free or fixed t0 and tf) on a mesh of its own, joined by links,
/// each from the end of a phase a to the start of a phase b != a (by default phase k to k + 1):
///
///     minimise (or maximise)  Σ_k [ Φ_k(x_k(t0_k), x_k(tf_k), p, t0_k, tf_k) + ∫ L_k dt ]
///                             + Ψ(x_i(t0_i), x_i(tf_i), t0_i, tf_i for the listed phases i, p)
///     subject to  every phase's own constraints (problem.hpp),
///                 t0_b = tf_a                                    (time continuity, default)
///                 l_lo <= l(x_a(tf_a), x_b(t0_b), p [, t0_a, tf_a, t0_b, tf_b]) <= l_hi
///
/// with, by default, l = x_b(t0_b) - x_a(tf_a) = 0 (state continuity; the phases must then have
/// as many states, paired by index). A linkage function may jump states (a stage's mass
/// dropped, a velocity kick), join phases with different numbers of states and controls, and
/// see the four end times of its two phases. Several links may leave one phase (branching).
/// Ψ (`MultiPhaseProblem::mayer`, optional) is a Mayer term of several phases' ends.
/// The static parameters p are shared: every phase declares the same parameters (names in the
/// same order); the NLP keeps one copy per phase tied by equality rows, so each phase's model is
/// evaluated as it is alone. The NLP is the phases' transcriptions side by side (LGL, IPOPT,
/// exact sparse first and second derivatives) plus the linkage rows.

#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "manta/core/error.hpp"
#include "manta/optimal/ad.hpp"
#include "manta/optimal/hyper.hpp"
#include "manta/optimal/model.hpp"
#include "manta/optimal/problem.hpp"
#include "manta/optimal/solve.hpp"

namespace manta::optimal {

/// A linkage function l(x_f, x_0, p) or l(x_f, x_0, p, t) between the end of a phase a (x_f: its
/// final state, of n_from() states) and the start of a phase b (x_0, n_to() states), with its
/// constraints' names and bounds. Variables, in order: x_f, x_0, p, then when uses_times() the
/// four end times t = (t0_a, tf_a, t0_b, tf_b); outputs: one per constraint.
class LinkModel {
public:
    virtual ~LinkModel() = default;
    [[nodiscard]] virtual const std::vector<Constraint>& constraints() const = 0;
    /// Number of states of the phase that ends (x_f) and of the phase that starts (x_0).
    [[nodiscard]] virtual int n_from() const = 0;
    [[nodiscard]] virtual int n_to() const = 0;
    /// True when l is linear (its Hessian is zero and is not evaluated).
    [[nodiscard]] virtual bool linear() const { return false; }
    /// True when l takes the end times (t0_a, tf_a, t0_b, tf_b) after the parameters.
    [[nodiscard]] virtual bool uses_times() const { return false; }
    virtual void values(std::span<const double> v, std::span<double> out) const = 0;
    /// Outputs and their Jacobian (row-major, n_out x v.size()).
    virtual void jacobian(std::span<const double> v, std::span<double> out,
                          std::span<double> jac) const = 0;
    /// Hessian (full, symmetric) of sum_k weight_k out_k.
    virtual void hessian(std::span<const double> v, std::span<const double> weights,
                         std::span<double> hess) const = 0;
};

/// A LinkModel of a function object F with
///
///     template <class T> void operator()(std::span<const T> xf, std::span<const T> x0,
///                                        std::span<const T> p, std::span<T> l) const;
///
/// or, to see the times, with a span t = (t0_a, tf_a, t0_b, tf_b) before the outputs:
///
///     template <class T> void operator()(std::span<const T> xf, std::span<const T> x0,
///                                        std::span<const T> p, std::span<const T> t,
///                                        std::span<T> l) const;
///
/// (a generic lambda taking `auto` arguments will do), differentiated by forward AD
/// (run-time-sized scalars: links are few).
template <class F>
class LinkFunction final : public LinkModel {
public:
    /// True when F takes the times (five arguments).
    static constexpr bool kTimed =
        std::is_invocable_v<const F&, std::span<const double>, std::span<const double>,
                            std::span<const double>, std::span<const double>, std::span<double>>;
    static_assert(
        kTimed || std::is_invocable_v<const F&, std::span<const double>, std::span<const double>,
                                      std::span<const double>, std::span<double>>,
        "a linkage function takes (xf, x0, p, l) or (xf, x0, p, t, l)");

    LinkFunction(int n_from, int n_to, std::vector<Constraint> constraints, F f)
        : f_(std::move(f)), c_(std::move(constraints)), n_from_(n_from), n_to_(n_to) {}
    [[nodiscard]] const std::vector<Constraint>& constraints() const override { return c_; }
    [[nodiscard]] int n_from() const override { return n_from_; }
    [[nodiscard]] int n_to() const override { return n_to_; }
    [[nodiscard]] bool uses_times() const override { return kTimed; }
    void values(std::span<const double> v, std::span<double> out) const override {
        eval<double>(v, out);
    }
    void jacobian(std::span<const double> v, std::span<double> out,
                  std::span<double> jac) const override {
        const int n = static_cast<int>(v.size());
        std::vector<AdDyn1> a;
        a.reserve(v.size());
        for (int i = 0; i < n; ++i) a.push_back(AdDyn1::variable(v[i], n, i));
        std::vector<AdDyn1> o(out.size());
        eval<AdDyn1>(std::span<const AdDyn1>(a), std::span<AdDyn1>(o));
        for (std::size_t r = 0; r < o.size(); ++r) {
            out[r] = o[r].value();
            for (int c = 0; c < n; ++c)
                jac[r * static_cast<std::size_t>(n) + c] = o[r].derivative(c);
        }
    }
    void hessian(std::span<const double> v, std::span<const double> weights,
                 std::span<double> hess) const override {
        const int n = static_cast<int>(v.size());
        std::vector<AdDynH> a;
        a.reserve(v.size());
        for (int i = 0; i < n; ++i) a.push_back(AdDynH::variable(v[i], n, i));
        std::vector<AdDynH> o(weights.size());
        eval<AdDynH>(std::span<const AdDynH>(a), std::span<AdDynH>(o));
        std::fill(hess.begin(), hess.end(), 0.0);
        for (std::size_t r = 0; r < o.size(); ++r) {
            if (weights[r] == 0.0) continue;
            for (int i = 0; i < n; ++i) {
                for (int j = 0; j <= i; ++j) {
                    const double h = weights[r] * o[r].hessian(i, j);
                    hess[i * static_cast<std::size_t>(n) + j] += h;
                    if (j != i) hess[j * static_cast<std::size_t>(n) + i] += h;
                }
            }
        }
    }

private:
    template <class T>
    void eval(std::span<const T> v, std::span<T> out) const {
        const auto nf = static_cast<std::size_t>(n_from_);
        const auto nt = static_cast<std::size_t>(n_to_);
        if constexpr (kTimed) {
            const std::size_t np = v.size() - nf - nt - 4;
            f_(v.subspan(0, nf), v.subspan(nf, nt), v.subspan(nf + nt, np),
               v.subspan(nf + nt + np, 4), out);
        } else {
            f_(v.subspan(0, nf), v.subspan(nf, nt), v.subspan(nf + nt), out);
        }
    }
    F f_;
    std::vector<Constraint> c_;
    int n_from_ = 0, n_to_ = 0;
};

/// A linkage function of `n_from` final and `n_to` initial states with these constraints (F
/// with or without the times, see LinkFunction).
template <class F>
[[nodiscard]] std::shared_ptr<const LinkModel> make_link(int n_from, int n_to,
                                                         std::vector<Constraint> constraints, F f) {
    return std::make_shared<LinkFunction<F>>(n_from, n_to, std::move(constraints), std::move(f));
}

/// A link from the end of phase `from` (a) to the start of phase `to` (b).
struct Link {
    /// Null: continuity of every state, x_b(t0_b) = x_a(tf_a) (equal state counts).
    std::shared_ptr<const LinkModel> function;
    /// t0_b = tf_a (a linear row); false leaves the two times independent.
    bool time_continuity = true;
    /// The phases joined, a != b, any two (not only consecutive: several links may leave one
    /// phase). Both -1: by position, links[k] joins phase k to k + 1.
    int from = -1;
    int to = -1;
};

/// The ends of one phase as a cross-phase Mayer term sees them.
template <class T>
struct PhaseEnds {
    std::span<const T> x0;  ///< x(t0), the phase's states
    std::span<const T> xf;  ///< x(tf)
    T t0;
    T tf;
};

/// A Mayer term Ψ of the ends of several phases (the listed phases(), each's x(t0), x(tf), t0,
/// tf) and the static parameters, added to the phases' own objectives. Variables, in order: per
/// listed phase i x0 (n_states[i] values), xf (n_states[i]), t0, tf; then p.
class CrossPhaseMayer {
public:
    virtual ~CrossPhaseMayer() = default;
    /// The phases whose ends Ψ takes, in the order the function sees them.
    [[nodiscard]] virtual const std::vector<int>& phases() const = 0;
    /// True when Ψ (and the sum of all objectives) is maximised.
    [[nodiscard]] virtual bool maximise() const = 0;
    [[nodiscard]] virtual double value(std::span<const double> v,
                                       std::span<const int> n_states) const = 0;
    /// Ψ and its gradient (v.size() values).
    virtual double gradient(std::span<const double> v, std::span<const int> n_states,
                            std::span<double> grad) const = 0;
    /// Hessian of Ψ (full, symmetric, row-major v.size() x v.size()).
    virtual void hessian(std::span<const double> v, std::span<const int> n_states,
                         std::span<double> hess) const = 0;
};

/// A CrossPhaseMayer of a function object F with
///
///     template <class T> T operator()(std::span<const PhaseEnds<T>> ends,
///                                     std::span<const T> p) const;
///
/// (ends[i] those of phases()[i]; a generic lambda will do), differentiated by forward AD.
template <class F>
class CrossPhaseMayerFunction final : public CrossPhaseMayer {
public:
    CrossPhaseMayerFunction(std::vector<int> phases, F f, bool maximise)
        : f_(std::move(f)), phases_(std::move(phases)), maximise_(maximise) {}
    [[nodiscard]] const std::vector<int>& phases() const override { return phases_; }
    [[nodiscard]] bool maximise() const override { return maximise_; }
    [[nodiscard]] double value(std::span<const double> v,
                               std::span<const int> n_states) const override {
        return eval<double>(v, n_states);
    }
    double gradient(std::span<const double> v, std::span<const int> n_states,
                    std::span<double> grad) const override {
        const int n = static_cast<int>(v.size());
        std::vector<AdDyn1> a;
        a.reserve(v.size());
        for (int i = 0; i < n; ++i) a.push_back(AdDyn1::variable(v[i], n, i));
        const AdDyn1 r = eval<AdDyn1>(std::span<const AdDyn1>(a), n_states);
        for (int c = 0; c < n; ++c) grad[static_cast<std::size_t>(c)] = r.derivative(c);
        return r.value();
    }
    void hessian(std::span<const double> v, std::span<const int> n_states,
                 std::span<double> hess) const override {
        const int n = static_cast<int>(v.size());
        std::vector<AdDynH> a;
        a.reserve(v.size());
        for (int i = 0; i < n; ++i) a.push_back(AdDynH::variable(v[i], n, i));
        const AdDynH r = eval<AdDynH>(std::span<const AdDynH>(a), n_states);
        for (int i = 0; i < n; ++i) {
            for (int j = 0; j < n; ++j)
                hess[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + j] =
                    r.hessian(i, j);
        }
    }

private:
    template <class T>
    T eval(std::span<const T> v, std::span<const int> n_states) const {
        std::vector<PhaseEnds<T>> ends;
        ends.reserve(n_states.size());
        std::size_t at = 0;
        for (int ni : n_states) {
            const auto n = static_cast<std::size_t>(ni);
            ends.push_back(
                {v.subspan(at, n), v.subspan(at + n, n), v[at + 2 * n], v[at + 2 * n + 1]});
            at += 2 * n + 2;
        }
        return T(f_(std::span<const PhaseEnds<T>>(ends), v.subspan(at)));
    }
    F f_;
    std::vector<int> phases_;
    bool maximise_ = false;
};

/// A Mayer term of the ends of `phases` (see CrossPhaseMayerFunction), minimised unless
/// `maximise`; e.g. the total time tf of phase 2 less t0 of phase 0:
///
///     make_cross_phase_mayer({0, 2}, [](auto e, auto) { return e[1].tf - e[0].t0; });
template <class F>
[[nodiscard]] std::shared_ptr<const CrossPhaseMayer> make_cross_phase_mayer(std::vector<int> phases,
                                                                            F f,
                                                                            bool maximise = false) {
    return std::make_shared<CrossPhaseMayerFunction<F>>(std::move(phases), std::move(f), maximise);
}

/// One phase: its problem, mesh and initial guess (over the phase's own [t0, tf]).
struct Phase {
    std::shared_ptr<const Model> model;
    Mesh mesh;
    Guess guess;
};

/// Phases and the links between them.
struct MultiPhaseProblem {
    std::string name;           ///< reports
    std::vector<Phase> phases;  ///< at least one
    /// The links. Empty: default links (state and time continuity) from each phase k to k + 1.
    /// All by position (from = to = -1): phases.size() - 1 links, link k joining phase k to
    /// k + 1. Otherwise any number, each joining its `from` to its `to` (a by-position link k
    /// among them still joins k to k + 1).
    std::vector<Link> links;
    /// Optional Mayer term of several phases' ends, added to the phases' own objectives.
    std::shared_ptr<const CrossPhaseMayer> mayer;

    [[nodiscard]] int n_phases() const { return static_cast<int>(phases.size()); }
    /// Number of links (N - 1 when `links` is empty).
    [[nodiscard]] int n_links() const;
    /// Check counts, sizes, link indices, shared parameters, the sense of the objective and the
    /// bounds across each link (a continuity link whose two sides' bounds do not overlap, tf_a
    /// and t0_b bounds that do not overlap); throws a one-line InputError naming the phase, the
    /// link and the values in conflict. Called by solve and check_derivatives.
    void validate() const;
    /// Link k (the default one from k to k + 1 when `links` is empty), with `from` and `to`
    /// set (those of a by-position link: k and k + 1).
    [[nodiscard]] Link link(int k) const;
};

/// Result of a multi-phase solve: one Solution per phase (states, controls, costates, times,
/// the phase's own violations and re-simulation; status and iterations those of the whole
/// NLP; objective the phase's own Mayer + Lagrange part) and the totals.
struct MultiPhaseSolution {
    std::vector<Solution> phases;
    SolveStatus status = SolveStatus::failed;  ///< solved_unresolved when any phase is
    int ipopt_status = 0;
    std::string status_text;
    int iterations = 0;
    double cpu_time = 0.0;
    double wall_time = 0.0;
    double objective = 0.0;      ///< sum over phases and the cross-phase Mayer term, user's sign
    double mayer = 0.0;          ///< the cross-phase Mayer term (0 without one), user's sign
    Eigen::VectorXd parameters;  ///< the shared static parameters
    /// Values of each link's rows: t0_b - tf_a (unless both are fixed), the linkage function
    /// (continuity: x_b(t0) - x_a(tf) of each state not fixed on both sides), then, on the first
    /// link into a phase b >= 1, p^b - p^0 per parameter (the ties of phases no link enters
    /// are not listed).
    std::vector<Eigen::VectorXd> links;
    double max_violation = 0.0;       ///< largest unscaled violation, all rows
    double max_link_violation = 0.0;  ///< largest unscaled violation of the linkage rows
    int n_variables = 0;
    int n_constraints = 0;
    int n_jacobian_nonzeros = 0;
    int n_hessian_nonzeros = 0;

    [[nodiscard]] bool converged() const {
        return status == SolveStatus::solved || status == SolveStatus::solved_acceptable ||
               status == SolveStatus::solved_unresolved;
    }
    [[nodiscard]] bool resolved() const {
        return status == SolveStatus::solved || status == SolveStatus::solved_acceptable;
    }
    [[nodiscard]] const Solution& phase(int k) const {
        return phases.at(static_cast<std::size_t>(k));
    }
    /// Largest re-simulation error (scaled) over the phases (each phase from its own x(t0)).
    [[nodiscard]] double max_resimulation_error() const;
};

/// Solve the multi-phase problem (never throws on solver failure; InputError for bad input).
[[nodiscard]] MultiPhaseSolution solve(const MultiPhaseProblem& problem,
                                       const SolverOptions& options = {});

/// Derivative check of the multi-phase NLP (as check_derivatives of one phase, solve.hpp).
[[nodiscard]] DerivativeCheck check_derivatives(const MultiPhaseProblem& problem,
                                                double perturbation = 0.01, unsigned seed = 1);

/// One line per phase (t0, tf, objective part, x(t0), x(tf)) after the status and objective.
[[nodiscard]] std::string summary(const MultiPhaseSolution& solution);

/// Write the solution as CSV, one row per node of every phase: phase, t, segment, node, then
/// the states, controls, costates (lambda_<state>) and path constraints of all phases (the
/// union by name, in order of first appearance; empty where a phase has no such column).
/// `solve` writes it to SolverOptions::failure_csv when it fails. Throws IoError.
void write_csv(const MultiPhaseSolution& solution, const std::filesystem::path& file);

}  // namespace manta::optimal

#include "manta/optimal/refine.hpp"

namespace manta::optimal {

/// One solve of the multi-phase `solve_adaptive`.
struct MultiPhasePass {
    int pass = 0;                                     ///< 1 for the user's meshes
    std::vector<Mesh> meshes;                         ///< per phase, as solved
    std::vector<std::vector<double>> segment_errors;  ///< per phase, per segment
    double max_error = 0.0;                           ///< over all phases' segments
    int iterations = 0;
    double cpu_s = 0.0;
    SolveStatus status = SolveStatus::failed;
    double objective = 0.0;
    int total_nodes = 0;  ///< LGL points of all phases
};

/// Result of the multi-phase `solve_adaptive`.
struct MultiPhaseAdaptiveSolution {
    MultiPhaseSolution solution;  ///< the last converged solution (else the last one)
    std::vector<Mesh> meshes;     ///< its meshes, per phase
    std::vector<MultiPhasePass> passes;
    RefinementStatus status = RefinementStatus::solve_failed;
    std::string status_text;
};

/// Error-driven refinement of every phase's mesh (the single-phase rule of refine.hpp applied
/// per phase: segment_errors and refine_mesh on each phase's solution), all phases solved
/// together in each pass from the previous pass's solution, until every phase meets the
/// tolerance with its mesh unchanged by refine_mesh, or max_passes, or max_total_nodes (all
/// phases), or a failed solve (no retry with higher-degree pieces, unlike the single-phase
/// solve_adaptive). Phases with interior events are rejected (InputError): their junction
/// indices are not remapped here.
[[nodiscard]] MultiPhaseAdaptiveSolution solve_adaptive(const MultiPhaseProblem& problem,
                                                        const SolverOptions& solver_options = {},
                                                        const RefinementOptions& refinement = {});

/// The passes as a table (pass, points per phase, max error, IPOPT iterations, CPU, status,
/// objective) and the stop reason.
[[nodiscard]] std::string refinement_report(const MultiPhaseAdaptiveSolution& result);

}  // namespace manta::optimal
