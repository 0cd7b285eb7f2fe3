#pragma once
/// @file model.hpp
/// `Model`: the type-erased face of a user problem that the transcription calls, one node at a
/// time. `make_model(problem)` wraps a problem type (problem.hpp) and differentiates it per node
/// by forward AD: first derivatives with `Ad1` (ad.hpp), exact Hessians with `AdH` (hyper.hpp);
/// an evaluation with more than kMaxDirections local variables uses their run-time-sized
/// versions `AdDyn1` and `AdDynH` instead (heap storage sized to the problem), so a problem of
/// any size works and problems within kMaxDirections keep the fixed-size scalars. A problem type
/// with `static constexpr bool fixed_size_ad = true;` skips the run-time-sized path (see
/// detail::fixed_size_ad).
/// Nothing is recorded between calls, so derivatives follow the branches taken at each evaluation.
///
/// Local variables of a collocation node, in order: x (nx), u (nu), p (np), t0, tf, then the
/// segment's start and end fractions s_lo, s_hi when they are decision variables. Outputs of a
/// node: q = (h/2) f (nx), the path constraints g (ng), and l = (h/2) w L when the problem has a
/// Lagrange cost, then (h/2) w q for the integrands q of the integral constraints (nq), with
/// h = (tf - t0)(s_hi - s_lo) the segment duration, w the node's LGL weight and the node's time
/// t = t0 + (tf - t0)(s_lo + (s_hi - s_lo) a).
///
/// Boundary variables: x(t0) (nx), x(tf) (nx), p, t0, tf; outputs: the events e (ne), then the
/// Mayer cost when the problem has one.
///
/// Interior variables of mesh junction j: x(t_j) (nx), p, t0, tf, s_j (the break as a fraction of
/// [t0, tf]; t_j = t0 + (tf - t0) s_j); outputs: the interior events of junction j in order.

#include <algorithm>
#include <array>
#include <concepts>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "manta/core/error.hpp"
#include "manta/optimal/ad.hpp"
#include "manta/optimal/hyper.hpp"
#include "manta/optimal/problem.hpp"

namespace manta::optimal {

/// Where a collocation node sits in time (values; see the file comment).
struct NodePlacement {
    double s_lo = 0.0;     ///< segment start as a fraction of [t0, tf]
    double s_hi = 1.0;     ///< segment end as a fraction of [t0, tf]
    double a = 0.0;        ///< (tau + 1) / 2 of the node within its segment
    double weight = 0.0;   ///< LGL weight of the node
    bool seed_lo = false;  ///< s_lo is a decision variable (a local variable)
    bool seed_hi = false;  ///< s_hi is a decision variable (a local variable)
    [[nodiscard]] int n_time_vars() const { return 2 + int(seed_lo) + int(seed_hi); }
};

/// Type-erased problem evaluated per node (see the file comment for the variable order).
class Model {
public:
    virtual ~Model() = default;
    /// Sizes, names, bounds.
    [[nodiscard]] virtual const ProblemInfo& info() const = 0;
    [[nodiscard]] virtual bool has_lagrange() const = 0;
    [[nodiscard]] virtual bool has_mayer() const = 0;

    /// f(x, u, p, t) in double (re-simulation, reports).
    virtual void dynamics(std::span<const double> x, std::span<const double> u,
                          std::span<const double> p, double t, std::span<double> xdot) const = 0;
    /// g(x, u, p, t) in double (empty problem: nothing).
    virtual void path(std::span<const double> x, std::span<const double> u,
                      std::span<const double> p, double t, std::span<double> g) const = 0;

    /// Node outputs in double. `v`: local variables; `out`: n_node_outputs().
    virtual void node_values(std::span<const double> v, const NodePlacement& at,
                             std::span<double> out) const = 0;
    /// Node outputs and their Jacobian (row-major, n_out x n_local) by forward AD.
    virtual void node_jacobian(std::span<const double> v, const NodePlacement& at,
                               std::span<double> out, std::span<double> jac) const = 0;
    /// Hessian (n_local x n_local, full, symmetric) of sum_k weight_k out_k by forward-over-forward
    /// AD.
    virtual void node_hessian(std::span<const double> v, const NodePlacement& at,
                              std::span<const double> weights, std::span<double> hess) const = 0;

    /// Boundary outputs (events, then Mayer) in double.
    virtual void boundary_values(std::span<const double> v, std::span<double> out) const = 0;
    /// Boundary outputs and their Jacobian (row-major).
    virtual void boundary_jacobian(std::span<const double> v, std::span<double> out,
                                   std::span<double> jac) const = 0;
    /// Hessian of sum_k weight_k out_k over the boundary variables (full, symmetric).
    virtual void boundary_hessian(std::span<const double> v, std::span<const double> weights,
                                  std::span<double> hess) const = 0;

