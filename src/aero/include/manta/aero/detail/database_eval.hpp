#pragma once
/// @file database_eval.hpp
/// Private: the `AeroDatabase::evaluate` template and the interpolation kernels it shares with
/// database_eval.cpp. Included at the end of database.hpp; include that header, not this one.
///
/// Three paths, one arithmetic:
///  - `double`: a compiled, allocation-free kernel (database_eval.cpp), with a specialised
///    multilinear loop;
///  - first-order AD scalars whose value is a `double` and which carry a derivative vector
///    (`core::Dual` = Eigen::AutoDiffScalar<VectorXd>): the tables and the wind-to-body rotation
///    are evaluated in double together with the partial derivatives of every coefficient with
///    respect to the eleven query inputs (each 1-D weight and its derivative come from the same
///    `make_stencil` template), and each coefficient is lifted to T by the chain rule,
///    dC = sum_j dC/dx_j dx_j. This is exactly the derivative of the interpolant in the cell
///    chosen on the plain values, at a fraction of the cost of running every weight through a
///    heap-allocating AD type;
///  - any other scalar (nested AD, user types): `evaluate_slots<T>` with every weight in T.
/// In every path the cell is chosen on `core::value_of(x)` and the weights are functions of x
/// inside that cell, so derivatives follow the cell.

#include <algorithm>
#include <array>
#include <concepts>
#include <cstddef>
#include <type_traits>
#include <utility>

#include "manta/aero/detail/database_impl.hpp"
#include "manta/aero/types.hpp"
#include "manta/core/scalar.hpp"

