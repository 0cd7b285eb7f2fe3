// Multiple phases joined by linkage constraints: a linkage that jumps a state (an impulsive
// velocity kick) with its analytic optimum, phases with different numbers of states, free phase
// times, shared static parameters, derivative checks of the multi-phase NLP and the one-line
// errors of bad input.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "drift_model.hpp"
#include "manta/core/error.hpp"
#include "manta/optimal/model.hpp"
#include "manta/optimal/multiphase.hpp"
#include "manta/optimal/solve.hpp"

namespace {

using namespace manta::optimal;

/// x'' = u on [t0, tf] with min ∫ u²/2 dt (a Lagrange cost); `energy_state` adds E' = u²/2 as a
/// third state and takes E(tf) as a Mayer cost instead.
struct Leg {
    std::string name = "leg";
    double t0 = 0.0, tf = 0.5;
    bool free_t0 = false, free_tf = false;
    bool energy_state = false;
    std::vector<Bounds> initial, final;  // per state (empty: free)

    [[nodiscard]] ProblemInfo info() const {
        ProblemInfo p;
        p.name = name;
        p.states = {{"x", -10.0, 10.0, 1.0}, {"v", -10.0, 10.0, 1.0}};
        if (energy_state) p.states.push_back({"E", 0.0, 100.0, 1.0});
        p.controls = {{"u", -50.0, 50.0, 1.0}};
        p.initial_time = free_t0 ? Bounds{0.0, 10.0} : fixed(t0);
        p.final_time = free_tf ? Bounds{0.0, 10.0} : fixed(tf);
        p.initial_states = initial;
        p.final_states = final;
        return p;
    }
    template <class T>
    void dynamics(std::span<const T> x, std::span<const T> u, std::span<const T> /*p*/,
                  const T& /*t*/, std::span<T> xdot) const {
        xdot[0] = x[1];
        xdot[1] = u[0];
        if (energy_state) xdot[2] = 0.5 * u[0] * u[0];
    }
};
struct LagrangeLeg : Leg {
    template <class T>
    T lagrange(std::span<const T> /*x*/, std::span<const T> u, std::span<const T> /*p*/,
               const T& /*t*/) const {
        return 0.5 * u[0] * u[0];
    }
};
struct MayerLeg : Leg {
    template <class T>
    T mayer(std::span<const T> /*x0*/, std::span<const T> xf, std::span<const T> /*p*/,
            const T& /*t0*/, const T& /*tf*/) const {
        return xf[2];
    }
};

/// The linkage of an impulsive kick dv at the junction: x continuous, v jumps by dv; the states
/// after the first two (E of a MayerLeg) start at 0.
std::shared_ptr<const LinkModel> kick(double dv, int n_to) {
    std::vector<Constraint> c = {{"x continuity", 0.0, 0.0, 1.0}, {"v kick", dv, dv, 1.0}};
    if (n_to > 2) c.push_back({"E starts at 0", 0.0, 0.0, 1.0});
    return make_link(2, n_to, c, [n_to](auto xf, auto x0, auto /*p*/, auto l) {
        l[0] = x0[0] - xf[0];
        l[1] = x0[1] - xf[1];
        if (n_to > 2) l[2] = x0[2];
    });
}

/// Rest at x = 0 to rest at x = 1 over [0, 1] with a kick dv at t = 1/2, min ∫u²/2. The costates
/// are continuous across the kick (the jump is a translation), so u is one straight line over
/// [0, 1]: u = a + b t with ∫u = -dv (v(1) = 0) and ∫(1 - s) u ds = 1 - dv/2 (x(1) = 1), giving
/// b = -12, a = 6 - dv, J = (a² + a b + b²/3)/2; v(1/2-) = a/2 + b/8, x(1/2) = a/8 + b/48.
MultiPhaseProblem kicked(double dv, bool energy_state, int nodes) {
    LagrangeLeg a;
    a.name = "before the kick";
    a.t0 = 0.0;
    a.tf = 0.5;
    a.initial = {fixed(0.0), fixed(0.0)};
    MultiPhaseProblem mp;
    mp.name = "kicked double integrator";
    Eigen::VectorXd x0(2), x1(2), u(1);
    x0 << 0.0, 0.0;
    x1 << 0.5, 0.0;
    u << 0.0;
    mp.phases.push_back(
        {make_model(a), Mesh::uniform(1, nodes), Guess::linear(0.0, 0.5, x0, x1, u, u)});
    if (energy_state) {
        MayerLeg b;
        b.name = "after the kick";
        b.energy_state = true;
        b.t0 = 0.5;
        b.tf = 1.0;
        b.final = {fixed(1.0), fixed(0.0), {0.0, kInf}};
        Eigen::VectorXd y0(3), y1(3);
        y0 << 0.5, 0.0, 0.0;
        y1 << 1.0, 0.0, 0.0;
        mp.phases.push_back(
            {make_model(b), Mesh::uniform(1, nodes), Guess::linear(0.5, 1.0, y0, y1, u, u)});
        mp.links = {{kick(dv, 3), true}};
    } else {
        LagrangeLeg b;
        b.name = "after the kick";
        b.t0 = 0.5;
        b.tf = 1.0;
        b.final = {fixed(1.0), fixed(0.0)};
        Eigen::VectorXd y1(2);
        y1 << 1.0, 0.0;
        mp.phases.push_back(
            {make_model(b), Mesh::uniform(1, nodes), Guess::linear(0.5, 1.0, x1, y1, u, u)});
        mp.links = {{kick(dv, 2), true}};
    }
    return mp;
}

TEST(MultiPhase, LinkageJumpMatchesTheAnalyticOptimum) {
    const double dv = 1.0, a = 6.0 - dv, b = -12.0;
    const MultiPhaseSolution s = solve(kicked(dv, false, 6));
    std::printf("kick: J %.12f (6.5), %d IPOPT iterations, %.3f s CPU, resim %.1e\n", s.objective,
                s.iterations, s.cpu_time, s.max_resimulation_error());
    ASSERT_TRUE(s.resolved()) << s.status_text;
    EXPECT_NEAR(s.objective, 0.5 * (a * a + a * b + b * b / 3.0), 1e-9);       // 6.5
    EXPECT_NEAR(s.phase(0).final_state("v"), a / 2.0 + b / 8.0, 1e-9);         // 1 before the kick
    EXPECT_NEAR(s.phase(1).initial_state("v"), a / 2.0 + b / 8.0 + dv, 1e-9);  // 2 after
    EXPECT_NEAR(s.phase(0).final_state("x"), a / 8.0 + b / 48.0, 1e-9);
    EXPECT_NEAR(s.phase(1).initial_state("x"), a / 8.0 + b / 48.0, 1e-9);
    for (double t : {0.0, 0.2, 0.45}) EXPECT_NEAR(s.phase(0).control(t, "u"), a + b * t, 1e-8);
    for (double t : {0.55, 0.8, 1.0}) EXPECT_NEAR(s.phase(1).control(t, "u"), a + b * t, 1e-8);
    EXPECT_LT(s.max_link_violation, 1e-9);
    EXPECT_LT(s.max_resimulation_error(), 1e-6);
    // costates continuous across the kick (a translation of the state)
    EXPECT_NEAR(s.phase(0).costate(0.5)(1), s.phase(1).costate(0.5)(1), 1e-6);
    // the same with IPOPT's limited-memory Hessian (first derivatives only)
    SolverOptions lbfgs;
    lbfgs.hessian = HessianMode::limited_memory;
    const MultiPhaseSolution q = solve(kicked(dv, false, 6), lbfgs);
    ASSERT_TRUE(q.resolved()) << q.status_text;
    EXPECT_NEAR(q.objective, 6.5, 1e-7);
    EXPECT_EQ(q.n_hessian_nonzeros, 0);
    // without the kick: the single-phase optimum J = 6
    const MultiPhaseSolution s0 = solve(kicked(0.0, false, 6));
    ASSERT_TRUE(s0.resolved());
    EXPECT_NEAR(s0.objective, 6.0, 1e-9);
}

TEST(MultiPhase, PhasesWithDifferentStatesAndObjectives) {
    // the second phase carries its energy as a third state and a Mayer cost: same optimum
    const double dv = 1.0, a = 6.0 - dv, b = -12.0;
    const MultiPhaseSolution s = solve(kicked(dv, true, 6));
    std::printf("kick, 2 and 3 states: J %.12f (6.5), %d IPOPT iterations\n", s.objective,
                s.iterations);
    ASSERT_TRUE(s.resolved()) << s.status_text;
    EXPECT_NEAR(s.objective, 0.5 * (a * a + a * b + b * b / 3.0), 1e-9);
    EXPECT_EQ(s.phase(0).info.n_states(), 2);
    EXPECT_EQ(s.phase(1).info.n_states(), 3);
    EXPECT_NEAR(s.phase(1).initial_state("E"), 0.0, 1e-10);
    EXPECT_NEAR(s.phase(1).final_state("E"), s.phase(1).objective, 1e-12);
    EXPECT_NEAR(s.phase(0).objective + s.phase(1).objective, s.objective, 1e-12);
    EXPECT_FALSE(summary(s).empty());
}

/// Rest at 0 to x = 1 (phase 1, v free at its end) and back to rest at 0 (phase 2) in least
/// time, |u| <= 1, both times free: each leg is rest to rest over 1 (Kirk 1970, ch. 5,
/// minimum-time double integrator), 2 s each, so t_f = 4 and the phase boundary at 2; the
/// switches at 1 and 3 s fall on each phase's free break.
struct BangLeg {
    std::string name;
    double x_start = 0.0, x_end = 1.0;
    bool minimise_time = false;
    bool first = true;
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
            p.set_final("x", x_end);
        } else {
            p.set_final("x", x_end);
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
struct TimedBangLeg : BangLeg {
    template <class T>
    T mayer(std::span<const T> /*x0*/, std::span<const T> /*xf*/, std::span<const T> /*p*/,
            const T& /*t0*/, const T& tf) const {
        return tf;
    }
};

MultiPhaseProblem there_and_back() {
    BangLeg out;
    out.name = "out";
    out.x_end = 1.0;
    TimedBangLeg back;
    back.name = "back";
    back.first = false;
    back.x_end = 0.0;
    Mesh m = Mesh::uniform(2, 8);
    m.free_breaks = true;
    std::vector<double> t{0.0, 1.0, 2.0};
    Eigen::MatrixXd X(3, 2), U(3, 1);
    X << 0.0, 0.0, 0.5, 1.0, 1.0, 0.0;
    U << 1.0, 0.0, -1.0;
    Guess g1 = Guess::from_history(t, X, U);
    std::vector<double> t2{2.0, 3.0, 4.0};
    Eigen::MatrixXd X2(3, 2);
    X2 << 1.0, 0.0, 0.5, -1.0, 0.0, 0.0;
    Eigen::MatrixXd U2(3, 1);
    U2 << -1.0, 0.0, 1.0;
    Guess g2 = Guess::from_history(t2, X2, U2);
    MultiPhaseProblem mp;
    mp.name = "there and back";
    mp.phases = {{make_model(out), m, g1}, {make_model(back), m, g2}};
    return mp;
}

TEST(MultiPhase, FreePhaseTimesWithDefaultLinks) {
    const MultiPhaseSolution s = solve(there_and_back());
    std::printf("there and back: t_f %.9f (4), turn %.9f (2), %d IPOPT iterations, %.3f s CPU\n",
                s.objective, s.phase(0).final_time, s.iterations, s.cpu_time);
    ASSERT_TRUE(s.resolved()) << s.status_text;
    EXPECT_NEAR(s.objective, 4.0, 1e-6);
    EXPECT_NEAR(s.phase(0).final_time, 2.0, 1e-6);
    EXPECT_NEAR(s.phase(1).initial_time, s.phase(0).final_time, 1e-12);
    EXPECT_NEAR(s.phase(0).final_state("v"), 0.0, 1e-6);
    EXPECT_NEAR(s.phase(1).initial_state("v"), s.phase(0).final_state("v"), 1e-10);
    EXPECT_NEAR(s.phase(0).breaks[1], 1.0, 1e-6);
    EXPECT_NEAR(s.phase(1).breaks[1], 3.0, 1e-6);
}

/// A shared static parameter p: x' = u over two phases of 1 s from x(0) = 0, min ∫u²/2 dt +
/// (p - 3)²/2, the first phase ending at x(1) = p/4 (its event), the second at x(2) = p (its
/// event; the Mayer term is the second phase's). Each leg is a straight line: u = p/4, then 3p/4,
/// J = 5p²/16 + (p - 3)²/2, so p = 24/13 and J = 585/338. Were the parameter not shared, the
/// first phase would take p = 0 and the second p = 3/2, J = 9/4.
using test::Drift;  // drift_model.hpp (x(t0) = 0 given where t0 = 0)
struct DriftCost : Drift {
    template <class T>
    T mayer(std::span<const T> /*x0*/, std::span<const T> /*xf*/, std::span<const T> p,
            const T& /*t0*/, const T& /*tf*/) const {
        return 0.5 * (p[0] - 3.0) * (p[0] - 3.0);
    }
};

MultiPhaseProblem shared_parameter() {
    Drift a;
    a.name = "first second";
    DriftCost b;
    b.name = "second second";
    b.t0 = 1.0;
    b.share = 1.0;
    b.start = false;
    Eigen::VectorXd x0(1), x1(1), u(1), p(1);
    x0 << 0.0;
    x1 << 0.0;
    u << 0.0;
    p << 3.0;
    MultiPhaseProblem mp;
    mp.name = "shared parameter";
    mp.phases = {{make_model(a), Mesh::uniform(1, 5), Guess::linear(0.0, 1.0, x0, x1, u, u, p)},
                 {make_model(b), Mesh::uniform(1, 5), Guess::linear(1.0, 2.0, x0, x1, u, u, p)}};
    return mp;
}

TEST(MultiPhase, StaticParametersAreShared) {
    const MultiPhaseSolution s = solve(shared_parameter());
    std::printf("shared parameter: p %.12f (24/13), J %.12f (585/338), %d IPOPT iterations\n",
                s.parameters(0), s.objective, s.iterations);
    ASSERT_TRUE(s.resolved()) << s.status_text;
    EXPECT_NEAR(s.parameters(0), 24.0 / 13.0, 1e-9);
    EXPECT_NEAR(s.phase(1).parameter("p"), 24.0 / 13.0, 1e-9);
    EXPECT_NEAR(s.phase(0).final_state("x"), 6.0 / 13.0, 1e-9);
    EXPECT_NEAR(s.objective, 585.0 / 338.0, 1e-9);
}

TEST(MultiPhase, DerivativesOfTheMultiPhaseNlp) {
    for (bool energy : {false, true}) {
        const DerivativeCheck c = check_derivatives(kicked(1.0, energy, 5));
        EXPECT_LT(c.gradient_error, 2e-6);
        EXPECT_LT(c.jacobian_error, 2e-6) << c.worst_row << " " << c.worst_col;
        EXPECT_LT(c.hessian_error, 2e-6);
    }
    const DerivativeCheck sp = check_derivatives(shared_parameter());
    EXPECT_LT(sp.gradient_error, 2e-6);
    EXPECT_LT(sp.jacobian_error, 2e-6) << sp.worst_row << " " << sp.worst_col;
    EXPECT_LT(sp.hessian_error, 2e-6);
    const DerivativeCheck t = check_derivatives(there_and_back());
    EXPECT_LT(t.jacobian_error, 2e-6) << t.worst_row << " " << t.worst_col;
    EXPECT_LT(t.hessian_error, 2e-6);
    // a nonlinear linkage with the parameter: x0 = xf² sin(p), v0 = v xf p, in its Hessian
    MultiPhaseProblem mp = kicked(1.0, false, 5);
    mp.links[0].function = make_link(
        2, 2, {{"nonlinear x", -kInf, kInf, 1.0}, {"nonlinear v", 0.0, 0.0, 1.0}},
        [](auto xf, auto x0, auto p, auto l) {
            using std::sin;
            l[0] = x0[0] - xf[0] * xf[0] * sin(xf[1]);
            l[1] = x0[1] * xf[0] - xf[1] * xf[1] * x0[0] + (p.empty() ? 0.0 * xf[0] : p[0]);
        });
    const DerivativeCheck n = check_derivatives(mp);
    std::printf("derivative check, nonlinear linkage: gradient %.1e, Jacobian %.1e, Hessian %.1e\n",
                n.gradient_error, n.jacobian_error, n.hessian_error);
    EXPECT_LT(n.jacobian_error, 2e-6) << n.worst_row << " " << n.worst_col;
    EXPECT_LT(n.hessian_error, 2e-6);
    // the same link seeing the end times (t0_a, tf_a, t0_b, tf_b), and a Mayer term of both
    // phases' ends, on the free times of there_and_back
    MultiPhaseProblem tt = there_and_back();
    tt.links = {{make_link(2, 2, {{"timed x", -kInf, kInf, 1.0}, {"timed v", 0.0, 0.0, 1.0}},
                           [](auto xf, auto x0, auto /*p*/, auto t, auto l) {
                               using std::sin;
                               l[0] = x0[0] - xf[0] * sin(t[1] * t[2]) + t[0];
                               l[1] = x0[1] * t[3] - xf[1] * t[1] * t[1];
                           }),
                 true}};
    tt.mayer = make_cross_phase_mayer({0, 1}, [](auto e, auto /*p*/) {
        return e[1].tf * e[0].tf + e[0].xf[1] * e[1].x0[0] * e[1].t0;
    });
    const DerivativeCheck tc = check_derivatives(tt);
    std::printf(
        "derivative check, timed linkage and cross-phase Mayer: gradient %.1e, Jacobian "
        "%.1e, Hessian %.1e\n",
        tc.gradient_error, tc.jacobian_error, tc.hessian_error);
    EXPECT_LT(tc.gradient_error, 2e-6);
    EXPECT_LT(tc.jacobian_error, 2e-6) << tc.worst_row << " " << tc.worst_col;
    EXPECT_LT(tc.hessian_error, 2e-6);
}

TEST(MultiPhase, SinglePhaseProblemAsOnePhase) {
    // one phase and no links: the same solve as the single-phase API, to the last bit
    LagrangeLeg a;
    a.t0 = 0.0;
    a.tf = 1.0;
    a.initial = {fixed(0.0), fixed(0.0)};
    a.final = {fixed(1.0), fixed(0.0)};
    Eigen::VectorXd x0(2), x1(2), u(1);
    x0 << 0.0, 0.0;
    x1 << 1.0, 0.0;
    u << 0.0;
    const Guess g = Guess::linear(0.0, 1.0, x0, x1, u, u);
    auto model = make_model(a);
    const Solution one = solve(*model, Mesh::uniform(2, 6), g);
    MultiPhaseProblem mp;
    mp.phases = {{std::shared_ptr<const Model>(make_model(a)), Mesh::uniform(2, 6), g}};
    const MultiPhaseSolution multi = solve(mp);
    ASSERT_TRUE(one.resolved());
    ASSERT_TRUE(multi.resolved());
    EXPECT_EQ(one.objective, multi.objective);
    EXPECT_EQ(one.iterations, multi.iterations);
    EXPECT_NEAR(one.objective, 6.0, 1e-9);
}

/// A leg with an interior event (solve_adaptive rejects it in a multi-phase problem).
struct WithEvent : BangLeg {
    [[nodiscard]] ProblemInfo info() const {
        ProblemInfo p = BangLeg::info();
        p.interior_events = {{{"x", -kInf, kInf, 1.0}, 1}};
        return p;
    }
    template <class T>
    void interior(int, std::span<const T> x, std::span<const T>, const T&, std::span<T> e) const {
        e[0] = x[0];
    }
};

TEST(MultiPhase, AdaptiveRefinementPerPhase) {
    // there and back from one 6-point segment per phase, fixed breaks: the refinement cuts each
    // phase at its switch (free breaks) and reaches t_f = 4
    MultiPhaseProblem mp = there_and_back();
    for (auto& ph : mp.phases) ph.mesh = Mesh::uniform(1, 6);
    const MultiPhaseAdaptiveSolution a = solve_adaptive(mp);
    const std::string report = refinement_report(a);
    std::printf("%s", report.c_str());
    ASSERT_EQ(a.status, RefinementStatus::tolerance_met) << report;
    EXPECT_NEAR(a.solution.objective, 4.0, 1e-6);
    EXPECT_NEAR(a.solution.phase(0).final_time, 2.0, 1e-6);
    EXPECT_GE(a.meshes[0].n_segments(), 2);
    EXPECT_GE(a.meshes[1].n_segments(), 2);
    // interior events are not remapped across phases: rejected
    MultiPhaseProblem bad = mp;
    WithEvent w;
    w.name = "out";
    bad.phases[0].model = make_model(w);
    bad.phases[0].mesh = Mesh::uniform(2, 6);
    EXPECT_THROW((void)solve_adaptive(bad), manta::InputError);
}

std::string error_of(const MultiPhaseProblem& mp) {
    try {
        (void)check_derivatives(mp);
    } catch (const manta::InputError& e) {
        return e.what();
    }
    return "no error";
}

TEST(MultiPhase, BadInputIsAOneLineError) {
    MultiPhaseProblem none;
    none.name = "empty";
    EXPECT_NE(error_of(none).find("0 phases, expected at least 1"), std::string::npos)
        << error_of(none);

    // a linkage function of the wrong size
    MultiPhaseProblem size = kicked(1.0, false, 5);
    size.links[0].function = kick(1.0, 3);
    const std::string e1 = error_of(size);
    EXPECT_NE(e1.find("takes 2 final and 3 initial states, expected 2 and 2"), std::string::npos)
        << e1;

    // default continuity between phases of 2 and 3 states
    MultiPhaseProblem counts = kicked(1.0, true, 5);
    counts.links.clear();
    const std::string e2 = error_of(counts);
    EXPECT_NE(e2.find("continuity needs equal state counts, 2 and 3 states"), std::string::npos)
        << e2;

    // bounds that cannot meet across a continuity link
    MultiPhaseProblem gap = kicked(0.0, false, 5);
    gap.links.clear();
    LagrangeLeg a;
    a.name = "before";
    a.initial = {fixed(0.0), fixed(0.0)};
    a.final = {fixed(0.3), {-kInf, kInf}};
    gap.phases[0].model = make_model(a);
    LagrangeLeg b;
    b.name = "after";
    b.t0 = 0.5;
    b.tf = 1.0;
    b.initial = {fixed(0.4), {-kInf, kInf}};
    gap.phases[1].model = make_model(b);
    const std::string e3 = error_of(gap);
    EXPECT_NE(e3.find("state 'x' ends in [0.3, 0.3] and the next phase's 'x' starts in [0.4, 0.4]"),
              std::string::npos)
        << e3;
    EXPECT_EQ(e3.find('\n'), std::string::npos);

    // times that cannot meet: the second phase starts at its default t0 = 0, the first ends at 0.5
    MultiPhaseProblem times = kicked(0.0, false, 5);
    LagrangeLeg c;
    c.t0 = 0.0;
    c.tf = 1.0;
    c.final = {fixed(1.0), fixed(0.0)};
    times.phases[1].model = make_model(c);
    const std::string e4 = error_of(times);
    EXPECT_NE(e4.find("tf in [0.5, 0.5] and the next t0 in [0, 0] do not overlap"),
              std::string::npos)
        << e4;

    // link count
    MultiPhaseProblem links = kicked(1.0, false, 5);
    links.links.push_back(links.links[0]);
    const std::string e5 = error_of(links);
    EXPECT_NE(e5.find("2 links for 2 phases, expected 1"), std::string::npos) << e5;

    // parameters that differ between phases
    MultiPhaseProblem params = kicked(1.0, false, 5);
    Drift d;
    d.name = "drift";
    params.phases[1].model = make_model(d);
    params.links.clear();
    const std::string e6 = error_of(params);
    EXPECT_NE(e6.find("has parameters [p], expected those of phase 0 'before the kick', []"),
              std::string::npos)
        << e6;

    // linkage bounds reversed
    MultiPhaseProblem rev = kicked(1.0, false, 5);
    rev.links[0].function = make_link(2, 2, {{"bad", 1.0, 0.0, 1.0}},
                                      [](auto xf, auto x0, auto, auto l) { l[0] = x0[0] - xf[0]; });
    const std::string e7 = error_of(rev);
    EXPECT_NE(e7.find("linkage constraint 'bad': bounds [1, 0], expected lower <= upper"),
              std::string::npos)
        << e7;

    // a null model
    MultiPhaseProblem null = kicked(1.0, false, 5);
    null.phases[1].model.reset();
    EXPECT_NE(error_of(null).find("phase 1 has no model"), std::string::npos);
}

}  // namespace