    /// Interior events of junction j (n_interior_vars() variables, see the file comment).
    virtual void interior_values(int junction, std::span<const double> v,
                                 std::span<double> out) const = 0;
    /// Interior events of junction j and their Jacobian (row-major).
    virtual void interior_jacobian(int junction, std::span<const double> v, std::span<double> out,
                                   std::span<double> jac) const = 0;
    /// Hessian of sum_k weight_k out_k over the interior variables of junction j.
    virtual void interior_hessian(int junction, std::span<const double> v,
                                  std::span<const double> weights,
                                  std::span<double> hess) const = 0;

    /// Number of interior variables of a junction: nx + np + 3.
    [[nodiscard]] int n_interior_vars() const {
        return info().n_states() + info().n_parameters() + 3;
    }
    /// Number of node outputs: nx + ng (+1 with a Lagrange cost) + nq (integral constraints).
    [[nodiscard]] int n_node_outputs() const {
        return info().n_states() + info().n_path() + (has_lagrange() ? 1 : 0) +
               info().n_integrals();
    }
    /// Number of local node variables for a placement.
    [[nodiscard]] int n_node_vars(const NodePlacement& at) const {
        return info().n_states() + info().n_controls() + info().n_parameters() + at.n_time_vars();
    }
    /// Number of boundary outputs: ne (+1 with a Mayer cost).
    [[nodiscard]] int n_boundary_outputs() const {
        return info().n_events() + (has_mayer() ? 1 : 0);
    }
    /// Number of boundary variables: 2 nx + np + 2.
    [[nodiscard]] int n_boundary_vars() const {
        return 2 * info().n_states() + info().n_parameters() + 2;
    }
};

namespace detail {

template <class P, class T>
concept HasPath = requires(const P& p, std::span<const T> x, const T& t, std::span<T> g) {
    p.path(x, x, x, t, g);
};
template <class P, class T>
concept HasLagrange = requires(const P& p, std::span<const T> x, const T& t) {
    { p.lagrange(x, x, x, t) } -> std::convertible_to<T>;
};
template <class P, class T>
concept HasEvents = requires(const P& p, std::span<const T> x, const T& t, std::span<T> e) {
    p.events(x, x, x, t, t, e);
};
template <class P, class T>
concept HasMayer = requires(const P& p, std::span<const T> x, const T& t) {
    { p.mayer(x, x, x, t, t) } -> std::convertible_to<T>;
};

template <class P, class T>
concept HasIntegrand = requires(const P& p, std::span<const T> x, const T& t, std::span<T> q) {
    p.integrand(x, x, x, t, q);
};
template <class P, class T>
concept HasNode = requires(const P& p, std::span<const T> x, const T& t, std::span<T> out) {
    p.node(x, x, x, t, out, out);
};
template <class P, class T>
concept HasInterior = requires(const P& p, std::span<const T> x, const T& t, std::span<T> e) {
    p.interior(1, x, x, t, e);
};

/// A problem type that declares `static constexpr bool fixed_size_ad = true;` is differentiated
/// with the fixed-size scalars only: the run-time-sized path is not instantiated (a shorter
/// compile for a large model), and more than kMaxDirections local variables is an InputError.
template <class P>
concept DeclaresFixedSizeAd = requires {
    { P::fixed_size_ad } -> std::convertible_to<bool>;
};
template <class P>
constexpr bool fixed_size_ad() {
    if constexpr (DeclaresFixedSizeAd<P>) {
        return P::fixed_size_ad;
    } else {
        return false;
    }
}

}  // namespace detail

/// Second-order AD scalar of the Hessians (value, gradient, packed symmetric Hessian).
using AdH = Hyper<kMaxDirections>;
/// Second-order AD scalar with any number of directions (heap storage).
using AdDynH = Hyper<kDynamic>;

namespace detail {

/// Seed n AD variables of type A from plain values.
template <class A>
std::vector<A> seed(std::span<const double> v) {
    const int n = static_cast<int>(v.size());
    std::vector<A> r;
    r.reserve(v.size());
    for (int i = 0; i < n; ++i) r.push_back(A::variable(v[i], n, i));
    return r;
}
template <>
inline std::vector<Ad2> seed<Ad2>(std::span<const double> v) {
    const int n = static_cast<int>(v.size());
    std::vector<Ad2> r;
    r.reserve(v.size());
    for (int i = 0; i < n; ++i) r.push_back(Ad2::variable(Ad1::variable(v[i], n, i), n, i));
    return r;
}

}  // namespace detail

/// `Model` of a problem type P, differentiated by forward AD. Holds a copy of the problem.
template <OptimalControlProblem P>
class ProblemModel final : public Model {
public:
    explicit ProblemModel(P problem) : problem_(std::move(problem)), info_(problem_.info()) {
        info_.validate();
        const int nx = info_.n_states();
        if (detail::fixed_size_ad<P>() &&
            (nx + info_.n_controls() + info_.n_parameters() + 4 > kMaxDirections ||
             2 * nx + info_.n_parameters() + 2 > kMaxDirections)) {
            throw InputError("optimal control problem '" + info_.name + "': " + std::to_string(nx) +
                             " states, " + std::to_string(info_.n_controls()) + " controls and " +
                             std::to_string(info_.n_parameters()) +
                             " parameters exceed the fixed-size AD capacity of " +
                             std::to_string(kMaxDirections) +
                             " directions per node, expected fixed_size_ad = false for a problem "
                             "of this size");
        }
        if (info_.n_path() > 0 && !detail::HasPath<P, double>) {
            throw InputError("optimal control problem '" + info_.name +
                             "' declares path constraints but has no path() function");
        }
        if (info_.n_events() > 0 && !detail::HasEvents<P, double>) {
            throw InputError("optimal control problem '" + info_.name +
                             "' declares events but has no events() function");
        }
        if (info_.n_interior_events() > 0 && !detail::HasInterior<P, double>) {
            throw InputError("optimal control problem '" + info_.name +
                             "' declares interior events but has no interior() function");
        }
        if (info_.n_integrals() > 0 && !detail::HasIntegrand<P, double>) {
            throw InputError("optimal control problem '" + info_.name +
                             "' declares integral constraints but has no integrand() function");
        }
    }

