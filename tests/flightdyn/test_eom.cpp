// Equations of motion: conversions, consistency of the two state forms, analytic motions
// (free fall, torque-free rigid body) and automatic derivatives.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <string>

#include "manta/aircraft/aircraft.hpp"
#include "manta/core/autodiff.hpp"
#include "manta/core/frames.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/eom.hpp"
#include "manta/flightdyn/simulate.hpp"
#include "test_sim_models.hpp"

namespace fd = manta::flightdyn;
using manta::core::deg;

namespace {

fd::EulerState<double> make_state(double V, double altitude) {
    fd::EulerState<double> s = fd::EulerState<double>::Zero();
    s[fd::euler::z] = -altitude;
    s[fd::euler::V] = V;
    return s;
}

/// A general state away from table breakpoints and singularities.
fd::EulerState<double> general_state() {
    fd::EulerState<double> s;
    s << 120.0, -40.0, -3100.0, deg(23.0), deg(11.0), deg(-37.0), 143.0, deg(5.3), deg(2.9), 0.21,
        -0.07, 0.13;
    return s;
}

fd::Controls<double> general_controls() {
    fd::Controls<double> u;
    u.elevator = deg(-3.3);
    u.aileron = deg(2.2);
    u.rudder = deg(-1.1);
    u.throttle = 0.63;
    return u;
}

/// Rotation-invariant comparison of attitudes: max |C1 - C2|.
double dcm_distance(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
    return (a - b).cwiseAbs().maxCoeff();
}

/// Angular momentum about the CG in earth axes from an output row (phi theta psi p q r).
Eigen::Vector3d h_earth(const fd::FlightModel& m, const std::vector<double>& row) {
    const Eigen::Vector3d w(row[10], row[11], row[12]);
    return manta::core::dcm_earth_from_body(row[4], row[5], row[6]) * (m.mass.inertia * w);
}

}  // namespace

// ---------------------------------------------------------------------------------- conversions

TEST(Conversions, EulerQuaternionRoundTrip) {
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> ang(-manta::core::pi, manta::core::pi);
    std::uniform_real_distribution<double> pitch(deg(-89.5), deg(89.5));
    for (int i = 0; i < 1000; ++i) {
        const double phi = ang(rng), theta = pitch(rng), psi = ang(rng);
        const Eigen::Vector4d q = fd::quaternion_from_euler(phi, theta, psi);
        EXPECT_NEAR(q.norm(), 1.0, 1e-15);
        const Eigen::Vector3d e = fd::euler_from_quaternion(q);
        EXPECT_NEAR(e[0], phi, 1e-9);
        EXPECT_NEAR(e[1], theta, 1e-9);
        EXPECT_NEAR(e[2], psi, 1e-9);
        // The quaternion and the Euler angles give the same direction-cosine matrix.
        EXPECT_LT(dcm_distance(manta::core::dcm_earth_from_quaternion(q),
                               manta::core::dcm_earth_from_body(phi, theta, psi)),
                  1e-14);
    }
}

