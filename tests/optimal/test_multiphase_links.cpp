// Multi-phase problems beyond a chain of consecutive phases: links between any two phases
// (branching, out of order), linkage functions of the phases' end times, a Mayer term of
// several phases' ends, parameters of a phase no link enters, the failure CSV of the multi-phase
// solve, and the one-line errors of bad links and cross-phase Mayer terms. Analytic optima
// throughout; derivative checks against finite differences.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "drift_model.hpp"
#include "manta/core/error.hpp"
#include "manta/optimal/model.hpp"
#include "manta/optimal/multiphase.hpp"
#include "manta/optimal/solve.hpp"

namespace {

using namespace manta::optimal;
namespace fs = std::filesystem;

/// x' = u on [t0, t0 + 1], min ∫u²/2 dt; x(t0) fixed when `start` is set, x(tf) when `end` is.
struct Walk {
    std::string name;
    double t0 = 0.0;
    bool has_start = false, has_end = false;
    double start = 0.0, end = 0.0;
    [[nodiscard]] ProblemInfo info() const {
        ProblemInfo p;
        p.name = name;
        p.states = {{"x", -10.0, 10.0, 1.0}};
        p.controls = {{"u", -20.0, 20.0, 1.0}};
        p.initial_time = fixed(t0);
        p.final_time = fixed(t0 + 1.0);
        if (has_start) p.set_initial("x", start);
        if (has_end) p.set_final("x", end);
        return p;
    }
    template <class T>
    void dynamics(std::span<const T> /*x*/, std::span<const T> u, std::span<const T> /*p*/,
                  const T& /*t*/, std::span<T> xdot) const {
        xdot[0] = u[0];
    }
    template <class T>
    T lagrange(std::span<const T> /*x*/, std::span<const T> u, std::span<const T> /*p*/,
               const T& /*t*/) const {
        return 0.5 * u[0] * u[0];
    }
};

template <class W>
Phase walk_phase(const W& w, int nodes = 5) {
    Eigen::VectorXd x(1), u(1);
    x << 0.0;
    u << 0.0;
    return {make_model(w), Mesh::uniform(1, nodes), Guess::linear(w.t0, w.t0 + 1.0, x, x, u, u)};
}

/// A branch: phase 0 from x(0) = 0 to a free x(1) = c, then two phases on [1, 2] both starting
/// at c (links 0 -> 1 and 0 -> 2), ending at x(2) = a and x(2) = b. Every leg is a straight
/// line (u constant, its cost (Δx)²/2), so J(c) = c²/2 + (a - c)²/2 + (b - c)²/2 is least at
/// c = (a + b)/3.
MultiPhaseProblem branch(double a, double b) {
    Walk trunk;
    trunk.name = "trunk";
    trunk.has_start = true;
    Walk left;
    left.name = "left";
    left.t0 = 1.0;
    left.has_end = true;
    left.end = a;
    Walk right = left;
    right.name = "right";
    right.end = b;
    MultiPhaseProblem mp;
    mp.name = "branch";
    mp.phases = {walk_phase(trunk), walk_phase(left), walk_phase(right)};
    mp.links = {{nullptr, true, 0, 1}, {nullptr, true, 0, 2}};
    return mp;
}

TEST(MultiPhaseLinks, BranchingFromOnePhase) {
    const double a = 1.0, b = 3.0, c = (a + b) / 3.0;
    const MultiPhaseSolution s = solve(branch(a, b));
    std::printf("branch: x(1) %.12f (4/3), J %.12f (7/3), %d IPOPT iterations\n",
                s.phase(0).final_state("x"), s.objective, s.iterations);
    ASSERT_TRUE(s.resolved()) << s.status_text;
    EXPECT_NEAR(s.phase(0).final_state("x"), c, 1e-9);
    EXPECT_NEAR(s.phase(1).initial_state("x"), c, 1e-9);
    EXPECT_NEAR(s.phase(2).initial_state("x"), c, 1e-9);
    EXPECT_NEAR(s.objective, 0.5 * (c * c + (a - c) * (a - c) + (b - c) * (b - c)), 1e-9);
    EXPECT_NEAR(s.phase(2).control(1.5, "u"), b - c, 1e-9);
    ASSERT_EQ(s.links.size(), 2U);
    EXPECT_EQ(s.links[1].size(), 1);  // continuity of x (the times are fixed on both sides)
    EXPECT_LT(s.max_link_violation, 1e-10);
    // the chain 0 -> 1 only (phase 2 unlinked, free to start anywhere): c = a/2 instead
    MultiPhaseProblem chain = branch(a, b);
    chain.links = {{nullptr, true, 0, 1}};
    const MultiPhaseSolution q = solve(chain);
    ASSERT_TRUE(q.resolved()) << q.status_text;
    EXPECT_NEAR(q.phase(0).final_state("x"), a / 2.0, 1e-9);
    EXPECT_NEAR(q.phase(2).initial_state("x"), b, 1e-9);
    EXPECT_NEAR(q.objective, a * a / 4.0, 1e-9);
}

TEST(MultiPhaseLinks, PhasesListedOutOfOrder) {
    // three walks over [0, 1], [1, 2], [2, 3], listed as phases [first, last, middle] and linked
    // 0 -> 2 -> 1: one straight line x = t from 0 to 3, J = 3/2 (1²/2 per leg)
    Walk first;
    first.name = "first";
    first.has_start = true;
    Walk middle;
    middle.name = "middle";
    middle.t0 = 1.0;
    Walk last;
    last.name = "last";
    last.t0 = 2.0;
    last.has_end = true;
    last.end = 3.0;
    MultiPhaseProblem mp;
    mp.name = "out of order";
    mp.phases = {walk_phase(first), walk_phase(last), walk_phase(middle)};
    mp.links = {{nullptr, true, 0, 2}, {nullptr, true, 2, 1}};
    const MultiPhaseSolution s = solve(mp);
    std::printf("out of order: J %.12f (3/2), x(1) %.12f, x(2) %.12f\n", s.objective,
                s.phase(0).final_state("x"), s.phase(2).final_state("x"));
    ASSERT_TRUE(s.resolved()) << s.status_text;
    EXPECT_NEAR(s.objective, 1.5, 1e-9);
    EXPECT_NEAR(s.phase(0).final_state("x"), 1.0, 1e-9);
    EXPECT_NEAR(s.phase(2).final_state("x"), 2.0, 1e-9);
    EXPECT_NEAR(s.phase(1).initial_state("x"), 2.0, 1e-9);
}

using test::Drift;  // drift_model.hpp

TEST(MultiPhaseLinks, ParametersOfAPhaseNoLinkEnters) {
    // x' = u, min ∫u²/2 + (p - 3)²/2 with x(1) = p/4 (phase 0), x(2) = p (phase 1, linked to
    // phase 0) and a third phase, linked to none, from x = 0 to p/4 over 1 s: each leg a straight
    // line, J = 5p²/16 + p²/32 + (p - 3)²/2, least at p = 16/9 with J = 11/6. The third phase's
    // copy of p is tied to phase 0's by its own rows (were it free: p = 24/13, J = 585/338).
    Drift a;
    a.name = "first";
    Drift b;
    b.name = "second";
    b.t0 = 1.0;
    b.share = 1.0;
    b.start = false;
    Drift c;
    c.name = "aside";
    MultiPhaseProblem mp;
    mp.name = "untied parameter";
    Eigen::VectorXd x(1), u(1), p(1);
    x << 0.0;
    u << 0.0;
    p << 3.0;
    auto phase = [&](const Drift& d) {
        return Phase{make_model(d), Mesh::uniform(1, 5),
                     Guess::linear(d.t0, d.t0 + 1.0, x, x, u, u, p)};
    };
    // the parameter's cost as a cross-phase Mayer term of phase 1's ends (and p)
    mp.phases = {phase(a), phase(b), phase(c)};
    mp.links = {{nullptr, true, 0, 1}};
    mp.mayer = make_cross_phase_mayer(
        {1}, [](auto /*e*/, auto q) { return 0.5 * (q[0] - 3.0) * (q[0] - 3.0); });
    const DerivativeCheck dc = check_derivatives(mp);
    EXPECT_LT(dc.jacobian_error, 2e-6) << dc.worst_row << " " << dc.worst_col;
    EXPECT_LT(dc.hessian_error, 2e-6);
    const MultiPhaseSolution s = solve(mp);
    std::printf("untied parameter: p %.12f (16/9), J %.12f (11/6), Mayer %.12f\n", s.parameters(0),
                s.objective, s.mayer);
    ASSERT_TRUE(s.resolved()) << s.status_text;
    EXPECT_NEAR(s.parameters(0), 16.0 / 9.0, 1e-9);
    EXPECT_NEAR(s.phase(2).parameter("p"), 16.0 / 9.0, 1e-9);
    EXPECT_NEAR(s.phase(2).final_state("x"), 4.0 / 9.0, 1e-9);
    EXPECT_NEAR(s.objective, 11.0 / 6.0, 1e-9);
    EXPECT_NEAR(s.mayer, 0.5 * (16.0 / 9.0 - 3.0) * (16.0 / 9.0 - 3.0), 1e-9);
    EXPECT_NEAR(s.phase(0).objective + s.phase(1).objective + s.phase(2).objective + s.mayer,
                s.objective, 1e-12);
    EXPECT_LT(s.max_link_violation, 1e-10);
}

/// x'' = u, |u| <= 1, from rest at 0 (phase 0, tf free) and, after a coast of fixed length d
/// between the phases, to rest at L (phase 1, both times free), in least time. The link sees
/// the times: during the gap the body moves at its speed, x_1(t0_1) = x_0(tf_0) + v (t0_1 -
/// tf_0), and t0_1 - tf_0 = d. The fastest profile accelerates at 1 for t1, coasts d at v = t1
/// and brakes for t1 (the coast is best at the peak speed), L = t1² + t1 d, so the total time
/// is 2 t1 + d = √(d² + 4L).
struct Sprint {
    std::string name;
    bool first = true;
    double L = 1.0;
    [[nodiscard]] ProblemInfo info() const {
        ProblemInfo p;
        p.name = name;
        p.states = {{"x", -10.0, 10.0, 1.0}, {"v", -10.0, 10.0, 1.0}};
        p.controls = {{"u", -1.0, 1.0, 1.0}};
        p.initial_time = first ? fixed(0.0) : Bounds{0.1, 20.0};
        p.final_time = {0.1, 20.0};
        if (first) {
            p.set_initial("x", 0.0);
            p.set_initial("v", 0.0);
        } else {
            p.set_final("x", L);
            p.set_final("v", 0.0);
        }
        return p;
    }
    template <class T>
    void dynamics(std::span<const T> x, std::span<const T> u, std::span<const T> /*p*/,
                  const T& /*t*/, std::span<T> xdot) const {
        xdot[0] = x[1];
        xdot[1] = u[0];
    }
};

std::shared_ptr<const LinkModel> coast(double d) {
    return make_link(2, 2,
                     {{"x after the coast", 0.0, 0.0, 1.0},
                      {"v continuity", 0.0, 0.0, 1.0},
                      {"coast time", d, d, 1.0}},
                     [](auto xf, auto x0, auto /*p*/, auto t, auto l) {
                         l[0] = x0[0] - xf[0] - xf[1] * (t[2] - t[1]);
                         l[1] = x0[1] - xf[1];
                         l[2] = t[2] - t[1];
                     });
}

MultiPhaseProblem sprint(double d, double L) {
    Sprint a;
    a.name = "accelerate";
    Sprint b;
    b.name = "brake";
    b.first = false;
    b.L = L;
    Eigen::MatrixXd X(2, 2), U(2, 1), X2(2, 2), U2(2, 1);
    X << 0.0, 0.0, 0.3, 0.8;
    U << 1.0, 1.0;
    X2 << 0.7, 0.8, L, 0.0;
    U2 << -1.0, -1.0;
    MultiPhaseProblem mp;
    mp.name = "sprint with a coast";
    mp.phases = {{make_model(a), Mesh::uniform(1, 6), Guess::from_history({0.0, 0.8}, X, U)},
                 {make_model(b), Mesh::uniform(1, 6), Guess::from_history({1.3, 2.1}, X2, U2)}};
    mp.links = {{coast(d), false}};
    // the total time, a Mayer term of two phases' ends
    mp.mayer = make_cross_phase_mayer({0, 1}, [](auto e, auto /*p*/) { return e[1].tf - e[0].t0; });
    return mp;
}

TEST(MultiPhaseLinks, LinkageFunctionOfTheTimes) {
    const double d = 0.5, L = 1.0;
    const double total = std::sqrt(d * d + 4.0 * L), t1 = 0.5 * (total - d);
    const MultiPhaseSolution s = solve(sprint(d, L));
    std::printf(
        "sprint with a coast: T %.12f (sqrt(4.25) = %.12f), t1 %.12f (%.12f), t0_1 %.12f, %d "
        "IPOPT iterations, %.3f s CPU\n",
        s.objective, total, s.phase(0).final_time, t1, s.phase(1).initial_time, s.iterations,
        s.cpu_time);
    ASSERT_TRUE(s.resolved()) << s.status_text;
    EXPECT_NEAR(s.objective, total, 1e-7);
    EXPECT_NEAR(s.mayer, s.objective, 1e-15);  // no phase has an objective of its own
    EXPECT_NEAR(s.phase(0).final_time, t1, 1e-7);
    EXPECT_NEAR(s.phase(1).initial_time - s.phase(0).final_time, d, 1e-10);
    EXPECT_NEAR(s.phase(0).final_state("v"), t1, 1e-7);
    EXPECT_NEAR(s.phase(1).initial_state("x"), t1 * t1 / 2.0 + t1 * d, 1e-7);
    EXPECT_LT(s.max_link_violation, 1e-9);
    // without the coast the same link gives the rest-to-rest minimum time 2 √L
    const MultiPhaseSolution s0 = solve(sprint(0.0, L));
    ASSERT_TRUE(s0.resolved()) << s0.status_text;
    EXPECT_NEAR(s0.objective, 2.0 * std::sqrt(L), 1e-7);
}

/// A Walk maximising -∫u²/2.
struct NegWalk : Walk {
    [[nodiscard]] ProblemInfo info() const {
        ProblemInfo p = Walk::info();
        p.maximise = true;
        return p;
    }
    template <class T>
    T lagrange(std::span<const T> /*x*/, std::span<const T> u, std::span<const T> /*p*/,
               const T& /*t*/) const {
        return -0.5 * u[0] * u[0];
    }
};

TEST(MultiPhaseLinks, CrossPhaseMayerOfTwoPhasesFinalStates) {
    // the branch with a free right end e and Ψ = W/2 (x_2(2) - x_0(1) - D)², phase 0's final
    // state against phase 2's: with s = e - c, J = c²/2 + (a - c)²/2 + s²/2 + W (s - D)²/2,
    // least at c = a/2, s = W D/(1 + W): J = a²/4 + W D²/(2(1 + W))
    const double a = 1.0, W = 3.0, D = 2.0;
    MultiPhaseProblem mp = branch(a, 0.0);
    Walk right;
    right.name = "right";
    right.t0 = 1.0;
    mp.phases[2] = walk_phase(right);
    mp.mayer = make_cross_phase_mayer({2, 0}, [W, D](auto e, auto /*p*/) {
        const auto s = e[0].xf[0] - e[1].xf[0] - D;
        return 0.5 * W * s * s;
    });
    const MultiPhaseSolution s = solve(mp);
    const double sr = W * D / (1.0 + W);
    std::printf("cross-phase Mayer: J %.12f (1.75), x_2(2) - x_0(1) %.12f (1.5)\n", s.objective,
                s.phase(2).final_state("x") - s.phase(0).final_state("x"));
    ASSERT_TRUE(s.resolved()) << s.status_text;
    EXPECT_NEAR(s.objective, a * a / 4.0 + W * D * D / (2.0 * (1.0 + W)), 1e-9);
    EXPECT_NEAR(s.phase(0).final_state("x"), a / 2.0, 1e-8);
    EXPECT_NEAR(s.phase(2).final_state("x") - s.phase(0).final_state("x"), sr, 1e-8);
    EXPECT_NEAR(s.mayer, 0.5 * W * (sr - D) * (sr - D), 1e-9);
    // maximising the negative: the same optimum, the user's sign
    MultiPhaseProblem neg = mp;
    for (std::size_t k = 0; k < 3; ++k) {
        NegWalk w;
        w.name = k == 0 ? "trunk" : k == 1 ? "left" : "right";
        w.t0 = k == 0 ? 0.0 : 1.0;
        w.has_start = k == 0;
        w.has_end = k == 1;
        w.end = a;
        neg.phases[k] = walk_phase(w);
    }
    neg.mayer = make_cross_phase_mayer(
        {2, 0},
        [W, D](auto e, auto /*p*/) {
            const auto s = e[0].xf[0] - e[1].xf[0] - D;
            return -0.5 * W * s * s;
        },
        true);
    const MultiPhaseSolution n = solve(neg);
    ASSERT_TRUE(n.resolved()) << n.status_text;
    EXPECT_NEAR(n.objective, -s.objective, 1e-9);
    EXPECT_NEAR(n.phase(2).final_state("x"), s.phase(2).final_state("x"), 1e-9);
}

TEST(MultiPhaseLinks, DerivativesWithTimesAndCrossPhaseMayer) {
    // the sprint's link and total time, and a nonlinear link and Mayer term of all four times,
    // the states and a parameter-free product: exact AD against central differences
    const DerivativeCheck s = check_derivatives(sprint(0.5, 1.0));
    std::printf("derivative check, sprint: gradient %.1e, Jacobian %.1e, Hessian %.1e\n",
                s.gradient_error, s.jacobian_error, s.hessian_error);
    EXPECT_LT(s.gradient_error, 2e-6);
    EXPECT_LT(s.jacobian_error, 2e-6) << s.worst_row << " " << s.worst_col;
    EXPECT_LT(s.hessian_error, 2e-6);
    MultiPhaseProblem mp = sprint(0.5, 1.0);
    mp.links[0].function =
        make_link(2, 2, {{"nonlinear 1", -kInf, kInf, 1.0}, {"nonlinear 2", 0.0, 0.0, 1.0}},
                  [](auto xf, auto x0, auto /*p*/, auto t, auto l) {
                      using std::exp;
                      using std::sin;
                      l[0] = x0[0] * t[2] - xf[0] * sin(t[1] * xf[1]) + t[0] * t[3] * t[3];
                      l[1] = x0[1] * exp(0.1 * (t[2] - t[1])) - xf[1] * t[3] + x0[0] * t[0];
                  });
    mp.mayer = make_cross_phase_mayer({1, 0}, [](auto e, auto /*p*/) {
        using std::cos;
        return e[0].tf * e[0].tf * e[1].xf[1] + cos(e[1].tf * e[0].x0[0]) +
               e[0].xf[0] * e[1].xf[0] * e[0].t0;
    });
    const DerivativeCheck n = check_derivatives(mp);
    std::printf(
        "derivative check, nonlinear timed link and Mayer: gradient %.1e, Jacobian %.1e, "
        "Hessian %.1e\n",
        n.gradient_error, n.jacobian_error, n.hessian_error);
    EXPECT_LT(n.gradient_error, 2e-6);
    EXPECT_LT(n.jacobian_error, 2e-6) << n.worst_row << " " << n.worst_col;
    EXPECT_LT(n.hessian_error, 2e-6);
    // the branch (two links out of phase 0) with a Mayer term of phases 0 and 2
    MultiPhaseProblem b = branch(1.0, 3.0);
    b.mayer = make_cross_phase_mayer({0, 2}, [](auto e, auto /*p*/) {
        return e[0].xf[0] * e[0].xf[0] * e[1].xf[0] + e[1].tf * e[1].x0[0];
    });
    const DerivativeCheck bc = check_derivatives(b);
    EXPECT_LT(bc.gradient_error, 2e-6);
    EXPECT_LT(bc.jacobian_error, 2e-6);
    EXPECT_LT(bc.hessian_error, 2e-6);
}

TEST(MultiPhaseLinks, PeriodicLinkBackToTheFirstPhase) {
    // phase 0 on [0, 1] from a free x(0) to x(1) = a, phase 1 on [1, 2] from there to a free
    // x(2), and a link 1 -> 0 without time continuity: x_0(0) = x_1(2) = y (periodic). With
    // Ψ = W y²/2 of phase 1's end, J = (a - y)²/2 + (y - a)²/2 + W y²/2, least at
    // y = 2a/(2 + W). Without the periodic link: x(0) = a, y = a/(1 + W), J = W a²/(2(1 + W)).
    const double a = 1.0, W = 2.0, y = 2.0 * a / (2.0 + W);
    Walk first;
    first.name = "first";
    first.has_end = true;
    first.end = a;
    Walk second;
    second.name = "second";
    second.t0 = 1.0;
    MultiPhaseProblem mp;
    mp.name = "periodic";
    mp.phases = {walk_phase(first), walk_phase(second)};
    mp.links = {{nullptr, true, 0, 1}, {nullptr, false, 1, 0}};
    mp.mayer = make_cross_phase_mayer(
        {1}, [W](auto e, auto /*p*/) { return 0.5 * W * e[0].xf[0] * e[0].xf[0]; });
    const MultiPhaseSolution s = solve(mp);
    std::printf("periodic: x(0) %.12f (0.5), J %.12f (0.5)\n", s.phase(0).initial_state("x"),
                s.objective);
    ASSERT_TRUE(s.resolved()) << s.status_text;
    EXPECT_NEAR(s.phase(0).initial_state("x"), y, 1e-8);
    EXPECT_NEAR(s.phase(1).final_state("x"), y, 1e-8);
    EXPECT_NEAR(s.objective, (a - y) * (a - y) + 0.5 * W * y * y, 1e-9);
    mp.links.pop_back();
    const MultiPhaseSolution o = solve(mp);
    ASSERT_TRUE(o.resolved()) << o.status_text;
    EXPECT_NEAR(o.phase(1).final_state("x"), a / (1.0 + W), 1e-8);
    EXPECT_NEAR(o.objective, W * a * a / (2.0 * (1.0 + W)), 1e-9);
    // with time continuity on both links the cycle is rejected
    mp.links = {{nullptr, true, 0, 1}, {nullptr, true, 1, 0}};
    EXPECT_THROW((void)solve(mp), manta::InputError);
}

std::vector<std::vector<std::string>> read_csv(const fs::path& file) {
    std::vector<std::vector<std::string>> rows;
    std::ifstream in(file);
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> cells;
        std::stringstream ss(line);
        std::string cell;
        while (std::getline(ss, cell, ',')) cells.push_back(cell);
        if (!line.empty() && line.back() == ',') cells.emplace_back();
        rows.push_back(cells);
    }
    return rows;
}

