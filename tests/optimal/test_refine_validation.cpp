// Error-driven ph mesh refinement (refine.hpp) on problems with published optima, each started
// from a coarse uniform mesh that the user did not adapt to the solution:
//
// 1. Minimum-time double integrator x'' = u, |u| <= 1 from (1, 1) to rest at the origin:
//    bang-bang, t_s = v0 + sqrt(v0^2/2 + x0) = 2.2247449 s, t_f = v0 + 2 sqrt(v0^2/2 + x0)
//    = 3.4494897 s (Kirk, Optimal Control Theory, 1970, ch. 5, minimum-time problems).
// 2. Bryson's F-4 minimum time to climb (Bryson, Desai & Hoffman, J. Aircraft 6(6), 1969) in
//    PSOPT's form and data (/work/shared/reference/min_time_to_climb/README.md): PSOPT documents
//    t_f = 321.11 s, measured 321.1089 s with 30-80 LGL nodes.
// 3. Goddard's rocket (R. H. Goddard, "A method of reaching extreme altitudes", Smithsonian
//    Misc. Collections 71(2), 1919), in the dimensionless form of the COPS 3.0 benchmark
//    (E. D. Dolan, J. J. Moré, T. S. Munson, "Benchmarking optimization software with COPS 3.0",
//    Argonne ANL/MCS-TM-273, 2004, problem 8 "Goddard rocket"; also J. T. Betts, Practical
//    Methods for Optimal Control Using Nonlinear Programming, SIAM, 2nd ed. 2010): maximum
//    final altitude 1.01283; the thrust is full, then on a singular arc, then zero.
//
// The pass tables printed here are those of docs/optimal-control.md.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <span>

#include "manta/optimal/problems.hpp"
#include "manta/optimal/refine.hpp"

namespace {

using namespace manta::optimal;

/// Goddard's rocket, COPS 3.0 constants: h0 = v0 = ... in units of the initial radius, mass and
/// g0. States h, v, m; control T; maximise h(t_f) with m(t_f) = 0.6, t_f free.
struct GoddardRocket {
    static constexpr double h0 = 1.0, v0 = 0.0, m0 = 1.0, g0 = 1.0;
    static constexpr double tc = 3.5, hc = 500.0, vc = 620.0, mc = 0.6;
    static constexpr double c = 0.5;                  // 0.5 sqrt(g0 h0)
    static constexpr double dc = 0.5 * vc * m0 / g0;  // 310
    static constexpr double t_max = tc * g0 * m0;     // 3.5