TEST(Conversions, DcmIsAProperRotationAndMatchesTheNavigationEquation) {
    const double phi = deg(30.0), theta = deg(-20.0), psi = deg(135.0);
    const Eigen::Matrix3d c = manta::core::dcm_earth_from_body(phi, theta, psi);
    EXPECT_LT((c * c.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-15);
    EXPECT_NEAR(c.determinant(), 1.0, 1e-15);
    // Body x axis in earth axes: heading psi, pitched up by theta.
    EXPECT_NEAR(c(0, 0), std::cos(theta) * std::cos(psi), 1e-15);
    EXPECT_NEAR(c(2, 0), -std::sin(theta), 1e-15);
}

TEST(Conversions, StateFormsRoundTrip) {
    const fd::EulerState<double> s = general_state();
    const fd::QuatState<double> q = fd::to_quaternion_state(s);
    const fd::EulerState<double> back = fd::to_euler_state(q);
    EXPECT_LT((back - s).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_NEAR(q.segment<3>(fd::quat::u).norm(), s[fd::euler::V], 1e-12);
    // Body velocity components from (V, alpha, beta).
    EXPECT_NEAR(q[fd::quat::v], s[fd::euler::V] * std::sin(s[fd::euler::beta]), 1e-12);
    EXPECT_NEAR(std::atan2(q[fd::quat::w], q[fd::quat::u]), s[fd::euler::alpha], 1e-14);
}

// ------------------------------------------------------------------ the two forms, same physics

namespace {

/// Check that the quaternion derivative is the Euler derivative mapped through the conversion.
void expect_forms_consistent(const fd::FlightModel& m, const fd::EulerState<double>& s,
                             const fd::Controls<double>& u) {
    const fd::EulerState<double> de = fd::euler_rhs(m, s, u);
    const fd::QuatState<double> q = fd::to_quaternion_state(s);
    const fd::QuatState<double> dq = fd::quaternion_rhs(m, q, u);
    // d/dt of to_quaternion_state(s) by a central difference along de.
    const double h = 1e-6;
    const fd::QuatState<double> fd_dq =
        (fd::to_quaternion_state(s + h * de) - fd::to_quaternion_state(s - h * de)) / (2 * h);
    for (int i = 0; i < fd::quat::size; ++i) {
        SCOPED_TRACE("quaternion state index " + std::to_string(i));
        EXPECT_NEAR(dq[i], fd_dq[i], 1e-6 * (1.0 + std::abs(dq[i])));
    }
}

}  // namespace

TEST(StateForms, DerivativesAgreeWithoutAero) {
    auto m = manta::test::rigid_body(5000.0, 8000.0, 25000.0, 30000.0, 1000.0);
    m.engine.static_thrust_sl = 14000.0;
    m.engine.thrust_angle = deg(2.0);
    expect_forms_consistent(m, general_state(), general_controls());
}

TEST(StateForms, DerivativesAgreeWithAeroTables) {
    const auto m = manta::test::ranger_like();
    expect_forms_consistent(m, general_state(), general_controls());
}

// -------------------------------------------------------------------------- analytic motions

TEST(AnalyticMotion, FreeFallFromRest) {
    // No aero, no thrust, V = 0 (singular for the Euler form, so the quaternion form).
    const auto m = manta::test::rigid_body(1000.0, 1000.0, 2000.0, 2500.0);
    for (auto integ : {fd::Integrator::rk4, fd::Integrator::dopri5}) {
        SCOPED_TRACE(std::string(fd::to_string(integ)));
        fd::SimulationOptions opt;
        opt.duration = 20.0;
        opt.dt = 0.01;
        opt.output_interval = 0.5;
        opt.integrator = integ;
        opt.rtol = 1e-12;
        opt.atol = 1e-10;
        const auto r = fd::simulate(m, make_state(0.0, 5000.0), fd::InputHistory(), opt);
        ASSERT_EQ(r.end_reason, fd::EndReason::completed);
        const double g = m.environment.gravity;
        for (const auto& row : r.rows) {
            const double t = row[0];
            // z(t) = z0 + g t^2 / 2. RK4 integrates a quadratic exactly; dopri5 too (order 5).
            EXPECT_NEAR(row[3], -5000.0 + 0.5 * g * t * t, 1e-8 * (1.0 + t * t));
            EXPECT_NEAR(row[1], 0.0, 1e-12);
            EXPECT_NEAR(row[7], g * t, 1e-9 * (1.0 + t));  // V
            EXPECT_NEAR(row[5], 0.0, 1e-15);               // attitude unchanged
            EXPECT_NEAR(row[19], 0.0, 1e-15);              // nz: no aero or thrust force
        }
    }
}

TEST(AnalyticMotion, SpinAboutAPrincipalAxisStaysConstant) {
    auto m = manta::test::rigid_body(1000.0, 1000.0, 2000.0, 3000.0);
    m.environment.gravity = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
        SCOPED_TRACE("axis " + std::to_string(axis));
        fd::EulerState<double> s = make_state(0.0, 5000.0);
        s[fd::euler::p + axis] = 0.7;
        fd::SimulationOptions opt;
        opt.duration = 10.0;
        opt.dt = 0.005;
        opt.output_interval = 0.5;
        const auto r = fd::simulate(m, s, fd::InputHistory(), opt);
        for (const auto& row : r.rows) {
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(row[10 + k], k == axis ? 0.7 : 0.0, 1e-13);
        }
        // The attitude turns about that axis at 0.7 rad/s: the rotation angle of the final DCM.
        const auto& last = r.rows.back();
        const Eigen::Matrix3d c = manta::core::dcm_earth_from_body(last[4], last[5], last[6]);
        const double angle = std::acos(std::clamp((c.trace() - 1.0) / 2.0, -1.0, 1.0));
        const double expected = std::remainder(0.7 * 10.0, 2 * manta::core::pi);
        EXPECT_NEAR(angle, std::abs(expected), 1e-9);
    }
}

TEST(AnalyticMotion, TorqueFreeIntermediateAxisFlipsAndConservesEnergyAndMomentum) {
    // Ixx < Iyy < Izz, spin about y (intermediate) with a small perturbation: the spin axis
    // flips periodically (the tennis-racket / Dzhanibekov effect) while the rotational energy,
    // |H| and the inertial angular-momentum vector stay constant.
    auto m = manta::test::rigid_body(1000.0, 1000.0, 2000.0, 3000.0);
    m.environment.gravity = 0.0;
    fd::EulerState<double> s = make_state(0.0, 5000.0);
    s[fd::euler::p] = 1e-3;
    s[fd::euler::q] = 1.0;
    s[fd::euler::r] = 1e-3;
    fd::SimulationOptions opt;
    opt.duration = 40.0;
    opt.dt = 0.002;
    opt.output_interval = 0.1;
    const auto r = fd::simulate(m, s, fd::InputHistory(), opt);
    const auto energy = [&](const std::vector<double>& row) {
        const Eigen::Vector3d w(row[10], row[11], row[12]);
        return 0.5 * w.dot(m.mass.inertia * w);
    };
    const double e0 = energy(r.rows.front());
    const Eigen::Vector3d h0 = h_earth(m, r.rows.front());
    double q_min = 1.0, max_de = 0.0, max_dh = 0.0, max_dhv = 0.0;
    for (const auto& row : r.rows) {
        q_min = std::min(q_min, row[11]);
        max_de = std::max(max_de, std::abs(energy(row) / e0 - 1.0));
        const Eigen::Vector3d w(row[10], row[11], row[12]);
        max_dh = std::max(max_dh, std::abs((m.mass.inertia * w).norm() / h0.norm() - 1.0));
        max_dhv = std::max(max_dhv, (h_earth(m, row) - h0).norm() / h0.norm());
    }
    EXPECT_LT(q_min, -0.9) << "the spin about the intermediate axis should flip";
    // RK4 local error ~ (|w| dt)^5 per step: 2e4 steps of (0.002)^5 -> ~1e-10 at most.
    EXPECT_LT(max_de, 1e-10);
    EXPECT_LT(max_dh, 1e-10);
    EXPECT_LT(max_dhv, 1e-8);  // includes the attitude integration (quaternion)
}

TEST(AnalyticMotion, TorqueFreeWithProductOfInertiaConservesInvariants) {
    auto m = manta::test::rigid_body(5000.0, 8000.0, 25000.0, 30000.0, 3000.0);
    m.environment.gravity = 0.0;
    fd::EulerState<double> s = make_state(0.0, 5000.0);
    s[fd::euler::p] = 0.5;
    s[fd::euler::q] = -0.3;
    s[fd::euler::r] = 0.2;
    for (auto integ : {fd::Integrator::rk4, fd::Integrator::dopri5}) {
        SCOPED_TRACE(std::string(fd::to_string(integ)));
        fd::SimulationOptions opt;
        opt.duration = 30.0;
        opt.dt = 0.005;
        opt.output_interval = 0.5;
        opt.integrator = integ;
        opt.rtol = 1e-12;
        opt.atol = 1e-12;
        opt.max_step = 0.05;
        const auto r = fd::simulate(m, s, fd::InputHistory(), opt);
        const Eigen::Vector3d h0 = h_earth(m, r.rows.front());
        for (const auto& row : r.rows) EXPECT_LT((h_earth(m, row) - h0).norm() / h0.norm(), 1e-9);
    }
}

TEST(AnalyticMotion, QuaternionNormIsHeld) {
    // Integrate the quaternion form directly with a coarse step: the k (1 - |q|^2) q term pulls
    // the norm back to 1.
    auto m = manta::test::rigid_body(1000.0, 1000.0, 2000.0, 3000.0);
    m.environment.gravity = 0.0;
    fd::EulerState<double> s = make_state(0.0, 5000.0);
    s[fd::euler::p] = 2.0;
    s[fd::euler::q] = 1.0;
    s[fd::euler::r] = -1.5;
    fd::QuatState<double> x = fd::to_quaternion_state(s);
    x[fd::quat::q0] *= 1.01;  // start off the unit sphere
    const fd::Controls<double> u;
    const double dt = 0.02;
    for (int i = 0; i < 5000; ++i) {
        const auto k1 = fd::quaternion_rhs(m, x, u);
        const auto k2 = fd::quaternion_rhs(m, fd::QuatState<double>(x + 0.5 * dt * k1), u);
        const auto k3 = fd::quaternion_rhs(m, fd::QuatState<double>(x + 0.5 * dt * k2), u);
        const auto k4 = fd::quaternion_rhs(m, fd::QuatState<double>(x + dt * k3), u);
        x += dt / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
    EXPECT_NEAR(x.segment<4>(fd::quat::q0).norm(), 1.0, 1e-6);
}

// ------------------------------------------------------------------ automatic differentiation

namespace {

/// Jacobian of euler_rhs w.r.t. (state, controls) by AD and by central differences.
void expect_ad_matches_fd(const fd::FlightModel& m, const fd::EulerState<double>& s,
                          const fd::Controls<double>& u) {
    using manta::core::Dual;
    const int n = fd::euler::size, nu = 4, nt = n + nu;
    fd::EulerState<Dual> sd;
    for (int i = 0; i < n; ++i) sd[i] = manta::core::make_dual(s[i], nt, i);
    fd::Controls<Dual> ud;
    ud.elevator = manta::core::make_dual(u.elevator, nt, n + 0);
    ud.aileron = manta::core::make_dual(u.aileron, nt, n + 1);
    ud.rudder = manta::core::make_dual(u.rudder, nt, n + 2);
    ud.throttle = manta::core::make_dual(u.throttle, nt, n + 3);
    const fd::EulerState<Dual> d = fd::euler_rhs(m, sd, ud);
    const fd::EulerState<double> d0 = fd::euler_rhs(m, s, u);

    auto eval = [&](int j, double h) {
        fd::EulerState<double> sp = s;
        fd::Controls<double> up = u;
        if (j < n) {
            sp[j] += h;
        } else {
            double* c[] = {&up.elevator, &up.aileron, &up.rudder, &up.throttle};
            *c[j - n] += h;
        }
        return fd::euler_rhs(m, sp, up);
    };
    for (int j = 0; j < nt; ++j) {
        // Steps small against the table cells (2 deg, 0.1 Mach) so no breakpoint is crossed.
        double h = 1e-6;  // angles [rad], rates [rad/s], controls
        if (j == fd::euler::x || j == fd::euler::y) h = 1.0;  // no dependence: any step
        if (j == fd::euler::z) h = 1e-2;                      // [m]
        if (j == fd::euler::V) h = 1e-4;                      // [m/s]
        const fd::EulerState<double> fdj = (eval(j, h) - eval(j, -h)) / (2 * h);
        for (int i = 0; i < n; ++i) {
            SCOPED_TRACE("d f[" + std::to_string(i) + "] / d x[" + std::to_string(j) + "]");
            EXPECT_NEAR(d[i].value(), d0[i], 1e-12 * (1.0 + std::abs(d0[i])));
            EXPECT_NEAR(d[i].derivatives()[j], fdj[i], 1e-6 * (1.0 + std::abs(fdj[i])));
        }
    }
}

}  // namespace

TEST(AutomaticDerivatives, EulerRhsMatchesFiniteDifferencesWithoutAero) {
    auto m = manta::test::rigid_body(5000.0, 8000.0, 25000.0, 30000.0, 1000.0);
    m.engine.static_thrust_sl = 14000.0;
    m.engine.thrust_angle = deg(2.0);
    expect_ad_matches_fd(m, general_state(), general_controls());
}

TEST(AutomaticDerivatives, EulerRhsMatchesFiniteDifferencesWithAeroTables) {
    const auto m = manta::test::ranger_like();
    expect_ad_matches_fd(m, general_state(), general_controls());
}

// The alpha-dot terms make the equations implicit; euler_rhs solves them exactly. The loads it
// returns must equal the table value at the alpha-dot it returns (fixed point), and the Ranger,
// whose tables have alpha-dot but no beta-dot columns, must be flagged accordingly.
TEST(EomAngleRates, AlphaDotSolveIsAFixedPoint) {
    const auto ac = manta::aircraft::load_aircraft(std::string(MANTA_SOURCE_DIR) +
                                                   "/examples/ranger2000/aircraft.yaml");
    const fd::FlightModel m = ac.flight_model();
    ASSERT_TRUE(m.alpha_dot_terms);
    ASSERT_FALSE(m.beta_dot_terms);
    fd::EulerState<double> s = fd::EulerState<double>::Zero();
    s[fd::euler::z] = -3000.0;
    s[fd::euler::V] = 140.0;
    s[fd::euler::alpha] = 0.08;
    s[fd::euler::beta] = 0.03;
    s[fd::euler::theta] = 0.1;
    s[fd::euler::phi] = 0.3;
    s[fd::euler::q] = 0.2;
    s[fd::euler::p] = -0.1;
    fd::Controls<double> u;
    u.elevator = -0.05;
    u.throttle = 0.6;
    fd::Loads<double> L;
    const auto d = fd::euler_rhs(m, s, u, &L);
    const double V = s[fd::euler::V], b = m.reference.span, c = m.reference.chord;
    manta::aero::AeroQuery<double> q;
    q.alpha = s[fd::euler::alpha];
    q.beta = s[fd::euler::beta];
    q.mach = L.mach;
    q.p_hat = s[fd::euler::p] * b / (2 * V);
    q.q_hat = s[fd::euler::q] * c / (2 * V);
    q.r_hat = s[fd::euler::r] * b / (2 * V);
    q.alpha_dot_hat = d[fd::euler::alpha] * c / (2 * V);
    q.beta_dot_hat = d[fd::euler::beta] * b / (2 * V);
    q.elevator = u.elevator;
    const auto C = m.aero->evaluate(q, m.interpolation);
    EXPECT_NEAR(L.coefficients.CZ, C.CZ, 1e-12);
    EXPECT_NEAR(L.coefficients.Cm, C.Cm, 1e-12);
    EXPECT_NEAR(L.coefficients.CX, C.CX, 1e-12);
    // And the alpha-dot term is not negligible here, so the check has teeth.
    q.alpha_dot_hat = 0.0;
    EXPECT_GT(std::abs(m.aero->evaluate(q, m.interpolation).Cm - C.Cm), 1e-6);
}