TEST(MultiPhaseLinks, FailedSolveWritesTheFailureCsv) {
    // the branch with a link that cannot hold: the right phase must start 30 above the trunk's
    // end, outside its state bounds [-10, 10]
    MultiPhaseProblem mp = branch(1.0, 3.0);
    mp.links[1].function = make_link(1, 1, {{"jump of 30", 30.0, 30.0, 1.0}},
                                     [](auto xf, auto x0, auto, auto l) { l[0] = x0[0] - xf[0]; });
    SolverOptions o;
    o.failure_csv = fs::temp_directory_path() / "manta_multiphase_failure" / "best.csv";
    fs::remove(o.failure_csv);
    const MultiPhaseSolution s = solve(mp, o);
    std::printf("infeasible branch: %s, %d IPOPT iterations, max violation %.3g\n",
                to_string(s.status).c_str(), s.iterations, s.max_violation);
    EXPECT_FALSE(s.converged());
    EXPECT_GT(s.max_link_violation, 1.0);
    ASSERT_TRUE(fs::exists(o.failure_csv));
    const auto rows = read_csv(o.failure_csv);
    ASSERT_EQ(rows.size(), 1U + 3U * 5U);  // header, 5 nodes per phase
    EXPECT_EQ(rows[0],
              (std::vector<std::string>{"phase", "t", "segment", "node", "x", "u", "lambda_x"}));
    for (int k = 0; k < 3; ++k) {
        const auto& seg = s.phase(k).segments.at(0);
        for (int i = 0; i < 5; ++i) {
            const auto& r = rows[static_cast<std::size_t>(1 + 5 * k + i)];
            ASSERT_EQ(r.size(), 7U);
            EXPECT_EQ(r[0], std::to_string(k));
            EXPECT_EQ(std::stod(r[1]), seg.time(i));
            EXPECT_EQ(r[2], "0");
            EXPECT_EQ(r[3], std::to_string(i));
            EXPECT_EQ(std::stod(r[4]), seg.states(i, 0));  // 17 digits: exact
            EXPECT_EQ(std::stod(r[5]), seg.controls(i, 0));
        }
    }
    fs::remove_all(o.failure_csv.parent_path());
    // a converged solve writes nothing
    const MultiPhaseSolution ok = solve(branch(1.0, 3.0), o);
    ASSERT_TRUE(ok.converged());
    EXPECT_FALSE(fs::exists(o.failure_csv));
}

