#pragma once
/// @file problems.hpp
/// Validation problems of the optimal-control solver (docs/optimal-control.md#validation):
/// the brachistochrone (analytic cycloid), the minimum-time double integrator (bang-bang,
/// analytic switch and final times) and Bryson's F-4 minimum time to climb (tabular
/// aerodynamics and thrust, PSOPT's data and interpolation).

#include <array>
#include <cmath>
#include <numbers>
#include <span>
#include <vector>

#include "manta/core/scalar.hpp"
#include "manta/optimal/ad.hpp"
#include "manta/optimal/problem.hpp"
#include "manta/optimal/solve.hpp"

namespace manta::optimal {

// ---------------------------------------------------------------------------------------------
/// Brachistochrone: a bead slides without friction from rest at the origin to (x_f, y_f), y
/// positive downwards, in least time. States x, y [m], v [m/s]; control theta [rad], the path
/// angle from the downward vertical: x' = v sin theta, y' = v cos theta, v' = g cos theta.
struct Brachistochrone {
    double gravity = 9.80665;  ///< [m/s^2]
    double x_final = 10.0;     ///< [m]
    double y_final = 5.0;      ///< [m], below the start

    [[nodiscard]] ProblemInfo info() const;
    template <class T>
    void dynamics(std::span<const T> x, std::span<const T> u, std::span<const T> /*p*/,
                  const T& /*t*/, std::span<T> xdot) const {
        using std::cos;
        using std::sin;
        const T s = sin(u[0]);
        const T c = cos(u[0]);
        xdot[0] = x[2] * s;
        xdot[1] = x[2] * c;
        xdot[2] = gravity * c;
    }
    template <class T>
    T mayer(std::span<const T> /*x0*/, std::span<const T> /*xf*/, std::span<const T> /*p*/,
            const T& /*t0*/, const T& tf) const {
        return tf;
    }
    /// Linear guess from rest at the origin to the end point.
    [[nodiscard]] Guess guess() const;
};

/// The analytic optimum of the brachistochrone: the cycloid x = R (phi - sin phi),
/// y = R (1 - cos phi) through (x_f, y_f), descended in t_f = phi_f sqrt(R / g).
struct CycloidSolution {
    double phi_final = 0.0;   ///< cycloid parameter at the end point [rad]
    double radius = 0.0;      ///< R [m]
    double final_time = 0.0;  ///< t_f [s]
};
/// Solve (phi - sin phi) / (1 - cos phi) = x_f / y_f for phi in (0, 2 pi) by bisection to
/// machine precision. Throws InputError for x_f <= 0 or y_f <= 0.
[[nodiscard]] CycloidSolution brachistochrone_cycloid(double x_final, double y_final,
                                                      double gravity);

// ---------------------------------------------------------------------------------------------
/// Minimum-time double integrator x'' = u, |u| <= 1, from (x0, v0) to rest at the origin.
/// Optional path constraint `speed_limit`: |v| <= max_speed (for the infeasibility test).
struct DoubleIntegrator {
    double x0 = 1.0;               ///< initial position
    double v0 = 1.0;               ///< initial velocity
    double max_final_time = 20.0;  ///< upper bound on t_f
    double max_speed = 0.0;        ///< > 0: path constraint |v| <= max_speed