    [[nodiscard]] ProblemInfo info() const {
        ProblemInfo p;
        p.name = "Goddard rocket";
        p.states = {{"h", h0, 1.1, 1.0}, {"v", 0.0, 1.0, 0.1}, {"m", mc * m0, m0, 1.0}};
        p.controls = {{"T", 0.0, t_max, t_max}};
        p.initial_states = {fixed(h0), fixed(v0), fixed(m0)};
        p.final_states = {{h0, 1.1}, {0.0, 1.0}, fixed(mc * m0)};
        p.final_time = {0.05, 1.0};
        p.time_scale = 0.2;
        p.objective_scale = 1.0;
        return p;
    }
    template <class T>
    void dynamics(std::span<const T> x, std::span<const T> u, std::span<const T> /*p*/,
                  const T& /*t*/, std::span<T> xdot) const {
        using std::exp;
        const T& h = x[0];
        const T& v = x[1];
        const T& m = x[2];
        const T drag = dc * v * v * exp(-hc * (h - h0) / h0);
        const T grav = g0 * (h0 / h) * (h0 / h);
        xdot[0] = v;
        xdot[1] = (u[0] - drag) / m - grav;
        xdot[2] = -u[0] / c;
    }
    template <class T>
    T mayer(std::span<const T> /*x0*/, std::span<const T> xf, std::span<const T> /*p*/,
            const T& /*t0*/, const T& /*tf*/) const {
        return -xf[0];
    }
    /// COPS's guess: h = 1, v = s (1 - s), m linear to m_f, T = T_max / 2 (s = t / t_f).
    [[nodiscard]] Guess guess(double tf) const {
        const int n = 11;
        std::vector<double> t(n);
        Eigen::MatrixXd X(n, 3), U(n, 1);
        for (int i = 0; i < n; ++i) {
            const double s = static_cast<double>(i) / (n - 1);
            t[i] = s * tf;
            X.row(i) << 1.0, s * (1.0 - s), (mc - 1.0) * s + 1.0;
            U(i, 0) = 0.5 * t_max;
        }
        return Guess::from_history(t, X, U);
    }
};

/// No part of [0, 1] has fewer points per unit time in a later pass than in the first mesh
/// (fixed breaks).
void expect_never_coarser(const AdaptiveSolution& r) {
    const Mesh& user = r.passes.front().mesh;
    for (const RefinementPass& p : r.passes) {
        for (int q = 0; q < p.mesh.n_segments(); ++q) {
            const double mid = 0.5 * (p.mesh.breaks[q] + p.mesh.breaks[q + 1]);
            int k = 0;
            while (k + 1 < user.n_segments() && mid >= user.breaks[k + 1]) ++k;
            EXPECT_GE(p.mesh.nodes[q] / (p.mesh.breaks[q + 1] - p.mesh.breaks[q]),
                      user.nodes[k] / (user.breaks[k + 1] - user.breaks[k]) * (1.0 - 1e-12))
                << "pass " << p.pass << " segment " << q;
        }
    }
}

TEST(RefineValidation, DoubleIntegratorBangBangFromSixPoints) {
    const DoubleIntegrator p;
    const BangBangSolution exact = double_integrator_bang_bang(p.x0, p.v0);
    const auto m = make_model(p);
    RefinementOptions ro;
    const AdaptiveSolution r = solve_adaptive(*m, Mesh::uniform(1, 6), p.guess(), {}, ro);
    std::printf("%s", refinement_report(r).c_str());
    std::printf("t_f error %.3e\n", r.solution.final_time - exact.final_time);
    ASSERT_TRUE(r.solution.converged()) << r.status_text;
    EXPECT_NEAR(r.solution.final_time, exact.final_time, 1e-6);
    expect_never_coarser(r);
}

TEST(RefineValidation, MinTimeToClimbFromTenPoints) {
    const MinTimeToClimb p;
    const auto m = make_model(p);
    // alone, ten points do not resolve the optimum
    const Solution coarse = solve(*m, Mesh::uniform(1, 10), p.guess());
    EXPECT_EQ(coarse.status, SolveStatus::solved_unresolved);
    // default options: the second pass (4 x 4 points) is infeasible from this start; its retry
    // splits into 12-point pieces, as do the later passes
    RefinementOptions ro;
    const AdaptiveSolution r = solve_adaptive(*m, Mesh::uniform(1, 10), p.guess(), {}, ro);
    std::printf("%s", refinement_report(r).c_str());
    std::printf("t_f %.6f s\n", r.solution.final_time);
    ASSERT_TRUE(r.solution.resolved()) << r.status_text;
    EXPECT_EQ(r.status, RefinementStatus::tolerance_met) << r.status_text;
    // within 0.1 % of PSOPT's documented 321.11 s (as test_problems_validation.cpp); the
    // refined optimum, 321.138 s, is 0.03 s above PSOPT's measured 321.1089 s
    // (docs/optimal-control.md, error-driven mesh refinement)
    EXPECT_LT(std::abs(r.solution.final_time - 321.11) / 321.11, 1e-3);
    expect_never_coarser(r);
}

TEST(RefineValidation, GoddardRocketSingularArc) {
    const GoddardRocket p;
    const auto m = make_model(p);
    // N_min 4 splits the singular arc into 4-point segments on which IPOPT ends at lower
    // local optima (1.0092); breaks at the chattering thrust's jumps slow IPOPT down (1849
    // iterations): both off here. The error estimate stays near 4e-4 on the singular arc.
    RefinementOptions ro;
    ro.min_nodes = 6;
    ro.max_nodes = 16;
    ro.breaks_at_jumps = false;
    const AdaptiveSolution r = solve_adaptive(*m, Mesh::uniform(1, 10), p.guess(0.2), {}, ro);
    std::printf("%s", refinement_report(r).c_str());
    std::printf("h_f %.8f\n", -r.solution.objective);
    ASSERT_TRUE(r.solution.converged()) << r.status_text;
    EXPECT_GT(r.solution.n_nodes(), 10);
    EXPECT_NEAR(-r.solution.objective, 1.01283, 1e-5);
    expect_never_coarser(r);
}

}  // namespace