TEST(MultiPhaseLinks, CsvOfPhasesWithDifferentColumns) {
    // the sprint's phases have x, v, u; a third phase of one state x and control u: the union
    // of columns, empty cells where a phase lacks one
    MultiPhaseProblem mp = sprint(0.5, 1.0);
    Walk w;
    w.name = "after";
    w.t0 = 5.0;
    mp.phases.push_back(walk_phase(w, 4));
    mp.links[0].from = 0;  // three phases, one link: given by its ends
    mp.links[0].to = 1;
    const MultiPhaseSolution s = solve(mp);
    ASSERT_TRUE(s.resolved()) << s.status_text;
    const fs::path file = fs::temp_directory_path() / "manta_multiphase_union.csv";
    write_csv(s, file);
    const auto rows = read_csv(file);
    ASSERT_EQ(rows.size(), 1U + 6U + 6U + 4U);
    EXPECT_EQ(rows[0], (std::vector<std::string>{"phase", "t", "segment", "node", "x", "v", "u",
                                                 "lambda_x", "lambda_v"}));
    const auto& last = rows.back();
    ASSERT_EQ(last.size(), 9U);
    EXPECT_EQ(last[0], "2");
    EXPECT_EQ(std::stod(last[1]), 6.0);
    EXPECT_TRUE(last[5].empty());  // no v in the third phase
    EXPECT_TRUE(last[8].empty());
    EXPECT_EQ(std::stod(last[4]), s.phase(2).final_state("x"));
    EXPECT_EQ(std::stod(rows[6][5]), s.phase(0).final_state("v"));
    fs::remove(file);
}

