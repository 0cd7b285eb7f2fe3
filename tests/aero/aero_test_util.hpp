#pragma once
/// Helpers shared by the aero database tests.

#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "manta/aero/database.hpp"

namespace manta::aero::test {

inline constexpr double deg = std::numbers::pi / 180.0;

/// Breakpoints lo, lo + step, ..., hi (inclusive, to rounding).
inline std::vector<double> linspace(double lo, double hi, int n) {
    std::vector<double> v;
    for (int i = 0; i < n; ++i) v.push_back(lo + (hi - lo) * i / (n - 1));
    return v;
}

/// A table over `axes` whose values at each grid point are f(point)[column].
inline Table make_table(std::string name, TableKind kind, std::vector<GridAxis> axes,
                        std::vector<std::string> columns,
                        const std::function<std::vector<double>(const std::vector<double>&)>& f) {
    Table t;
    t.name = std::move(name);
    t.kind = kind;
    t.axes = std::move(axes);
    t.columns = std::move(columns);
    std::vector<std::size_t> idx(t.axes.size(), 0);
    std::vector<double> p(t.axes.size());
    for (std::size_t n = 0; n < t.n_points(); ++n) {
        for (std::size_t k = 0; k < idx.size(); ++k) p[k] = t.axes[k].breakpoints[idx[k]];
        const auto row = f(p);
        t.values.insert(t.values.end(), row.begin(), row.end());
        for (std::size_t k = idx.size(); k-- > 0;) {
            if (++idx[k] < t.axes[k].breakpoints.size()) break;
            idx[k] = 0;
        }
    }
    return t;
}

/// Set the query field that an axis reads.
template <class T>
void set_axis(AeroQuery<T>& q, Axis a, const T& v) {
    switch (a) {
        case Axis::alpha:
            q.alpha = v;
            break;
        case Axis::beta:
            q.beta = v;
            break;
        case Axis::mach:
            q.mach = v;
            break;
        case Axis::elevator:
            q.elevator = v;
            break;
        case Axis::aileron:
            q.aileron = v;
            break;
        case Axis::rudder:
            q.rudder = v;
            break;
    }
}

/// Query inputs in a fixed order: alpha beta mach elevator aileron rudder p q r alphadot betadot.
template <class T>
std::array<T*, 11> fields(AeroQuery<T>& q) {
    return {&q.alpha, &q.beta,  &q.mach,  &q.elevator,      &q.aileron,     &q.rudder,
            &q.p_hat, &q.q_hat, &q.r_hat, &q.alpha_dot_hat, &q.beta_dot_hat};
}

template <class T>
std::array<T, 6> as_array(const BodyCoefficients<T>& c) {
    return {c.CX, c.CY, c.CZ, c.Cl, c.Cm, c.Cn};
}

/// A Ranger-like database built from derivatives: 17 alpha x 6 Mach x 9 beta static, three
/// control tables over (alpha, mach, delta) with 9 deflections, dynamic (alpha, mach).
inline AeroDatabase ranger_like(Extrapolation extrapolation = Extrapolation::clamp,
                                bool uniform_alpha = true) {
    LinearDerivatives d;
    d.CL_0 = 0.25;
    d.CL_alpha = 5.1;
    d.CL_q = 7.0;
    d.CL_alphadot = 2.0;
    d.CL_de = 0.43;
    d.CD_0 = 0.03;
    d.CD_k = 0.06;
    d.CL_min_drag = 0.1;
    d.CD_de = 0.05;
    d.CY_beta = -0.35;
    d.CY_p = -0.05;
    d.CY_r = 0.25;
    d.CY_da = 0.01;
    d.CY_dr = 0.19;
    d.Cl_beta = -0.09;
    d.Cl_p = -0.45;
    d.Cl_r = 0.1;
    d.Cl_da = 0.17;
    d.Cl_dr = 0.012;
    d.Cm_0 = 0.04;
    d.Cm_alpha = -0.7;
    d.Cm_q = -12.0;
    d.Cm_alphadot = -5.0;
    d.Cm_de = -1.3;
    d.Cn_beta = 0.065;
    d.Cn_p = -0.03;
    d.Cn_r = -0.1;
    d.Cn_da = -0.005;
    d.Cn_dr = -0.07;
    d.mach_ref = 0.2;
    d.prandtl_glauert = true;
    DerivativeGrids g;
    if (uniform_alpha) {
        g.alpha = linspace(-8 * deg, 24 * deg, 17);
    } else {
        g.alpha = {-8 * deg, -6 * deg, -4 * deg, -2 * deg, -1 * deg, 0.0,
                   1 * deg,  2 * deg,  3 * deg,  4 * deg,  6 * deg,  8 * deg,
                   10 * deg, 13 * deg, 16 * deg, 20 * deg, 24 * deg};
    }
    g.mach = linspace(0.1, 0.6, 6);
    g.beta = linspace(-8 * deg, 8 * deg, 9);
    g.elevator = linspace(-20 * deg, 20 * deg, 9);
    g.aileron = linspace(-20 * deg, 20 * deg, 9);
    g.rudder = linspace(-20 * deg, 20 * deg, 9);
    const AeroDatabase db =
        AeroDatabase::from_derivatives(d, g, {"Ranger-like", "benchmark database", ""});
    return AeroDatabase(db.info(), db.force_axes(), extrapolation, db.tables());
}

}  // namespace manta::aero::test