    [[nodiscard]] ProblemInfo info() const;
    template <class T>
    void dynamics(std::span<const T> x, std::span<const T> u, std::span<const T> /*p*/,
                  const T& /*t*/, std::span<T> xdot) const {
        xdot[0] = x[1];
        xdot[1] = u[0];
    }
    template <class T>
    void path(std::span<const T> x, std::span<const T> /*u*/, std::span<const T> /*p*/,
              const T& /*t*/, std::span<T> g) const {
        if (!g.empty()) g[0] = x[1];
    }
    template <class T>
    T mayer(std::span<const T> /*x0*/, std::span<const T> /*xf*/, std::span<const T> /*p*/,
            const T& /*t0*/, const T& tf) const {
        return tf;
    }
    [[nodiscard]] Guess guess() const;
};

/// Analytic bang-bang solution of DoubleIntegrator from a state above the switching curve
/// x = -v|v|/2: u = -1 until t_s = v0 + sqrt(v0^2/2 + x0), then u = +1 until
/// t_f = v0 + 2 sqrt(v0^2/2 + x0).
struct BangBangSolution {
    double switch_time = 0.0;  ///< t_s
    double final_time = 0.0;   ///< t_f
};
/// Throws InputError when (x0, v0) is not above the switching curve.
[[nodiscard]] BangBangSolution double_integrator_bang_bang(double x0, double v0);

// ---------------------------------------------------------------------------------------------
/// A natural cubic spline (zero second derivative at both ends) through (x_i, y_i), evaluated
/// on any scalar type; outside the knots the end cubic is extended (as PSOPT's
/// `spline_interpolation`). The interval is chosen on the plain value at each call.
class NaturalSpline {
public:
    NaturalSpline() = default;
    /// Knots strictly increasing, at least 2. Throws InputError.
    NaturalSpline(std::vector<double> x, std::vector<double> y);
    /// Second derivatives at the knots of the natural spline through y on knots x.
    [[nodiscard]] static std::vector<double> second_derivatives(const std::vector<double>& x,
                                                                const std::vector<double>& y);
    /// Interval k with x_k <= v < x_{k+1}, clamped to [0, n - 2].
    [[nodiscard]] int interval(double v) const;
    [[nodiscard]] const std::vector<double>& knots() const { return x_; }

    template <class T>
    [[nodiscard]] T operator()(const T& v) const {
        const int k = interval(core::value_of(v));
        return piece(v, k, y_[k], y_[k + 1], m_[k], m_[k + 1]);
    }
    /// The cubic of interval k with end values ya, yb and end second derivatives ma, mb.
    template <class T, class Y>
    [[nodiscard]] T piece(const T& v, int k, const Y& ya, const Y& yb, const Y& ma,
                          const Y& mb) const {
        const double h = x_[k + 1] - x_[k];
        const T a = (x_[k + 1] - v) / h;
        const T b = (v - x_[k]) / h;
        return a * ya + b * yb + ((a * a * a - a) * ma + (b * b * b - b) * mb) * (h * h / 6.0);
    }

private:
    std::vector<double> x_, y_, m_;
};

/// Bicubic interpolation as PSOPT's `spline_2d_interpolation`: a natural spline in the second
/// coordinate along each row, then a natural spline in the first coordinate through the row
/// values (the second derivatives of that spline are a fixed linear map of the row values).
class RowColumnSpline {
public:
    RowColumnSpline() = default;
    /// z(i, j) at (x_i, y_j); x and y strictly increasing.
    RowColumnSpline(std::vector<double> x, std::vector<double> y,
                    const std::vector<std::vector<double>>& z);
    template <class T>
    [[nodiscard]] T operator()(const T& xv, const T& yv) const {
        const std::size_t n = rows_.size();
        std::vector<T> col(n);
        for (std::size_t i = 0; i < n; ++i) col[i] = rows_[i](yv);
        const int k = column_.interval(core::value_of(xv));
        T mk = 0.0;
        T mk1 = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            mk = mk + map_[static_cast<std::size_t>(k)][i] * col[i];
            mk1 = mk1 + map_[static_cast<std::size_t>(k) + 1][i] * col[i];
        }
        return column_.piece(xv, k, col[k], col[k + 1], mk, mk1);
    }

private:
    std::vector<NaturalSpline> rows_;       // along y, one per x_i
    NaturalSpline column_;                  // knots x (values unused)
    std::vector<std::vector<double>> map_;  // second derivatives in x = map * column values
};

/// Bryson's F-4 minimum time to climb in PSOPT's form and units (ft, lb, s, rad):
/// /work/shared/reference/min_time_to_climb/README.md; Bryson, Desai & Hoffman 1969.
/// States h_ft, v_ft_s, gamma, w_lb; control alpha; min t_f.
struct MinTimeToClimb {
    /// Atmosphere used for density and speed of sound.
    enum class Atmosphere {
        /// The 8-layer US Standard Atmosphere 1976 in Carmichael's form (isothermal from 11 km):
        /// the problem's definition, and what reproduces PSOPT's documented optimum.
        us1976,
        /// The troposphere law (lapse -6.5 K/km) at every altitude: what PSOPT's climb.cxx computes
        /// as published, whose layer search loop `while (j <= i+1)` never runs; t_f = 318.81 s.
        troposphere_only
    };
    Atmosphere atmosphere = Atmosphere::us1976;  ///< default: the problem's definition

    MinTimeToClimb();
    [[nodiscard]] ProblemInfo info() const;