namespace manta::aero::detail {

/// Where a query coordinate falls on a grid.
enum class Where { inside, below, above };

/// Cell of `xv` on grid `g`: the largest i in [0, n-2] with x[i] <= xv for an in-range value,
/// 0 below the grid, n-2 above it (and for NaN, which then propagates through the weights).
struct Cell {
    int i = 0;
    Where where = Where::inside;
};

/// Cell of a value inside [lo, hi] (or NaN, which gives the last cell and then propagates).
[[nodiscard]] inline int locate_inside(const GridPlan& g, double xv) noexcept {
    const double* x = g.xp;
    if (g.uniform) {
        // Guess from the uniform spacing, then correct by at most one cell without branching:
        // the guess is never more than one cell off (nodes lie within h/4 of uniform).
        const double u = (xv - g.lo) * g.inv_h;
        int i = u < g.last_d ? static_cast<int>(u) : g.last;
        i -= static_cast<int>(xv < x[i]);  // never at i = 0, where x[0] = lo <= xv
        i += static_cast<int>((i < g.last) & (xv >= x[i + 1]));
        return i;
    }
    // Branch-free binary search over the n - 1 cells.
    const double* base = x;
    int len = g.last + 1;
    while (len > 1) {
        const int half = len / 2;
        base = base[half] <= xv ? base + half : base;
        len -= half;
    }
    return static_cast<int>(base - x);
}

[[nodiscard]] inline Cell locate(const GridPlan& g, double xv) noexcept {
    if (xv < g.lo) return {0, Where::below};
    if (xv > g.hi) return {g.last, Where::above};
    return {locate_inside(g, xv), Where::inside};
}

/// The nonzero 1-D interpolation weights along one grid: nodes start .. start+count-1.
template <class S>
struct Stencil {
    int start = 0;
    int count = 1;
    std::array<S, max_stencil> w{};
};

/// 1-D cardinal weights of `method` at `x` (in cell `c`) under the extrapolation
/// policy `linear` (else clamp). Weights are computed in S, so they carry x's derivatives.
template <class S>
[[nodiscard]] Stencil<S> make_stencil(const GridPlan& g, const S& x, Cell c, Interpolation method,
                                      bool linear) {
    Stencil<S> s;
    const int n = g.n;
    if (c.where != Where::inside && !linear) {
        // Clamp: the edge node alone, a constant weight (zero derivative outside the table).
        s.start = c.where == Where::below ? 0 : n - 1;
        s.count = 1;
        s.w[0] = S(1.0);
        return s;
    }
    const int i = c.i;
    if (method == Interpolation::multilinear) {
        // Inside, or linear extrapolation of the edge cell (t < 0 or t > 1).
        const S t = (x - g.x[static_cast<std::size_t>(i)]) * g.inv_w[static_cast<std::size_t>(i)];
        s.start = i;
        s.count = 2;
        s.w[0] = S(1.0) - t;
        s.w[1] = t;
        return s;
    }
    s.count = g.c1_count;
    if (c.where == Where::below) {
        // f(x0) + m_0 (x - x0): C1 continuation with the edge slope.
        s.start = 0;
        const S dx = x - g.lo;
        for (int l = 0; l < s.count; ++l) s.w[l] = dx * g.slope_lo[l];
        s.w[0] = s.w[0] + S(1.0);
        return s;
    }
    s.start = g.c1_start[static_cast<std::size_t>(i)];
    if (c.where == Where::above) {
        const S dx = x - g.hi;
        for (int l = 0; l < s.count; ++l) s.w[l] = dx * g.slope_hi[l];
        s.w[n - 1 - s.start] = s.w[n - 1 - s.start] + S(1.0);
        return s;
    }
    // Cubic Hermite on [x_i, x_{i+1}]: f = h00 f_i + h01 f_{i+1} + h10 (h m_i) + h11 (h m_{i+1}),
    // with the slopes linear in the node values (c1_left, c1_right hold h m as node weights).
    const S t = (x - g.x[static_cast<std::size_t>(i)]) * g.inv_w[static_cast<std::size_t>(i)];
    const S u = S(1.0) - t;
    const S t2 = t * t;
    const S u2 = u * u;
    const S h00 = (S(1.0) + t * 2.0) * u2;
    const S h01 = t2 * (S(3.0) - t * 2.0);
    const S h10 = t * u2;
    const S h11 = t2 * (t - S(1.0));
    const auto& left = g.c1_left[static_cast<std::size_t>(i)];
    const auto& right = g.c1_right[static_cast<std::size_t>(i)];
    for (int l = 0; l < s.count; ++l) s.w[l] = h10 * left[l] + h11 * right[l];
    s.w[i - s.start] = s.w[i - s.start] + h00;
    s.w[i + 1 - s.start] = s.w[i + 1 - s.start] + h01;
    return s;
}

/// acc[c] += sum over the stencil of (product of the axis weights) * value[point, c].
template <class S>
void contract(const TablePlan& tp, const Stencil<S>* st, S* acc, int axis, const S& weight,
              std::size_t offset) {
    if (axis == tp.n_active) {
        const double* v = tp.values.data() + offset;
        for (int c = 0; c < tp.n_columns; ++c) acc[c] = acc[c] + weight * v[c];
        return;
    }
    const Stencil<S>& s = st[tp.grid[static_cast<std::size_t>(axis)]];
    const std::size_t stride = tp.stride[static_cast<std::size_t>(axis)];
    for (int l = 0; l < s.count; ++l) {
        contract(tp, st, acc, axis + 1, S(weight * s.w[l]),
                 offset + static_cast<std::size_t>(s.start + l) * stride);
    }
}

/// Largest number of distinct grids: five tables (static, three controls, dynamic) x six axes.
inline constexpr int max_grids = 5 * n_axes;

/// Sum of every table at the inputs `in` (the six axes in `Axis` order, then p q r alphadot
/// betadot), in the database's force axes: {F1, F2, F3, Cl, Cm, Cn}. Weights in S.
template <class S>
[[nodiscard]] std::array<S, n_slots> evaluate_slots(const AeroDatabase::Impl& impl,
                                                    const std::array<const S*, n_inputs>& in,
                                                    Interpolation method) {
    const Plan& plan = impl.plan;
    std::array<Stencil<S>, max_grids> st;
    for (std::size_t g = 0; g < plan.grids.size(); ++g) {
        const GridPlan& gp = plan.grids[g];
        const S& x = *in[static_cast<std::size_t>(gp.axis)];
        const double xv = core::value_of(x);
        const Cell c = locate(gp, xv);
        if (c.where != Where::inside) {
            record_out_of_range(impl, static_cast<int>(g), xv, c.where == Where::above);
        }
        st[g] = make_stencil<S>(gp, x, c, method, plan.linear);
    }
    std::array<S, n_slots> out;
    for (auto& o : out) o = S(0.0);
    std::array<S, max_columns> acc;
    for (const TablePlan& tp : plan.tables) {
        for (int c = 0; c < tp.n_columns; ++c) acc[static_cast<std::size_t>(c)] = S(0.0);
        contract<S>(tp, st.data(), acc.data(), 0, S(1.0), 0);
        for (int c = 0; c < tp.n_columns; ++c) {
            const auto k = static_cast<std::size_t>(c);
            auto& o = out[static_cast<std::size_t>(tp.slot[k])];
            if (tp.factor[k] == unit_factor) {
                o = o + acc[k];
            } else {
                o = o + acc[k] * *in[static_cast<std::size_t>(n_axes + tp.factor[k])];
            }
        }
    }
    return out;
}

/// A coefficient and its partial derivatives with respect to the eleven query inputs (the six
/// axes in `Axis` order, then p q r alphadot betadot).
struct Jet {
    double v = 0.0;
    std::array<double, n_inputs> d{};
};

/// Body-axis coefficients {CX, CY, CZ, Cl, Cm, Cn} with their partial derivatives at the input
/// values `x` (same order as Jet::d). Defined in database_eval.cpp.
[[nodiscard]] std::array<Jet, n_slots> evaluate_jets(const AeroDatabase::Impl& impl,
                                                     const std::array<double, n_inputs>& x,
                                                     Interpolation method);

/// The plain-double evaluation (fast path). Defined in database_eval.cpp.
[[nodiscard]] BodyCoefficients<double> evaluate_double(const AeroDatabase::Impl& impl,
                                                       const AeroQuery<double>& q,
                                                       Interpolation method);

/// First-order AD scalar with a plain `double` value and a derivative vector (Eigen's
/// AutoDiffScalar<VectorXd>, <Vector4d>, ...). Nested AD does not qualify (value() is AD).
// (clang-format 14 mangles concept definitions.)
// clang-format off
template <class T>
concept HasDerivativeType = requires { typename T::DerType; };

template <class T>
using ValueType = std::remove_cvref_t<decltype(std::declval<const T&>().value())>;

template <class T>
concept FirstOrderAd = HasDerivativeType<T> && std::same_as<ValueType<T>, double>;
// clang-format on

template <class T>
[[nodiscard]] std::array<const T*, n_inputs> inputs_of(const AeroQuery<T>& q) {
    // Order: Axis {alpha, beta, mach, elevator, aileron, rudder}, then the rates.
    return {&q.alpha, &q.beta,  &q.mach,  &q.elevator,      &q.aileron,     &q.rudder,
            &q.p_hat, &q.q_hat, &q.r_hat, &q.alpha_dot_hat, &q.beta_dot_hat};
}

/// C as an AD scalar: value `j.v`, derivatives sum_k dC/dx_k * dx_k.
template <class T>
[[nodiscard]] T lift(const Jet& j, const std::array<const T*, n_inputs>& in) {
    T out(j.v);
    std::ptrdiff_t n = 0;
    for (const T* x : in) n = std::max<std::ptrdiff_t>(n, x->derivatives().size());
    if (n == 0) return out;
    out.derivatives().setZero(n);
    for (std::size_t k = 0; k < in.size(); ++k) {
        const auto& dx = in[k]->derivatives();
        if (j.d[k] != 0.0 && dx.size() == n) out.derivatives() += j.d[k] * dx;
    }
    return out;
}

/// Body-axis coefficients from the six slots in the database's force axes.
template <class T>
[[nodiscard]] BodyCoefficients<T> to_body(const std::array<T, n_slots>& s, bool wind,
                                          const T& alpha, const T& beta) {
    BodyCoefficients<T> b;
    if (wind) {
        const auto f = body_from_wind<T>(s[0], s[1], s[2], alpha, beta);
        b.CX = f[0];
        b.CY = f[1];
        b.CZ = f[2];
    } else {
        b.CX = s[0];
        b.CY = s[1];
        b.CZ = s[2];
    }
    b.Cl = s[3];
    b.Cm = s[4];
    b.Cn = s[5];
    return b;
}

}  // namespace manta::aero::detail

namespace manta::aero {

template <class T>
BodyCoefficients<T> AeroDatabase::evaluate(const AeroQuery<T>& q, Interpolation method) const {
    const Impl& impl = *impl_;
    if constexpr (std::is_same_v<T, double>) {
        return detail::evaluate_double(impl, q, method);
    } else if constexpr (detail::FirstOrderAd<T>) {
        const auto in = detail::inputs_of(q);
        std::array<double, detail::n_inputs> x{};
        for (std::size_t k = 0; k < in.size(); ++k) x[k] = in[k]->value();
        const auto j = detail::evaluate_jets(impl, x, method);
        BodyCoefficients<T> b;
        b.CX = detail::lift<T>(j[0], in);
        b.CY = detail::lift<T>(j[1], in);
        b.CZ = detail::lift<T>(j[2], in);
        b.Cl = detail::lift<T>(j[3], in);
        b.Cm = detail::lift<T>(j[4], in);
        b.Cn = detail::lift<T>(j[5], in);
        return b;
    } else {
        impl.evaluations.add();
        const auto s = detail::evaluate_slots<T>(impl, detail::inputs_of(q), method);
        return detail::to_body<T>(s, impl.plan.wind, q.alpha, q.beta);
    }
}

}  // namespace manta::aero