    [[nodiscard]] const ProblemInfo& info() const override { return info_; }
    [[nodiscard]] bool has_lagrange() const override { return detail::HasLagrange<P, double>; }
    [[nodiscard]] bool has_mayer() const override { return detail::HasMayer<P, double>; }
    /// The wrapped problem.
    [[nodiscard]] const P& problem() const { return problem_; }

    void dynamics(std::span<const double> x, std::span<const double> u, std::span<const double> p,
                  double t, std::span<double> xdot) const override {
        problem_.dynamics(x, u, p, t, xdot);
    }
    void path(std::span<const double> x, std::span<const double> u, std::span<const double> p,
              double t, std::span<double> g) const override {
        if constexpr (detail::HasPath<P, double>) {
            if (!g.empty()) problem_.path(x, u, p, t, g);
        }
    }

    void node_values(std::span<const double> v, const NodePlacement& at,
                     std::span<double> out) const override {
        node_eval<double>(v, at, out);
    }
    void node_jacobian(std::span<const double> v, const NodePlacement& at, std::span<double> out,
                       std::span<double> jac) const override {
        if constexpr (detail::fixed_size_ad<P>()) {
            node_jacobian_as<Ad1>(v, at, out, jac);
        } else if (v.size() <= static_cast<std::size_t>(kMaxDirections)) {
            node_jacobian_as<Ad1>(v, at, out, jac);
        } else {
            node_jacobian_as<AdDyn1>(v, at, out, jac);
        }
    }
    void node_hessian(std::span<const double> v, const NodePlacement& at,
                      std::span<const double> weights, std::span<double> hess) const override {
        if constexpr (detail::fixed_size_ad<P>()) {
            node_hessian_as<AdH>(v, at, weights, hess);
        } else if (v.size() <= static_cast<std::size_t>(kMaxDirections)) {
            node_hessian_as<AdH>(v, at, weights, hess);
        } else {
            node_hessian_as<AdDynH>(v, at, weights, hess);
        }
    }

    void boundary_values(std::span<const double> v, std::span<double> out) const override {
        boundary_eval<double>(v, out);
    }
    void boundary_jacobian(std::span<const double> v, std::span<double> out,
                           std::span<double> jac) const override {
        if constexpr (detail::fixed_size_ad<P>()) {
            boundary_jacobian_as<Ad1>(v, out, jac);
        } else if (v.size() <= static_cast<std::size_t>(kMaxDirections)) {
            boundary_jacobian_as<Ad1>(v, out, jac);
        } else {
            boundary_jacobian_as<AdDyn1>(v, out, jac);
        }
    }
    void boundary_hessian(std::span<const double> v, std::span<const double> weights,
                          std::span<double> hess) const override {
        if constexpr (detail::fixed_size_ad<P>()) {
            boundary_hessian_as<AdH>(v, weights, hess);
        } else if (v.size() <= static_cast<std::size_t>(kMaxDirections)) {
            boundary_hessian_as<AdH>(v, weights, hess);
        } else {
            boundary_hessian_as<AdDynH>(v, weights, hess);
        }
    }

