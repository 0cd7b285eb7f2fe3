// The plain-double fast paths of the equations of motion against the paths they replace: the
// single table pass for the alpha-dot/beta-dot solve against the three-pass solve, euler_rhs and
// quaternion_rhs in double against the same templates in AD scalars (std::sin, std::pow, three
// passes), the cached inverse inertia, and the atmosphere and engine lapse written as exp/log.

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "manta/core/autodiff.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/atmosphere.hpp"
#include "manta/flightdyn/eom.hpp"
#include "random_states.hpp"
#include "test_sim_models.hpp"

namespace fd = manta::flightdyn;
using manta::core::deg;
using manta::core::Dual;

namespace {

using Case = manta::test::RandomCase;
using manta::test::max_rel;

/// States over the tables (and a little beyond them), all attitudes and headings.
std::vector<Case> random_cases(int n, unsigned seed) {
    return manta::test::random_cases(n, seed, {60, 240, -10, 24, 12});
}

Eigen::Matrix<double, 6, 1> coefficients(const fd::Loads<double>& L) {
    const auto& C = L.coefficients;
    return (Eigen::Matrix<double, 6, 1>() << C.CX, C.CY, C.CZ, C.Cl, C.Cm, C.Cn).finished();
}

template <int N>
Eigen::Matrix<double, N, 1> values(const Eigen::Matrix<Dual, N, 1>& x) {
    Eigen::Matrix<double, N, 1> v;
    for (int i = 0; i < N; ++i) v[i] = x[i].value();
    return v;
}

}  // namespace

// The single-pass solve gives the loads of the three-pass solve to rounding, with and without
// beta-dot columns, multilinear and C1.
TEST(SinglePassAngleRates, LoadsMatchTheThreePassSolve) {
    const fd::FlightModel ranger = manta::test::ranger_like();
    const fd::FlightModel both = manta::test::with_beta_dot(ranger);
    fd::FlightModel both_c1 = both;
    both_c1.name += ", C1";
    both_c1.interpolation = manta::aero::Interpolation::c1;
    ASSERT_TRUE(ranger.alpha_dot_terms && !ranger.beta_dot_terms);
    ASSERT_TRUE(both.alpha_dot_terms && both.beta_dot_terms);
    for (const fd::FlightModel* m : {&ranger, &both, &std::as_const(both_c1)}) {
        double worst_F = 0.0, worst_M = 0.0, worst_C = 0.0;
        for (const Case& c : random_cases(500, 11)) {
            const auto& s = c.state;
            const double V = s[fd::euler::V], a = s[fd::euler::alpha], b = s[fd::euler::beta];
            const fd::Vec3<double> v(V * std::cos(a) * std::cos(b), V * std::sin(b),
                                     V * std::sin(a) * std::cos(b));
            const fd::Vec3<double> w(s[fd::euler::p], s[fd::euler::q], s[fd::euler::r]);
            const double g = m->environment.gravity, th = s[fd::euler::theta],
                         ph = s[fd::euler::phi];
            const fd::Vec3<double> g_body(-g * std::sin(th), g * std::sin(ph) * std::cos(th),
                                          g * std::cos(ph) * std::cos(th));
            const double h = -s[fd::euler::z];
            const auto fast =
                fd::detail::consistent_loads(*m, h, v, V, a, b, w, c.controls, g_body);
            const auto ref =
                fd::detail::consistent_loads_passes(*m, h, v, V, a, b, w, c.controls, g_body);
            worst_F = std::max(
                worst_F, (fast.force_body - ref.force_body).norm() / (1.0 + ref.force_body.norm()));
            worst_M = std::max(worst_M, (fast.moment_body - ref.moment_body).norm() /
                                            (1.0 + ref.moment_body.norm()));
            worst_C = std::max(worst_C, max_rel(coefficients(fast), coefficients(ref)));
            EXPECT_EQ(fast.thrust, ref.thrust);
            EXPECT_EQ(fast.dynamic_pressure, ref.dynamic_pressure);
        }
        EXPECT_LT(worst_F, 1e-12) << m->name;
        EXPECT_LT(worst_M, 1e-12) << m->name;
        EXPECT_LT(worst_C, 1e-12) << m->name;
    }
}

// With both angle rates, the loads euler_rhs returns are the tables at the alpha-dot and beta-dot
// it returns (fixed point of the implicit equations).
TEST(SinglePassAngleRates, BetaDotSolveIsAFixedPoint) {
    const fd::FlightModel m = manta::test::with_beta_dot(manta::test::ranger_like());
    for (const Case& c : random_cases(50, 5)) {
        fd::Loads<double> L;
        const auto d = fd::euler_rhs(m, c.state, c.controls, &L);
        const double V = c.state[fd::euler::V], b = m.reference.span, ch = m.reference.chord;
        manta::aero::AeroQuery<double> q;
        q.alpha = c.state[fd::euler::alpha];
        q.beta = c.state[fd::euler::beta];
        q.mach = L.mach;
        q.p_hat = c.state[fd::euler::p] * b / (2 * V);
        q.q_hat = c.state[fd::euler::q] * ch / (2 * V);
        q.r_hat = c.state[fd::euler::r] * b / (2 * V);
        q.alpha_dot_hat = d[fd::euler::alpha] * ch / (2 * V);
        q.beta_dot_hat = d[fd::euler::beta] * b / (2 * V);
        q.elevator = c.controls.elevator;
        q.aileron = c.controls.aileron;
        q.rudder = c.controls.rudder;
        const auto C = m.aero->evaluate(q, m.interpolation);
        EXPECT_NEAR(L.coefficients.CY, C.CY, 1e-12);
        EXPECT_NEAR(L.coefficients.Cn, C.Cn, 1e-12);
        EXPECT_NEAR(L.coefficients.Cl, C.Cl, 1e-12);
        EXPECT_NEAR(L.coefficients.Cm, C.Cm, 1e-12);
        EXPECT_NEAR(L.coefficients.CZ, C.CZ, 1e-12);
    }
}

