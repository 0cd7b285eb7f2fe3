// Validation of the LGL/IPOPT optimal-control solver on problems with known optima.
//
// 1. Brachistochrone from rest at the origin to (10 m, 5 m), y down, g = 9.80665 m/s^2: the
//    least-time path is the cycloid x = R(phi - sin phi), y = R(1 - cos phi) (Johann Bernoulli,
//    Acta Eruditorum, 1697); the speed v = sqrt(2 g y) on it gives phi = t sqrt(g/R), hence
//    t_f = phi_f sqrt(R/g) with (phi_f - sin phi_f)/(1 - cos phi_f) = x_f/y_f:
//    phi_f = 3.5083 rad, R = 2.5843 m, t_f = 1.8016031 s.
// 2. Bryson's F-4 minimum time to climb (Bryson, Desai & Hoffman, J. Aircraft 6(6), 1969) in
//    PSOPT's form and data (/work/shared/reference/min_time_to_climb/README.md): PSOPT documents
//    t_f = 321.11 s, measured 321.1089 s with 30-80 LGL nodes.
// 3. Minimum-time double integrator x'' = u, |u| <= 1 from (1, 1) to rest at the origin:
//    bang-bang with t_s = v0 + sqrt(v0^2/2 + x0) = 2.2247449 s, t_f = v0 + 2 sqrt(v0^2/2 + x0)
//    = 3.4494897 s (Kirk, Optimal Control Theory, 1970, ch. 5, minimum-time problems).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "manta/optimal/problems.hpp"

namespace {

using namespace manta::optimal;

TEST(OptimalValidation, BrachistochroneFinalTimeWithin1e6OfTheCycloid) {
    const Brachistochrone p;
    const CycloidSolution c = brachistochrone_cycloid(p.x_final, p.y_final, p.gravity);
    EXPECT_NEAR(c.final_time, 1.8016031, 1e-7);
    const auto m = make_model(p);
    for (const int n : {20, 40}) {
        const Solution s = solve(*m, Mesh::uniform(1, n), p.guess());
        ASSERT_TRUE(s.converged()) << s.status_text;
        EXPECT_NEAR(s.final_time, c.final_time, 1e-6) << n << " nodes";
        EXPECT_LT(s.max_violation, 1e-8);
        EXPECT_LT(s.resimulation.max_scaled_error, 1e-6);
    }
}

TEST(OptimalValidation, MinTimeToClimbMatchesPsopt) {
    // 1976 US Standard Atmosphere (8 layers), natural cubic splines in Mach, PSOPT's row-column
    // bicubic thrust spline. Tolerance 0.02 s (6e-5): the measured PSOPT optimum 321.1089 s is
    // reproduced to 0.001 s at 40 and 80 nodes; the documented 321.11 s within 0.1 %.
    const MinTimeToClimb p;
    const auto m = make_model(p);
    for (const int n : {40, 80}) {
        const Solution s = solve(*m, Mesh::uniform(1, n), p.guess());
        ASSERT_TRUE(s.converged()) << s.status_text;
        EXPECT_NEAR(s.final_time, 321.1089, 0.02) << n << " nodes";
        EXPECT_LT(std::abs(s.final_time - 321.11) / 321.11, 1e-3);
        EXPECT_LT(s.max_violation, 1e-6);
        EXPECT_LT(s.resimulation.max_scaled_error, 1e-2);
        EXPECT_LT(s.iterations, 60);
    }
}

TEST(OptimalValidation, DoubleIntegratorBangBangWithHpRefinement) {
    const DoubleIntegrator p;
    const BangBangSolution exact = double_integrator_bang_bang(p.x0, p.v0);
    EXPECT_NEAR(exact.switch_time, 1.0 + std::sqrt(1.5), 1e-15);
    const auto m = make_model(p);
    // one segment: the polynomial cannot jump; the switch is smeared over ~2 node spacings
    const Solution one = solve(*m, Mesh::uniform(1, 40), p.guess());
    ASSERT_TRUE(one.converged()) << one.status_text;
    EXPECT_NEAR(one.final_time, exact.final_time, 1e-2);
    EXPECT_GT(std::abs(one.final_time - exact.final_time), 1e-4);  // visibly inexact
    const SegmentSolution& g = one.segments[0];
    int first_positive = -1;
    for (Eigen::Index i = 0; i < g.time.size(); ++i) {
        if (g.controls(i, 0) > 0.0) {
            first_positive = static_cast<int>(i);
            break;
        }
    }
    ASSERT_GT(first_positive, 0);
    EXPECT_NEAR(g.time(first_positive), exact.switch_time, 0.2);
    // hp: a break where the control jumps, free, re-solved from the first solution
    const Mesh refined = refine_at_control_jumps(one, 20);
    ASSERT_EQ(refined.n_segments(), 2);
    const Solution two = solve(*m, refined, Guess::from_solution(one));
    ASSERT_TRUE(two.converged()) << two.status_text;
    std::printf("refined: %d + %d points, %d iterations, t_f error %.2e s, break error %.2e s\n",
                refined.nodes[0], refined.nodes[1], two.iterations,
                two.final_time - exact.final_time, two.breaks[1] - exact.switch_time);
    EXPECT_NEAR(two.final_time, exact.final_time, 1e-6);
    EXPECT_NEAR(two.breaks[1], exact.switch_time, 1e-6);
    EXPECT_LT((two.segments[0].controls.array() + 1.0).abs().maxCoeff(), 1e-6);
    EXPECT_LT((two.segments[1].controls.array() - 1.0).abs().maxCoeff(), 1e-6);
    EXPECT_LT(two.resimulation.max_scaled_error, 1e-6);
    EXPECT_GT(one.resimulation.max_scaled_error, 100.0 * two.resimulation.max_scaled_error);
}

}  // namespace