    /// Density [slug/ft^3] and speed of sound [ft/s] at altitude h [ft] (PSOPT's constants).
    template <class T>
    void air(const T& h_ft, T& rho, T& a) const {
        using std::exp;
        using std::pow;
        using std::sqrt;
        static constexpr std::array<double, 8> htab{0.0,  11.0, 20.0, 32.0,
                                                    47.0, 51.0, 71.0, 84.852};
        static constexpr std::array<double, 8> ttab{288.15, 216.65, 216.65, 228.65,
                                                    270.65, 270.65, 214.65, 186.946};
        static constexpr std::array<double, 8> ptab{1.0,          2.233611e-1,  5.403295e-2,
                                                    8.5666784e-3, 1.0945601e-3, 6.6063531e-4,
                                                    3.9046834e-5, 3.68501e-6};
        static constexpr std::array<double, 8> gtab{-6.5, 0.0, 1.0, 2.8, 0.0, -2.8, -2.0, 0.0};
        constexpr double gmr = 34.163195;
        constexpr double r_earth_km = 6369.0;
        const T alt_km = h_ft * (0.3048 / 1000.0);
        const T hgp = alt_km * r_earth_km / (alt_km + r_earth_km);  // geopotential [km]
        std::size_t i = 0;
        if (atmosphere == Atmosphere::us1976) {
            const double hv = core::value_of(hgp);
            while (i + 1 < htab.size() && hv >= htab[i + 1]) ++i;
        }
        const T dh = hgp - htab[i];
        const T tlocal = ttab[i] + gtab[i] * dh;
        const T theta = tlocal / ttab[0];
        const T delta = gtab[i] == 0.0 ? T(ptab[i] * exp(-gmr * dh / ttab[i]))
                                       : T(ptab[i] * pow(ttab[i] / tlocal, gmr / gtab[i]));
        const T sigma = delta / theta;
        rho = 1.22521 * sigma * (0.062427960841 / 32.174049);
        a = 20.0468 * sqrt(theta * 288.15) / 0.3048;
    }

    template <class T>
    void dynamics(std::span<const T> x, std::span<const T> u, std::span<const T> /*p*/,
                  const T& /*t*/, std::span<T> xdot) const {
        using std::cos;
        using std::sin;
        const T& h = x[0];
        const T& v = x[1];
        const T& gamma = x[2];
        const T& w = x[3];
        const T& alpha = u[0];
        T rho;
        T a;
        air(h, rho, a);
        const T mach = v / a;
        const T cla = cl_alpha_(mach);
        const T cd0 = cd0_(mach);
        const T eta = eta_(mach);
        const T thrust = thrust_(mach, h);
        const T m = w / g0;
        const T q = 0.5 * rho * v * v;
        const T lift = q * area * cla * alpha;
        const T drag = q * area * (cd0 + eta * cla * alpha * alpha);
        const T r = r_earth + h;
        const T r2 = r * r;
        xdot[0] = v * sin(gamma);
        xdot[1] = (thrust * cos(alpha) - drag) / m - mu * sin(gamma) / r2;
        xdot[2] = (thrust * sin(alpha) + lift) / (m * v) + cos(gamma) * (v / r - mu / (v * r2));
        xdot[3] = -thrust / isp;
    }
    template <class T>
    T mayer(std::span<const T> /*x0*/, std::span<const T> /*xf*/, std::span<const T> /*p*/,
            const T& /*t0*/, const T& tf) const {
        return tf;
    }
    /// PSOPT's guess: states linear between the boundary values (w to 0.8 w0), alpha = 0,
    /// t_f = 300 s.
    [[nodiscard]] Guess guess() const;

    /// Thrust [lbf] at (Mach, h [ft]) by the row-column spline.
    template <class T>
    [[nodiscard]] T thrust(const T& mach, const T& h_ft) const {
        return thrust_(mach, h_ft);
    }

    static constexpr double g0 = 32.174;           ///< [ft/s^2]
    static constexpr double area = 530.0;          ///< S [ft^2]
    static constexpr double isp = 1600.0;          ///< [s]
    static constexpr double r_earth = 20902900.0;  ///< [ft]
    static constexpr double mu = 0.14076539e17;    ///< [ft^3/s^2]

private:
    NaturalSpline cl_alpha_, cd0_, eta_;
    RowColumnSpline thrust_;
};

}  // namespace manta::optimal