// euler_rhs and quaternion_rhs in double (fast sine and cosine, exp/log, one table pass, cached
// inverse inertia) equal the same templates run with AD scalars (std::sin, std::pow, three table
// passes, inverse per call) to rounding.
TEST(SinglePassAngleRates, DoubleRhsMatchesTheAutomaticDifferentiationPath) {
    auto rigid = manta::test::rigid_body(5000.0, 8000.0, 25000.0, 30000.0, 1000.0);
    rigid.engine.static_thrust_sl = 14000.0;
    rigid.engine.thrust_angle = deg(2.0);
    const fd::FlightModel ranger = manta::test::ranger_like();
    const fd::FlightModel both = manta::test::with_beta_dot(ranger);
    // Constants with a short derivative vector (length 1 trips a GCC -Warray-bounds false
    // positive inside Eigen).
    auto constant = [](double v) { return manta::core::make_constant(v, 2); };
    for (const fd::FlightModel* m : {&std::as_const(rigid), &ranger, &both}) {
        double worst_e = 0.0, worst_q = 0.0;
        for (const Case& c : random_cases(200, 3)) {
            fd::EulerState<Dual> sd;
            for (int i = 0; i < fd::euler::size; ++i) sd[i] = constant(c.state[i]);
            fd::Controls<Dual> ud;
            ud.elevator = constant(c.controls.elevator);
            ud.aileron = constant(c.controls.aileron);
            ud.rudder = constant(c.controls.rudder);
            ud.throttle = constant(c.controls.throttle);
            const auto de = fd::euler_rhs(*m, c.state, c.controls);
            worst_e = std::max(worst_e, max_rel(de, values(fd::euler_rhs(*m, sd, ud))));
            const fd::QuatState<double> x = fd::to_quaternion_state(c.state);
            fd::QuatState<Dual> xd;
            for (int i = 0; i < fd::quat::size; ++i) xd[i] = constant(x[i]);
            const auto dq = fd::quaternion_rhs(*m, x, c.controls);
            worst_q = std::max(worst_q, max_rel(dq, values(fd::quaternion_rhs(*m, xd, ud))));
        }
        EXPECT_LT(worst_e, 1e-12) << m->name;
        EXPECT_LT(worst_q, 1e-12) << m->name;
    }
}

// The inverse inertia cached by finalize is used only while the inertia is the one it inverts.
TEST(InertiaInverseCache, AChangedInertiaIsNeverPairedWithAStaleInverse) {
    const fd::FlightModel m = manta::test::ranger_like();
    const Case c = random_cases(1, 17).front();
    const auto d0 = fd::euler_rhs(m, c.state, c.controls);
    fd::FlightModel changed = m;  // inertia changed after finalize, not finalized again
    changed.mass.inertia(0, 2) = changed.mass.inertia(2, 0) = -900.0;
    changed.mass.inertia(1, 1) *= 1.1;
    fd::FlightModel refinalized = changed;
    fd::finalize(refinalized);
    const auto d1 = fd::euler_rhs(changed, c.state, c.controls);
    const auto d2 = fd::euler_rhs(refinalized, c.state, c.controls);
    EXPECT_EQ(d1, d2);
    EXPECT_NE(d1[fd::euler::p], d0[fd::euler::p]);
    EXPECT_NE(d1[fd::euler::q], d0[fd::euler::q]);
    // A model never finalized inverts on every call.
    fd::FlightModel bare = m;
    bare.inertia_inverse = Eigen::Matrix3d::Zero();
    bare.inertia_inverse_of.setConstant(std::nan(""));
    EXPECT_EQ(fd::euler_rhs(bare, c.state, c.controls), d0);
}

// The double atmosphere (exp/log instead of pow, ln(sigma) from the same logarithm) and the
// engine lapse exp(n ln sigma) agree with the reference formulas (the AD path, std::pow) to
// rounding: a few ulp, times the exponent k = g0 / (R L) that amplifies any rounding of T / T_base.
TEST(FastAtmosphere, MatchesTheReferenceFormulasToRounding) {
    using fd::us1976_constants::reference_density;
    fd::EngineModel engine;
    engine.static_thrust_sl = 14190.0;
    for (double h = fd::us1976_constants::h_bottom; h <= fd::us1976_constants::h_top; h += 37.0) {
        const auto a = fd::us1976_geopotential(h);
        const auto r = fd::us1976_geopotential(manta::core::make_constant(h, 2));
        SCOPED_TRACE("h = " + std::to_string(h));
        EXPECT_EQ(a.temperature, r.temperature.value());
        EXPECT_NEAR(a.pressure, r.pressure.value(), 1e-14 * r.pressure.value());
        EXPECT_NEAR(a.density, r.density.value(), 1e-14 * r.density.value());
        EXPECT_NEAR(a.log_density_ratio, std::log(a.density / reference_density), 1e-14);
        EXPECT_NEAR(r.log_density_ratio.value(), std::log(a.density / reference_density), 1e-14);
        const double sigma = a.density / reference_density;
        const double t4 = engine.thrust_at(h, 0.5, 0.8, sigma);
        const double t5 = engine.thrust_at(h, 0.5, 0.8, sigma, a.log_density_ratio);
        EXPECT_NEAR(t5, t4, 1e-14 * t4);
    }
    // Sea level: sigma = 1 up to the printed reference density.
    EXPECT_NEAR(fd::us1976(0.0).log_density_ratio, 0.0, 2e-6);
}
