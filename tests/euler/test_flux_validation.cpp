// Shock-tube validation of the Roe and HLLC fluxes: a first-order 1-D finite-volume solution
// (the fluxes with n along x) against the exact solution of the Riemann problem.
//
// References:
// - G. A. Sod, "A survey of several finite difference methods for systems of nonlinear
//   hyperbolic conservation laws", J. Comput. Phys. 27 (1978) 1-31.
// - E. F. Toro, Riemann Solvers and Numerical Methods for Fluid Dynamics, 3rd ed., Springer 2009:
//   ch. 4 (exact Riemann solver), Table 4.1 (tests 1-5, gamma = 1.4), Table 4.3 (exact
//   star-region values, compared here with the exact solver written for this test), and the
//   sonic-rarefaction variant of Sod's problem used in chs. 6-11 (u_L = 0.75, x0 = 0.3,
//   t = 0.2) on which Roe's scheme without an entropy fix forms an expansion shock.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "manta/euler/flux.hpp"

namespace {

using namespace manta::euler;

constexpr double gam = 1.4;

/// 1-D primitive state.
struct State {
    double rho, u, p;
};

// ------------------------------------------------------------------ exact Riemann solver

/// Exact solution of the 1-D Riemann problem for an ideal gas (Toro 2009, ch. 4): the star
/// pressure from Newton's method on the pressure function, then sampling along x / t.
class ExactRiemann {
public:
    ExactRiemann(State L, State R) : L_(L), R_(R) {
        cL_ = std::sqrt(gam * L.p / L.rho);
        cR_ = std::sqrt(gam * R.p / R.rho);
        // Start from the two-rarefaction approximation (exact when both waves are
        // rarefactions), then Newton.
        const double z = (gam - 1) / (2 * gam);
        double p = std::pow((cL_ + cR_ - 0.5 * (gam - 1) * (R.u - L.u)) /
                                (cL_ / std::pow(L.p, z) + cR_ / std::pow(R.p, z)),
                            1 / z);
        for (int it = 0; it < 100; ++it) {
            double fl, dfl, fr, dfr;
            f(p, L_, cL_, fl, dfl);
            f(p, R_, cR_, fr, dfr);
            const double dp = (fl + fr + R.u - L.u) / (dfl + dfr);
            p = std::max(p - dp, 1e-14);
            if (std::abs(dp) < 1e-15 * p) break;
        }
        double fl, dfl, fr, dfr;
        f(p, L_, cL_, fl, dfl);
        f(p, R_, cR_, fr, dfr);
        p_star = p;
        u_star = 0.5 * (L.u + R.u) + 0.5 * (fr - fl);
        rho_star_L = star_density(L_);
        rho_star_R = star_density(R_);
    }

    double p_star, u_star, rho_star_L, rho_star_R;

    /// The state at x / t = xi.
    [[nodiscard]] State sample(double xi) const {
        const bool left = xi <= u_star;
        const State& K = left ? L_ : R_;
        const double c = left ? cL_ : cR_;
        const double s = left ? -1.0 : 1.0;  // direction of the K wave
        const State star{left ? rho_star_L : rho_star_R, u_star, p_star};
        if (p_star > K.p) {  // shock
            const double S =
                K.u +
                s * c * std::sqrt((gam + 1) / (2 * gam) * p_star / K.p + (gam - 1) / (2 * gam));
            return s * (xi - S) >= 0 ? K : star;
        }
        // Rarefaction: head, tail, and the fan between.
        const double head = K.u + s * c;
        const double tail = u_star + s * c * std::pow(p_star / K.p, (gam - 1) / (2 * gam));
        if (s * (xi - head) >= 0) return K;
        if (s * (xi - tail) <= 0) return star;
        const double cf = 2 / (gam + 1) * (c - s * 0.5 * (gam - 1) * (K.u - xi));
        const double uf = 2 / (gam + 1) * (-s * c + 0.5 * (gam - 1) * K.u + xi);
        const double r = cf / c;
        return {K.rho * std::pow(r, 2 / (gam - 1)), uf, K.p * std::pow(r, 2 * gam / (gam - 1))};
    }

    /// Speeds x / t of the ends of the star region: the left wave's tail (rarefaction) or the
    /// left shock, and the same on the right.
    [[nodiscard]] double star_left_end() const { return star_end(L_, cL_, -1.0); }
    [[nodiscard]] double star_right_end() const { return star_end(R_, cR_, 1.0); }

private:
    State L_, R_;
    double cL_, cR_;