std::string error_of(const MultiPhaseProblem& mp) {
    try {
        (void)check_derivatives(mp);
    } catch (const manta::InputError& e) {
        return e.what();
    }
    return "no error";
}

TEST(MultiPhaseLinks, BadLinksAndMayerTermsAreOneLineErrors) {
    auto expect = [](const MultiPhaseProblem& mp, const std::string& text) {
        const std::string e = error_of(mp);
        EXPECT_NE(e.find(text), std::string::npos) << e;
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    };
    MultiPhaseProblem range = branch(1.0, 3.0);
    range.links[1].to = 3;
    expect(range, "link 1: from = 0 and to = 3, expected phase indices in [0, 2]");
    MultiPhaseProblem half = branch(1.0, 3.0);
    half.links[1].from = -1;
    expect(half, "link 1: from = -1 and to = 2, expected phase indices in [0, 2] (or both -1");
    MultiPhaseProblem self = branch(1.0, 3.0);
    self.links[1].to = 0;
    expect(self, "link 1: from = to = 0, expected two different phases");
    MultiPhaseProblem beyond = branch(1.0, 3.0);
    beyond.links.push_back({nullptr, true, -1, -1});  // link 2 by position: phase 2 to 3
    expect(beyond, "link 2 is by position (from = to = -1), phase 2 to 3, but there are 3 phases");
    // by position, the old count rule: N - 1 links
    MultiPhaseProblem count = branch(1.0, 3.0);
    count.links = {{nullptr, true, -1, -1}};
    expect(count, "1 links for 3 phases, expected 2");
    // the bounds across a general link: the right phase must start where the trunk ends
    MultiPhaseProblem gap = branch(1.0, 3.0);
    Walk right;
    right.name = "right";
    right.t0 = 1.0;
    right.has_start = true;
    right.start = 4.0;
    gap.phases[2] = walk_phase(right);
    Walk trunk;
    trunk.name = "trunk";
    trunk.has_start = true;
    trunk.has_end = true;
    trunk.end = 2.0;
    gap.phases[0] = walk_phase(trunk);
    expect(gap,
           "link 1 (phase 0 'trunk' -> phase 2 'right'): state 'x' ends in [2, 2] and the next "
           "phase's 'x' starts in [4, 4]");
    // times across a general link
    MultiPhaseProblem times = branch(1.0, 3.0);
    Walk late = right;
    late.has_start = false;
    late.t0 = 1.5;
    times.phases[2] = walk_phase(late);
    expect(times,
           "tf in [1, 1] and the next t0 in [1.5, 1.5] do not overlap, expected "
           "overlapping bounds for t0_2 = tf_0");
    // a linkage function of the wrong size on a general link
    MultiPhaseProblem size = sprint(0.5, 1.0);
    size.links[0].function = make_link(
        1, 2, {{"x", 0.0, 0.0, 1.0}}, [](auto xf, auto x0, auto, auto l) { l[0] = x0[0] - xf[0]; });
    expect(size, "takes 1 final and 2 initial states, expected 2 and 2");
    // a cycle of time continuity
    MultiPhaseProblem cycle = branch(1.0, 3.0);
    cycle.links.push_back({nullptr, true, 2, 0});
    expect(cycle,
           "link 2 (phase 2 -> 0) closes a cycle of links with time continuity, expected "
           "time_continuity = false on one link of a cycle");
    // cross-phase Mayer terms
    auto total = [](auto e, auto) { return e[0].tf; };
    MultiPhaseProblem m1 = sprint(0.5, 1.0);
    m1.mayer = make_cross_phase_mayer({0, 2}, total);
    expect(m1, "the cross-phase Mayer term's phase 1 is 2, expected a phase index in [0, 1]");
    MultiPhaseProblem m2 = sprint(0.5, 1.0);
    m2.mayer = make_cross_phase_mayer({1, 1}, total);
    expect(m2, "the cross-phase Mayer term lists phase 1 twice, expected each phase once");
    MultiPhaseProblem m3 = sprint(0.5, 1.0);
    m3.mayer = make_cross_phase_mayer({}, total);
    expect(m3, "the cross-phase Mayer term lists no phases, expected at least one");
    MultiPhaseProblem m4 = branch(1.0, 3.0);  // minimised phases, a maximised Mayer term
    m4.mayer = make_cross_phase_mayer({0}, total, true);
    expect(m4,
           "the cross-phase Mayer term is maximised and phase 0 'trunk' minimised, expected "
           "one sense");
}

}  // namespace
