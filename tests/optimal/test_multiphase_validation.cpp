// Multi-phase problems with published or analytic optima: the two-phase Schwartz problem (a path
// constraint and a state bound in the first phase only, a wider control range in the second)
// and a two-stage rocket whose linkage drops the first stage's structure (a mass jump), with
// different engines in the two phases, against the classical optimal-staging solution.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include "manta/optimal/model.hpp"
#include "manta/optimal/multiphase.hpp"
#include "manta/optimal/solve.hpp"

namespace {

using namespace manta::optimal;

/// The two-phase Schwartz problem (A. L. Schwartz, "Theory and implementation of numerical
/// methods based on Runge-Kutta integration for solving optimal control problems", PhD thesis,
/// U. C. Berkeley, 1996; as in PROPT's and PSOPT's example sets, PSOPT's
/// examples/twophase_schwartz): x1' = x2, x2' = u - 0.1 (1 + 2 x1²) x2 from x(0) = (1, 1);
/// phase 1 on [0, 1] with |u| <= 1, x2 >= -0.8 and the elliptic obstacle
/// 1 - 9 (x1 - 1)² - ((x2 - 0.4)/0.3)² <= 0; phase 2 on [1, 2.9] with |u| <= 50, x2 >= -10;
/// min 5 (x1(2.9)² + x2(2.9)²). PSOPT reports an optimal cost of 4.634554e-15 (its
/// twophsc.txt): the second phase reaches the origin, J* = 0.
struct Schwartz {
    int phase = 1;
    [[nodiscard]] ProblemInfo info() const {
        ProblemInfo p;
        p.name = phase == 1 ? "Schwartz phase 1" : "Schwartz phase 2";
        p.states = {{"x1", -20.0, 10.0, 1.0}, {"x2", phase == 1 ? -0.8 : -10.0, 10.0, 1.0}};
        p.controls = {{"u", phase == 1 ? -1.0 : -50.0, phase == 1 ? 1.0 : 50.0, 1.0}};
        if (phase == 1) {
            p.path = {{"ellipse", -100.0, 0.0, 1.0}};
            p.initial_time = fixed(0.0);
            p.final_time = fixed(1.0);
            p.set_initial("x1", 1.0);
            p.set_initial("x2", 1.0);
        } else {
            p.initial_time = fixed(1.0);
            p.final_time = fixed(2.9);
            p.objective_scale = 1.0;
        }
        return p;
    }
    template <class T>
    void dynamics(std::span<const T> x, std::span<const T> u, std::span<const T> /*p*/,
                  const T& /*t*/, std::span<T> xdot) const {
        xdot[0] = x[1];
        xdot[1] = u[0] - 0.1 * (1.0 + 2.0 * x[0] * x[0]) * x[1];
    }
    template <class T>
    void path(std::span<const T> x, std::span<const T> /*u*/, std::span<const T> /*p*/,
              const T& /*t*/, std::span<T> g) const {
        const T a = x[0] - 1.0;
        const T b = (x[1] - 0.4) / 0.3;
        g[0] = 1.0 - 9.0 * a * a - b * b;
    }
};
struct SchwartzEnd : Schwartz {
    template <class T>
    T mayer(std::span<const T> /*x0*/, std::span<const T> xf, std::span<const T> /*p*/,
            const T& /*t0*/, const T& /*tf*/) const {
        return 5.0 * (xf[0] * xf[0] + xf[1] * xf[1]);
    }
};

TEST(MultiPhaseValidation, TwoPhaseSchwartz) {
    Schwartz one;
    SchwartzEnd two;
    two.phase = 2;
    // PSOPT's guess: x = (1, 1), u = 0 in both phases
    Eigen::VectorXd x(2), u(1);
    x << 1.0, 1.0;
    u << 0.0;
    MultiPhaseProblem mp;
    mp.name = "two-phase Schwartz";
    mp.phases = {{make_model(one), Mesh::uniform(4, 10), Guess::linear(0.0, 1.0, x, x, u, u)},
                 {make_model(two), Mesh::uniform(4, 10), Guess::linear(1.0, 2.9, x, x, u, u)}};
    EXPECT_LT(check_derivatives(mp).hessian_error, 2e-6);
    const MultiPhaseSolution s = solve(mp);
    std::printf(
        "two-phase Schwartz: J %.3e, %d IPOPT iterations, %.3f s CPU, resim %.2e, "
        "x(1) = (%.6f, %.6f)\n",
        s.objective, s.iterations, s.cpu_time, s.max_resimulation_error(),
        s.phase(0).final_state("x1"), s.phase(0).final_state("x2"));
    ASSERT_TRUE(s.resolved()) << s.status_text;
    EXPECT_LT(s.objective, 1e-8);  // PSOPT: 4.6e-15
    EXPECT_GE(s.objective, 0.0);
    EXPECT_LT(s.max_violation, 1e-8);
    // the first phase's own constraints, at its nodes
    for (const auto& seg : s.phase(0).segments) {
        for (Eigen::Index i = 0; i < seg.path.rows(); ++i) EXPECT_LE(seg.path(i, 0), 1e-8);
        for (Eigen::Index i = 0; i < seg.states.rows(); ++i)
            EXPECT_GE(seg.states(i, 1), -0.8 - 1e-8);
    }
    EXPECT_NEAR(s.phase(1).initial_state("x1"), s.phase(0).final_state("x1"), 1e-10);
    EXPECT_NEAR(s.phase(1).initial_state("x2"), s.phase(0).final_state("x2"), 1e-10);
    EXPECT_LT(s.max_resimulation_error(), 1e-3);
}

/// A two-stage rocket in vertical flight under constant gravity g: each stage burns at a
/// throttled mass flow u in [0, u_max] with exhaust speed c (v' = c u / m - g, m' = -u) and has
/// a structural mass ε/(1-ε) times its propellant; at staging the first stage's structure is
/// dropped (the linkage: m jumps), and the second stage must end with its own structure and the
/// payload P. Maximise the final speed. For given propellant masses p_1, p_2 the speed is
/// Tsiolkovsky's Σ c_i ln(m_i0 / m_if) less the gravity loss g Σ t_i, least at full flow
/// (t_i = p_i / u_max,i); the payload fixes p_2 from p_1, so the optimum is the maximum of one
/// function of p_1: the classical optimal-staging problem (H. D. Curtis, Orbital Mechanics for
/// Engineering Students, 2005, sec. 11.6; without gravity loss and with equal stages it gives
/// equal mass ratios n = 1 / (ε + (1 - ε) √(P / M0))).
struct Stage {
    int stage = 1;
    double c = 2943.0;     // exhaust speed [m/s]
    double u_max = 800.0;  // mass flow [kg/s]
    double g = 9.81;
    double M0 = 1e5, P = 5e3, k = 0.1 / 0.9;
    [[nodiscard]] ProblemInfo info() const {
        ProblemInfo p;
        p.name = stage == 1 ? "first stage" : "second stage";
        p.states = {{"v", -1e3, 2e4, 1e4}, {"m", 1e3, M0, 1e5}};
        p.controls = {{"u", 0.0, u_max, u_max}};
        if (stage == 1) {
            p.initial_time = fixed(0.0);
            p.set_initial("v", 0.0);
            p.set_initial("m", M0);
        } else {
            p.initial_time = {1.0, 1e3};
            p.maximise = true;
            p.events = {{"payload and structure left", 0.0, 0.0, 1e3}};
        }
        p.final_time = {1.0, 1e3};
        p.time_scale = 100.0;
        return p;
    }
    template <class T>
    void dynamics(std::span<const T> x, std::span<const T> u, std::span<const T> /*p*/,
                  const T& /*t*/, std::span<T> xdot) const {
        xdot[0] = c * u[0] / x[1] - g;
        xdot[1] = -u[0];
    }
    template <class T>
    void events(std::span<const T> x0, std::span<const T> xf, std::span<const T> /*p*/,
                const T& /*t0*/, const T& /*tf*/, std::span<T> e) const {
        e[0] = xf[1] - k * (x0[1] - xf[1]) - P;
    }
};
struct FinalSpeed : Stage {
    template <class T>
    T mayer(std::span<const T> /*x0*/, std::span<const T> xf, std::span<const T> /*p*/,
            const T& /*t0*/, const T& /*tf*/) const {
        return xf[0];
    }
};

/// Final speed as a function of the first stage's propellant p1 (see Stage).
double staged_speed(const Stage& a, const Stage& b, double p1) {
    const double m2 = a.M0 - (1.0 + a.k) * p1;
    const double p2 = (m2 - a.P) / (1.0 + a.k);
    return a.c * std::log(a.M0 / (a.M0 - p1)) + b.c * std::log(m2 / (m2 - p2)) -
           a.g * (p1 / a.u_max + p2 / b.u_max);
}

TEST(MultiPhaseValidation, TwoStageRocketWithAStructureDrop) {
    Stage one;
    FinalSpeed two;
    two.stage = 2;
    two.c = 3434.0;  // a vacuum engine on the upper stage
    two.u_max = 150.0;
    // the reference: golden-section maximum of staged_speed over p1
    double lo = 1.0, hi = (one.M0 - one.P) / (1.0 + one.k) - 1.0;
    const double r = 0.5 * (std::sqrt(5.0) - 1.0);
    for (int i = 0; i < 200; ++i) {
        const double a = hi - r * (hi - lo), b = lo + r * (hi - lo);
        if (staged_speed(one, two, a) > staged_speed(one, two, b)) {
            hi = b;
        } else {
            lo = a;
        }
    }
    const double p1 = 0.5 * (lo + hi);
    const double v_best = staged_speed(one, two, p1);
    const double t1 = p1 / one.u_max;
    const double m2 = one.M0 - (1.0 + one.k) * p1;
    const double t2 = (m2 - one.P) / (1.0 + one.k) / two.u_max;

    const double k = one.k, M0 = one.M0;
    MultiPhaseProblem mp;
    mp.name = "two-stage rocket";
    mp.phases = {{make_model(one), Mesh::uniform(1, 20),
                  Guess::linear(one.info(), 0.0, 60.0,
                                {{"v", 0.0, 2000.0}, {"m", 1e5, 5e4}, {"u", 800.0, 800.0}})},
                 {make_model(two), Mesh::uniform(1, 20),
                  Guess::linear(two.info(), 60.0, 160.0,
                                {{"v", 2000.0, 5000.0}, {"m", 4e4, 8e3}, {"u", 150.0, 150.0}})}};
    // v continuous; m drops the first stage's structure k (M0 - m_f)
    mp.links = {
        {make_link(2, 2, {{"v continuity", 0.0, 0.0, 1e3}, {"structure dropped", 0.0, 0.0, 1e4}},
                   [k, M0](auto xf, auto x0, auto /*p*/, auto l) {
                       l[0] = x0[0] - xf[0];
                       l[1] = x0[1] - (xf[1] - k * (M0 - xf[1]));
                   }),
         true}};
    const DerivativeCheck dc = check_derivatives(mp);
    EXPECT_LT(dc.jacobian_error, 2e-6);
    EXPECT_LT(dc.hessian_error, 2e-6);
    const MultiPhaseSolution s = solve(mp);
    std::printf(
        "two-stage rocket: v_f %.6f m/s (reference %.6f), staging at %.6f s (%.6f), burn "
        "out %.6f s (%.6f), %d IPOPT iterations, %.3f s CPU, resim %.2e\n",
        s.objective, v_best, s.phase(0).final_time, t1, s.phase(1).final_time, t1 + t2,
        s.iterations, s.cpu_time, s.max_resimulation_error());
    ASSERT_TRUE(s.resolved()) << s.status_text;
    // 20 points per phase: +1.3e-5 m/s, as with 30 (the end nodes' control converges from below,
    // 12 points: -3.6e-3 m/s); the excess is IPOPT's bound relaxation (bound_relax_factor 1e-8
    // on u_max: g t 1e-8 = 1.6e-5 m/s)
    EXPECT_NEAR(s.objective, v_best, 1e-7 * v_best);
    EXPECT_NEAR(s.phase(0).final_time, t1, 1e-5 * t1);
    EXPECT_NEAR(s.phase(1).final_time, t1 + t2, 1e-5 * (t1 + t2));
    // the jump: the mass after staging is the mass at burn-out less the stage's structure
    const double mf = s.phase(0).final_state("m");
    EXPECT_NEAR(s.phase(1).initial_state("m"), mf - k * (M0 - mf), 1e-6);
    EXPECT_NEAR(s.phase(1).initial_state("m"), m2, 1e-4 * m2);
    const double m20 = s.phase(1).initial_state("m"), m2f = s.phase(1).final_state("m");
    EXPECT_NEAR(m2f, one.P + k * (m20 - m2f), 1e-6);
    EXPECT_LT(s.max_resimulation_error(), 1e-6);
    // full flow throughout
    for (const auto& ph : s.phases) {
        for (const auto& seg : ph.segments) {
            for (Eigen::Index i = 0; i < seg.controls.rows(); ++i)
                EXPECT_NEAR(seg.controls(i, 0), ph.info.controls[0].upper,
                            1e-4 * ph.info.controls[0].upper);
        }
    }
}

}  // namespace