    void interior_values(int junction, std::span<const double> v,
                         std::span<double> out) const override {
        interior_eval<double>(junction, v, out);
    }
    void interior_jacobian(int junction, std::span<const double> v, std::span<double> out,
                           std::span<double> jac) const override {
        if constexpr (detail::fixed_size_ad<P>()) {
            interior_jacobian_as<Ad1>(junction, v, out, jac);
        } else if (v.size() <= static_cast<std::size_t>(kMaxDirections)) {
            interior_jacobian_as<Ad1>(junction, v, out, jac);
        } else {
            interior_jacobian_as<AdDyn1>(junction, v, out, jac);
        }
    }
    void interior_hessian(int junction, std::span<const double> v, std::span<const double> weights,
                          std::span<double> hess) const override {
        if constexpr (detail::fixed_size_ad<P>()) {
            interior_hessian_as<AdH>(junction, v, weights, hess);
        } else if (v.size() <= static_cast<std::size_t>(kMaxDirections)) {
            interior_hessian_as<AdH>(junction, v, weights, hess);
        } else {
            interior_hessian_as<AdDynH>(junction, v, weights, hess);
        }
    }

private:
    // Derivatives with first-order scalar A1 or second-order scalar A2 (fixed or run-time size).
    template <class A1>
    void node_jacobian_as(std::span<const double> v, const NodePlacement& at, std::span<double> out,
                          std::span<double> jac) const {
        const auto vars = detail::seed<A1>(v);
        std::vector<A1> o(out.size());
        node_eval<A1>(std::span<const A1>(vars), at, std::span<A1>(o));
        extract_first(o, static_cast<int>(v.size()), out, jac);
    }
    template <class A2>
    void node_hessian_as(std::span<const double> v, const NodePlacement& at,
                         std::span<const double> weights, std::span<double> hess) const {
        const auto vars = detail::seed<A2>(v);
        std::vector<A2> o(weights.size());
        node_eval<A2>(std::span<const A2>(vars), at, std::span<A2>(o));
        extract_second(o, weights, static_cast<int>(v.size()), hess);
    }
    template <class A1>
    void boundary_jacobian_as(std::span<const double> v, std::span<double> out,
                              std::span<double> jac) const {
        const auto vars = detail::seed<A1>(v);
        std::vector<A1> o(out.size());
        boundary_eval<A1>(std::span<const A1>(vars), std::span<A1>(o));
        extract_first(o, static_cast<int>(v.size()), out, jac);
    }
    template <class A2>
    void boundary_hessian_as(std::span<const double> v, std::span<const double> weights,
                             std::span<double> hess) const {
        const auto vars = detail::seed<A2>(v);
        std::vector<A2> o(weights.size());
        boundary_eval<A2>(std::span<const A2>(vars), std::span<A2>(o));
        extract_second(o, weights, static_cast<int>(v.size()), hess);
    }
    template <class A1>
    void interior_jacobian_as(int junction, std::span<const double> v, std::span<double> out,
                              std::span<double> jac) const {
        const auto vars = detail::seed<A1>(v);
        std::vector<A1> o(out.size());
        interior_eval<A1>(junction, std::span<const A1>(vars), std::span<A1>(o));
        extract_first(o, static_cast<int>(v.size()), out, jac);
    }
    template <class A2>
    void interior_hessian_as(int junction, std::span<const double> v,
                             std::span<const double> weights, std::span<double> hess) const {
        const auto vars = detail::seed<A2>(v);
        std::vector<A2> o(weights.size());
        interior_eval<A2>(junction, std::span<const A2>(vars), std::span<A2>(o));
        extract_second(o, weights, static_cast<int>(v.size()), hess);
    }

    /// Interior events of a junction in scalar type T.
    template <class T>
    void interior_eval(int junction, std::span<const T> v, std::span<T> out) const {
        const std::size_t nx = info_.states.size();
        const std::size_t np = info_.parameters.size();
        const auto x = v.subspan(0, nx);
        const auto p = v.subspan(nx, np);
        const T& t0 = v[nx + np];
        const T& tf = v[nx + np + 1];
        const T& s = v[nx + np + 2];
        const T t = t0 + (tf - t0) * s;
        if constexpr (detail::HasInterior<P, T>) {
            if (!out.empty()) problem_.interior(junction, x, p, t, out);
        }
    }