    /// Toro's pressure function f_K(p) and its derivative (eqs. 4.6-4.7, 4.37).
    static void f(double p, const State& K, double c, double& value, double& deriv) {
        if (p > K.p) {
            const double A = 2 / ((gam + 1) * K.rho), B = (gam - 1) / (gam + 1) * K.p;
            const double q = std::sqrt(A / (p + B));
            value = (p - K.p) * q;
            deriv = q * (1 - 0.5 * (p - K.p) / (B + p));
        } else {
            const double r = p / K.p;
            value = 2 * c / (gam - 1) * (std::pow(r, (gam - 1) / (2 * gam)) - 1);
            deriv = 1 / (K.rho * c) * std::pow(r, -(gam + 1) / (2 * gam));
        }
    }
    [[nodiscard]] double star_end(const State& K, double c, double s) const {
        if (p_star > K.p)
            return K.u +
                   s * c * std::sqrt((gam + 1) / (2 * gam) * p_star / K.p + (gam - 1) / (2 * gam));
        return u_star + s * c * std::pow(p_star / K.p, (gam - 1) / (2 * gam));
    }
    [[nodiscard]] double star_density(const State& K) const {
        const double r = p_star / K.p;
        if (p_star > K.p) {
            const double g = (gam - 1) / (gam + 1);
            return K.rho * (r + g) / (g * r + 1);
        }
        return K.rho * std::pow(r, 1 / gam);
    }
};

// ------------------------------------------------------------- first-order finite volumes

Vec5 to_primitive(const State& s) {
    Vec5 W;
    W << s.rho, s.u, 0.0, 0.0, s.p;
    return W;
}

/// First-order Godunov-type finite-volume solution on [0, 1] with N cells, the discontinuity at
/// x0, forward Euler with CFL 0.9, transmissive ends; returns the primitive cell states.
std::vector<Vec5> shock_tube(State L, State R, double x0, double t_end, int N,
                             const FluxOptions& o) {
    const double dx = 1.0 / N;
    std::vector<Vec5> U(N);
    for (int i = 0; i < N; ++i) U[i] = conservative(to_primitive((i + 0.5) * dx < x0 ? L : R), gam);
    std::vector<Vec5> W(N), F(N + 1);
    const Vec3 n(1.0, 0.0, 0.0);
    double t = 0.0;
    while (t < t_end) {
        double smax = 0.0;
        for (int i = 0; i < N; ++i) {
            W[i] = primitive(U[i], gam);
            smax = std::max(smax, spectral_radius(W[i], n, gam));
        }
        const double dt = std::min(0.9 * dx / smax, t_end - t);
        for (int f = 0; f <= N; ++f)
            F[f] = numerical_flux(W[std::max(f - 1, 0)], W[std::min(f, N - 1)], n, gam, o);
        for (int i = 0; i < N; ++i) U[i] -= dt / dx * (F[i + 1] - F[i]);
        t += dt;
    }
    for (int i = 0; i < N; ++i) W[i] = primitive(U[i], gam);
    return W;
}

/// L1 norm of the density error, (1/N) sum |rho_i - rho(x_i)|.
double density_l1(const std::vector<Vec5>& W, const ExactRiemann& ex, double x0, double t) {
    const int N = static_cast<int>(W.size());
    double e = 0.0;
    for (int i = 0; i < N; ++i) e += std::abs(W[i][0] - ex.sample(((i + 0.5) / N - x0) / t).rho);
    return e / N;
}

/// Mean of component k over the cells whose centres lie in the middle half of [a, b].
double plateau(const std::vector<Vec5>& W, int k, double a, double b) {
    const int N = static_cast<int>(W.size());
    double sum = 0.0;
    int count = 0;
    for (int i = 0; i < N; ++i) {
        const double x = (i + 0.5) / N;
        if (x > a + 0.25 * (b - a) && x < b - 0.25 * (b - a)) {
            sum += W[i][k];
            ++count;
        }
    }
    return sum / count;
}

struct Case {
    const char* name;
    State L, R;
    double x0, t;
    // Toro 2009, Table 4.3: exact p*, u*, rho*L, rho*R.
    double p_star, u_star, rho_L, rho_R;
};

// Toro 2009, Table 4.1 (tests 1-3; test 1 is Sod's problem), times as in Toro's ch. 4 figures.
const Case cases[] = {
    {"Sod (Toro test 1)",
     {1.0, 0.0, 1.0},
     {0.125, 0.0, 0.1},
     0.5,
     0.25,
     0.30313,
     0.92745,
     0.42632,
     0.26557},
    {"123 problem (Toro test 2)",
     {1.0, -2.0, 0.4},
     {1.0, 2.0, 0.4},
     0.5,
     0.15,
     0.00189,
     0.0,
     0.02185,
     0.02185},
    {"blast wave left (Toro test 3)",
     {1.0, 0.0, 1000.0},
     {1.0, 0.0, 0.01},
     0.5,
     0.012,
     460.894,
     19.5975,
     0.57506,
     5.99924},
};

/// Relative deviation |a - b| / max(|b|, floor).
double rel(double a, double b, double floor = 1e-12) {
    return std::abs(a - b) / std::max(std::abs(b), floor);
}

/// Half a unit in the last of the 6 significant (or 5 decimal) digits Toro's table prints.
double table_tolerance(double v) {
    if (std::abs(v) < 1.0) return 0.5e-5;
    return 0.5 * std::pow(10.0, std::floor(std::log10(std::abs(v))) - 5);
}

TEST(EulerShockTube, ExactSolverMatchesToroTable43) {
    for (const Case& c : cases) {
        const ExactRiemann ex(c.L, c.R);
        EXPECT_NEAR(ex.p_star, c.p_star, table_tolerance(c.p_star)) << c.name;
        EXPECT_NEAR(ex.u_star, c.u_star, table_tolerance(c.u_star)) << c.name;
        EXPECT_NEAR(ex.rho_star_L, c.rho_L, table_tolerance(c.rho_L)) << c.name;
        EXPECT_NEAR(ex.rho_star_R, c.rho_R, table_tolerance(c.rho_R)) << c.name;
    }
}

/// Largest density jump between neighbouring cells whose interface lies in [a, b], for the
/// numerical (first) and the exact solution sampled at the cell centres (second).
std::pair<double, double> largest_jump(const std::vector<Vec5>& W, const ExactRiemann& ex,
                                       double x0, double t, double a, double b) {
    const int N = static_cast<int>(W.size());
    double num = 0.0, exact = 0.0;
    for (int i = 0; i + 1 < N; ++i) {
        const double x = (i + 1.0) / N;
        if (x < a || x > b) continue;
        num = std::max(num, std::abs(W[i + 1][0] - W[i][0]));
        exact = std::max(exact, std::abs(ex.sample(((i + 1.5) / N - x0) / t).rho -
                                         ex.sample(((i + 0.5) / N - x0) / t).rho));
    }
    return {num, exact};
}

/// Plateau tolerances at N = 800 (relative): p*, u*, rho*L, rho*R; negative: not checked.
struct Tolerances {
    double p, u, rho_L, rho_R;
};

void check_shock_tube(const Case& c, const FluxOptions& o, const Tolerances& tol) {
    const ExactRiemann ex(c.L, c.R);
    const double a = c.x0 + ex.star_left_end() * c.t;
    const double m = c.x0 + ex.u_star * c.t;
    const double b = c.x0 + ex.star_right_end() * c.t;
    const char* scheme = o.scheme == FluxScheme::roe ? "Roe" : "HLLC";
    double previous = 0.0;
    for (const int N : {100, 200, 400, 800}) {
        const std::vector<Vec5> W = shock_tube(c.L, c.R, c.x0, c.t, N, o);
        for (const Vec5& w : W) {
            ASSERT_TRUE(w.allFinite() && w[0] > 0 && w[4] > 0) << c.name << " " << scheme;
        }
        const double e = density_l1(W, ex, c.x0, c.t);
        const double p = plateau(W, 4, a, b), u = plateau(W, 1, a, b);
        const double rho_L = plateau(W, 0, a, m), rho_R = plateau(W, 0, m, b);
        std::printf("%-30s %-4s N %3d  L1(rho) %.5f  p* %.6g  u* %.6g  rho*L %.6g  rho*R %.6g\n",
                    c.name, scheme, N, e, p, u, rho_L, rho_R);
        if (N > 100) {
            EXPECT_LT(e, 0.8 * previous) << c.name << " " << scheme << " N " << N;
        }
        previous = e;
        if (N == 800) {
            EXPECT_LT(rel(p, ex.p_star), tol.p) << c.name << " " << scheme;
            if (tol.u > 0) {
                EXPECT_LT(rel(u, ex.u_star), tol.u) << c.name << " " << scheme;
            }
            EXPECT_LT(rel(rho_L, ex.rho_star_L), tol.rho_L) << c.name << " " << scheme;
            if (tol.rho_R > 0) {
                EXPECT_LT(rel(rho_R, ex.rho_star_R), tol.rho_R) << c.name;
            }
        }
    }
}

// Sod's problem (Toro test 1): first order on 800 cells gets the star pressure and velocity to
// 1e-3 (measured: 2e-5 and 4e-5) and both star densities to 0.5 % (0.2 %, 0.01 %); the density
// L1 error falls by at least 20 % per mesh doubling (measured: 35 %).
TEST(EulerShockTube, Sod) {
    for (const FluxScheme s : {FluxScheme::roe, FluxScheme::hllc})
        check_shock_tube(cases[0], {s, 0.05}, {1e-3, 1e-3, 5e-3, 5e-3});
}

// Toro's test 3 (strong shock, pressure ratio 1e5): p* to 0.2 % (measured 0.06 %), u* to 0.5 %,
// rho*L to 0.5 %; the thin post-shock shell (rho*R) is not resolved at first order on 800 cells
// (6.6 % low) and only enters through the L1 error.
TEST(EulerShockTube, ToroTest3) {
    for (const FluxScheme s : {FluxScheme::roe, FluxScheme::hllc})
        check_shock_tube(cases[2], {s, 0.05}, {2e-3, 5e-3, 5e-3, -1});
}

// Toro's test 2 (the "123 problem", two strong rarefactions leaving a near vacuum): HLLC with
// Einfeldt's wave speeds keeps density and pressure positive (Einfeldt, Munz, Roe & Sjogreen,
// J. Comput. Phys. 92 (1991) 273-295) and converges; its star pressure 0.00189 is approached
// slowly at first order (0.0031 on 800 cells), so only the L1 error and positivity are checked
// tightly. Roe's linearisation is not positivity-preserving: its linearised star density
// 1 - rho c du / (2 c^2) < 0 here, and the scheme breaks down (as Einfeldt et al. show), so it
// is not run.
TEST(EulerShockTube, Toro123Problem) {
    check_shock_tube(cases[1], {FluxScheme::hllc, 0.05}, {1.0, -1, 0.25, 0.25});
}

// Sonic rarefaction: Sod's problem with u_L = 0.75 (Toro 2009, test 1 of chs. 6-11, x0 = 0.3,
// t = 0.2), whose left rarefaction fan contains the sonic point (at x = 0.3). Without an
// entropy fix Roe's scheme keeps an expansion shock there: a density jump of 0.12 across one
// cell whatever the mesh. The fix must remove it: the largest density jump between neighbours
// inside the fan must shrink with the mesh and, on 800 cells, be no larger than 1.5 times the
// exact solution's (measured: 0.92 times with the default width 0.05). The same check applied
// to the unfixed scheme must fail (shown here, so the test can fail).
TEST(EulerShockTube, SonicRarefactionEntropyFix) {
    const State L{1.0, 0.75, 1.0}, R{0.125, 0.0, 0.1};
    const double x0 = 0.3, t = 0.2;
    const ExactRiemann ex(L, R);
    const double a = x0 + (L.u - std::sqrt(gam * L.p / L.rho)) * t - 0.02;
    const double b = x0 + ex.star_left_end() * t + 0.02;
    auto jumps = [&](const FluxOptions& o, int N) {
        return largest_jump(shock_tube(L, R, x0, t, N, o), ex, x0, t, a, b);
    };
    const FluxOptions fixed{FluxScheme::roe, FluxOptions{}.entropy_fix};
    const auto [j200, e200] = jumps(fixed, 200);
    const auto [j800, e800] = jumps(fixed, 800);
    std::printf(
        "sonic rarefaction, Roe, fix %.2f: largest jump %.4f (N 200), %.4f (N 800); exact "
        "%.4f, %.4f\n",
        fixed.entropy_fix, j200, j800, e200, e800);
    EXPECT_LT(j800, 0.5 * j200);
    EXPECT_LT(j800, 1.5 * e800);

    const FluxOptions unfixed{FluxScheme::roe, 0.0};
    const auto [u200, ue200] = jumps(unfixed, 200);
    const auto [u800, ue800] = jumps(unfixed, 800);
    std::printf("sonic rarefaction, Roe, no fix: largest jump %.4f (N 200), %.4f (N 800)\n", u200,
                u800);
    EXPECT_GT(u800, 0.8 * u200);  // an expansion shock does not shrink with the mesh
    EXPECT_GT(u800, 10 * ue800);

    const auto [h800, he800] = jumps({FluxScheme::hllc, 0.0}, 800);
    EXPECT_LT(h800, 2.0 * he800);  // HLLC needs no fix (measured 1.43)
}

}  // namespace