    /// Node outputs in scalar type T (see the file comment).
    template <class T>
    void node_eval(std::span<const T> v, const NodePlacement& at, std::span<T> out) const {
        const std::size_t nx = info_.states.size();
        const std::size_t nu = info_.controls.size();
        const std::size_t np = info_.parameters.size();
        const std::size_t ng = info_.path.size();
        const auto x = v.subspan(0, nx);
        const auto u = v.subspan(nx, nu);
        const auto p = v.subspan(nx + nu, np);
        std::size_t k = nx + nu + np;
        const T& t0 = v[k];
        const T& tf = v[k + 1];
        k += 2;
        const T s_lo = at.seed_lo ? v[k++] : T(at.s_lo);
        const T s_hi = at.seed_hi ? v[k] : T(at.s_hi);
        const T duration = tf - t0;
        const T half_h = 0.5 * duration * (s_hi - s_lo);
        const T t = t0 + duration * (s_lo + (s_hi - s_lo) * at.a);
        std::vector<T> xdot(nx);
        if constexpr (detail::HasNode<P, T>) {
            // dynamics and path constraints in one pass (shared intermediate results)
            problem_.node(x, u, p, t, std::span<T>(xdot), out.subspan(nx, ng));
        } else {
            problem_.dynamics(x, u, p, t, std::span<T>(xdot));
            if constexpr (detail::HasPath<P, T>) {
                if (ng > 0) problem_.path(x, u, p, t, out.subspan(nx, ng));
            }
        }
        for (std::size_t r = 0; r < nx; ++r) out[r] = half_h * xdot[r];
        [[maybe_unused]] std::size_t next = nx + ng;
        if constexpr (detail::HasLagrange<P, T>) {
            out[next++] = half_h * at.weight * problem_.lagrange(x, u, p, t);
        }
        if constexpr (detail::HasIntegrand<P, T>) {
            const std::size_t nq = info_.integrals.size();
            if (nq > 0) {
                std::vector<T> q(nq);
                problem_.integrand(x, u, p, t, std::span<T>(q));
                for (std::size_t j = 0; j < nq; ++j) out[next + j] = half_h * at.weight * q[j];
            }
        }
    }

    /// Boundary outputs in scalar type T.
    template <class T>
    void boundary_eval(std::span<const T> v, std::span<T> out) const {
        const std::size_t nx = info_.states.size();
        const std::size_t np = info_.parameters.size();
        const std::size_t ne = info_.events.size();
        const auto x0 = v.subspan(0, nx);
        const auto xf = v.subspan(nx, nx);
        const auto p = v.subspan(2 * nx, np);
        const T& t0 = v[2 * nx + np];
        const T& tf = v[2 * nx + np + 1];
        if constexpr (detail::HasEvents<P, T>) {
            if (ne > 0) problem_.events(x0, xf, p, t0, tf, out.subspan(0, ne));
        }
        if constexpr (detail::HasMayer<P, T>) {
            out[ne] = problem_.mayer(x0, xf, p, t0, tf);
        }
    }

    template <class A1>
    static void extract_first(const std::vector<A1>& o, int n, std::span<double> out,
                              std::span<double> jac) {
        for (std::size_t r = 0; r < o.size(); ++r) {
            out[r] = o[r].value();
            for (int c = 0; c < n; ++c) jac[r * n + c] = o[r].derivative(c);
        }
    }
    template <class A2>
    static void extract_second(const std::vector<A2>& o, std::span<const double> weights, int n,
                               std::span<double> hess) {
        std::fill(hess.begin(), hess.end(), 0.0);
        for (std::size_t r = 0; r < o.size(); ++r) {
            const double w = weights[r];
            if (w == 0.0) continue;
            for (int i = 0; i < n; ++i) {
                for (int j = 0; j <= i; ++j) hess[i * n + j] += w * o[r].hessian(i, j);
            }
        }
        for (int i = 0; i < n; ++i) {
            for (int j = i + 1; j < n; ++j) hess[i * n + j] = hess[j * n + i];
        }
    }

    P problem_;
    ProblemInfo info_;
};

/// Wrap a problem type as a Model (copies the problem).
template <OptimalControlProblem P>
[[nodiscard]] std::unique_ptr<Model> make_model(P problem) {
    return std::make_unique<ProblemModel<P>>(std::move(problem));
}

}  // namespace manta::optimal
