// Trim and linearisation on the Ranger 2000 (examples/ranger2000/aircraft.yaml): residuals at
// machine precision for level flight, a climb and a coordinated turn; the constraints of
// Stevens, Lewis & Johnson (2015) sec. 3.6 hold at the solution; clear errors where no trim
// exists; the A and B matrices of `linearise` against central finite differences.

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "manta/aircraft/aircraft.hpp"
#include "manta/core/error.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/eom.hpp"
#include "manta/flightdyn/trim.hpp"

namespace fd = manta::flightdyn;
using manta::core::deg;

namespace {

const fd::FlightModel& ranger() {
    static const fd::FlightModel model = [] {
        const auto def = manta::aircraft::load_aircraft(std::string(MANTA_SOURCE_DIR) +
                                                        "/examples/ranger2000/aircraft.yaml");
        fd::FlightModel m = def.flight_model();
        fd::finalize(m);
        return m;
    }();
    return model;
}

fd::TrimTarget target(double V, double h, double gamma = 0.0, double turn_rate = 0.0) {
    fd::TrimTarget t;
    t.airspeed = V;
    t.altitude = h;
    t.climb_angle = gamma;
    t.turn_rate = turn_rate;
    return t;
}

/// Max |d/dt| of (V, alpha, beta, p, q, r) recomputed independently of the trim code.
double dynamic_residual(const fd::FlightModel& m, const fd::TrimResult& r) {
    const auto d = fd::euler_rhs(m, r.state, r.controls);
    double res = 0.0;
    for (int i : {fd::euler::V, fd::euler::alpha, fd::euler::beta, fd::euler::p, fd::euler::q,
                  fd::euler::r})
        res = std::max(res, std::abs(d[i]));
    return res;
}

std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const manta::Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(TrimRanger, LevelFlight150ms3000m) {
    const auto& m = ranger();
    const auto r = fd::trim(m, target(150.0, 3000.0));
    EXPECT_LT(r.residual_norm, 1e-8);
    EXPECT_LT(dynamic_residual(m, r), 1e-8);
    const auto& s = r.state;
    // Wings level, symmetric: the lateral unknowns come out zero, theta = alpha.
    EXPECT_NEAR(s[fd::euler::beta], 0.0, 1e-10);
    EXPECT_NEAR(r.controls.aileron, 0.0, 1e-10);
    EXPECT_NEAR(r.controls.rudder, 0.0, 1e-10);
    EXPECT_EQ(s[fd::euler::phi], 0.0);
    EXPECT_NEAR(s[fd::euler::theta], s[fd::euler::alpha], 1e-14);
    EXPECT_EQ(s[fd::euler::p], 0.0);
    EXPECT_EQ(s[fd::euler::q], 0.0);
    EXPECT_EQ(s[fd::euler::r], 0.0);
    EXPECT_DOUBLE_EQ(s[fd::euler::V], 150.0);
    EXPECT_DOUBLE_EQ(-s[fd::euler::z], 3000.0);
    // Plausible numbers for a jet trainer at 150 m/s.
    EXPECT_GT(s[fd::euler::alpha], deg(0.0));
    EXPECT_LT(s[fd::euler::alpha], deg(6.0));
    EXPECT_GT(r.controls.throttle, 0.05);
    EXPECT_LT(r.controls.throttle, 1.0);
    EXPECT_TRUE(r.violations.empty());
    // Steady: no vertical speed, flying north at V.
    const auto d = fd::euler_rhs(m, r.state, r.controls);
    EXPECT_NEAR(d[fd::euler::z], 0.0, 1e-9);
    EXPECT_NEAR(d[fd::euler::x], 150.0, 1e-9);
    EXPECT_NEAR(d[fd::euler::theta], 0.0, 1e-12);
}

TEST(TrimRanger, Climb5Degrees) {
    const auto& m = ranger();
    const double gamma = deg(5.0);
    const auto level = fd::trim(m, target(150.0, 3000.0));
    const auto r = fd::trim(m, target(150.0, 3000.0, gamma));
    EXPECT_LT(r.residual_norm, 1e-8);
    EXPECT_LT(dynamic_residual(m, r), 1e-8);
    // Rate-of-climb constraint: dh/dt = V sin(gamma); wings level: theta = alpha + gamma.
    const auto d = fd::euler_rhs(m, r.state, r.controls);
    EXPECT_NEAR(-d[fd::euler::z], 150.0 * std::sin(gamma), 1e-9);
    EXPECT_NEAR(r.state[fd::euler::theta], r.state[fd::euler::alpha] + gamma, 1e-12);
    // Climbing needs more thrust: W sin(gamma) = 3765 kg * 9.81 * 0.087 = 3.2 kN more.
    EXPECT_GT(r.controls.throttle, level.controls.throttle + 0.1);
    EXPECT_NEAR(r.controls.aileron, 0.0, 1e-10);
}

TEST(TrimRanger, CoordinatedTurn10DegPerSecond) {
    const auto& m = ranger();
    const double psi_dot = deg(10.0);
    const auto r = fd::trim(m, target(150.0, 3000.0, 0.0, psi_dot));
    EXPECT_LT(r.residual_norm, 1e-8);
    EXPECT_LT(dynamic_residual(m, r), 1e-8);
    const auto& s = r.state;
    const auto d = fd::euler_rhs(m, r.state, r.controls);
    // Steady turn: attitude fixed but for the heading, which turns at psi_dot; level.
    EXPECT_NEAR(d[fd::euler::psi], psi_dot, 1e-12);
    EXPECT_NEAR(d[fd::euler::phi], 0.0, 1e-12);
    EXPECT_NEAR(d[fd::euler::theta], 0.0, 1e-12);
    EXPECT_NEAR(d[fd::euler::z], 0.0, 1e-9);
    // Bank close to the zero-sideslip value atan(psi_dot V / g) (exact for beta = 0 and level
    // flight; S&L eq. 3.6-5 with G = psi_dot V / g).
    const double G = psi_dot * 150.0 / m.environment.gravity;
    EXPECT_NEAR(s[fd::euler::phi], std::atan(G), deg(0.5));
    EXPECT_GT(s[fd::euler::phi], deg(60.0));
    // Body rates of a turn about the vertical: omega = psi_dot (-sin theta, cos theta sin phi, cos
    // theta cos phi).
    const double th = s[fd::euler::theta], ph = s[fd::euler::phi];
    EXPECT_NEAR(s[fd::euler::p], -psi_dot * std::sin(th), 1e-15);
    EXPECT_NEAR(s[fd::euler::q], psi_dot * std::cos(th) * std::sin(ph), 1e-15);
    EXPECT_NEAR(s[fd::euler::r], psi_dot * std::cos(th) * std::cos(ph), 1e-15);
    // A right turn needs (small) controls; the sideslip stays small.
    EXPECT_LT(std::abs(s[fd::euler::beta]), deg(2.0));
    EXPECT_TRUE(r.violations.empty()) << r.violations;
}

TEST(TrimRanger, LeftTurnMirrorsRightTurn) {
    const auto& m = ranger();
    const auto right = fd::trim(m, target(150.0, 3000.0, 0.0, deg(6.0)));
    const auto left = fd::trim(m, target(150.0, 3000.0, 0.0, deg(-6.0)));
    EXPECT_NEAR(left.state[fd::euler::phi], -right.state[fd::euler::phi], 1e-9);
    EXPECT_NEAR(left.state[fd::euler::alpha], right.state[fd::euler::alpha], 1e-9);
    EXPECT_NEAR(left.controls.throttle, right.controls.throttle, 1e-9);
    EXPECT_NEAR(left.controls.aileron, -right.controls.aileron, 1e-9);
    EXPECT_NEAR(left.controls.rudder, -right.controls.rudder, 1e-9);
}

TEST(TrimRanger, HeadingOnlyRotatesThePath) {
    const auto& m = ranger();
    auto t = target(150.0, 3000.0);
    t.heading = deg(90.0);
    const auto r = fd::trim(m, t);
    const auto d = fd::euler_rhs(m, r.state, r.controls);
    EXPECT_NEAR(d[fd::euler::y], 150.0, 1e-9);  // flying east
    EXPECT_NEAR(d[fd::euler::x], 0.0, 1e-9);
    EXPECT_LT(r.residual_norm, 1e-8);
}

TEST(TrimRanger, TooSlowIsNoTrimAndSaysWhy) {
    const auto& m = ranger();
    const std::string msg = message_of([&] { (void)fd::trim(m, target(40.0, 3000.0)); });
    ASSERT_FALSE(msg.empty());
    EXPECT_NE(msg.find("no trim at V = 40 m/s, h = 3000 m"), std::string::npos) << msg;
    EXPECT_NE(msg.find("alpha"), std::string::npos) << msg;
    EXPECT_THROW((void)fd::trim(m, target(40.0, 3000.0)), manta::ConvergenceError);
}

TEST(TrimRanger, TooSteepAClimbNeedsMoreThanFullThrottle) {
    // A 20 deg climb needs W sin(20 deg) = 12.6 kN more than level flight; the engine gives
    // about 10 kN at 3000 m and M 0.46.
    const auto& m = ranger();
    const auto steep = target(150.0, 3000.0, deg(20.0));
    const std::string msg = message_of([&] { (void)fd::trim(m, steep); });
    ASSERT_FALSE(msg.empty());
    EXPECT_NE(msg.find("needs throttle"), std::string::npos) << msg;
    EXPECT_NE(msg.find("> 1"), std::string::npos) << msg;
    // Reported, not thrown, without limit enforcement: the equilibrium itself exists.
    fd::TrimOptions o;
    o.enforce_limits = false;
    const auto r = fd::trim(m, steep, o);
    EXPECT_GT(r.controls.throttle, 1.0);
    EXPECT_LT(r.residual_norm, 1e-8);
    EXPECT_NE(r.violations.find("needs throttle"), std::string::npos);
}

TEST(TrimRanger, BadTargetsAreInputErrors) {
    const auto& m = ranger();
    EXPECT_THROW((void)fd::trim(m, target(0.0, 3000.0)), manta::InputError);
    EXPECT_THROW((void)fd::trim(m, target(-10.0, 3000.0)), manta::InputError);
    EXPECT_THROW((void)fd::trim(m, target(std::nan(""), 3000.0)), manta::InputError);
    EXPECT_THROW((void)fd::trim(m, target(150.0, 1e6)), manta::InputError);
    EXPECT_THROW((void)fd::trim(m, target(150.0, 3000.0, deg(95.0))), manta::InputError);
    EXPECT_THROW((void)fd::trim(m, target(150.0, 3000.0, 0.0, std::nan(""))), manta::InputError);
    const std::string msg = message_of([&] { (void)fd::trim(m, target(-10.0, 3000.0)); });
    EXPECT_NE(msg.find("airspeed -10"), std::string::npos) << msg;
    fd::FlightModel no_aero = m;
    no_aero.aero.reset();
    EXPECT_THROW((void)fd::trim(no_aero, target(150.0, 3000.0)), manta::InputError);
}

TEST(Linearise, MatchesCentralDifferences) {
    const auto& m = ranger();
    // About a turning trim so that every coupling is present.
    const auto r = fd::trim(m, target(150.0, 3000.0, deg(2.0), deg(5.0)));
    const auto lin = fd::linearise(m, r.state, r.controls);
    auto f = [&](const fd::EulerState<double>& x, const fd::Controls<double>& u) {
        return fd::euler_rhs(m, x, u);
    };
    for (int j = 0; j < fd::euler::size; ++j) {
        // Steps small enough that no table breakpoint is crossed, large enough for rounding.
        const double h =
            (j == fd::euler::x || j == fd::euler::y || j == fd::euler::z || j == fd::euler::V)
                ? 1e-3
                : 1e-6;
        fd::EulerState<double> xp = r.state, xm = r.state;
        xp[j] += h;
        xm[j] -= h;
        const fd::EulerState<double> fdiff = (f(xp, r.controls) - f(xm, r.controls)) / (2.0 * h);
        for (int i = 0; i < fd::euler::size; ++i) {
            EXPECT_NEAR(lin.A(i, j), fdiff[i], 1e-6 * std::max(1.0, std::abs(fdiff[i])))
                << "A(" << i << ", " << j << ")";
        }
    }
    for (int j = 0; j < 4; ++j) {
        const double h = 1e-6;
        fd::Controls<double> up = r.controls, um = r.controls;
        double* pu[4] = {&up.elevator, &up.aileron, &up.rudder, &up.throttle};
        double* mu[4] = {&um.elevator, &um.aileron, &um.rudder, &um.throttle};
        *pu[j] += h;
        *mu[j] -= h;
        const fd::EulerState<double> fdiff = (f(r.state, up) - f(r.state, um)) / (2.0 * h);
        for (int i = 0; i < fd::euler::size; ++i) {
            EXPECT_NEAR(lin.B(i, j), fdiff[i], 1e-6 * std::max(1.0, std::abs(fdiff[i])))
                << "B(" << i << ", " << j << ")";
        }
    }
    EXPECT_EQ(lin.x0, r.state);
}

TEST(Linearise, TrimPointIsAnEquilibriumOfTheDynamics) {
    // The dynamic rows of f vanish at trim, so A x + B u describes perturbations only.
    const auto& m = ranger();
    const auto r = fd::trim(m, target(150.0, 3000.0));
    const auto lin = fd::linearise(m, r.state, r.controls);
    // Elevator step: pitch acceleration is nose-down for trailing edge down (Cm_de < 0).
    EXPECT_LT(lin.B(fd::euler::q, 0), 0.0);
    // Aileron: right wing down (Cl_da > 0) -> dp/dt > 0.
    EXPECT_GT(lin.B(fd::euler::p, 1), 0.0);
    // Rudder trailing edge left: nose left (Cn_dr < 0) -> dr/dt < 0.
    EXPECT_LT(lin.B(fd::euler::r, 2), 0.0);
    // Throttle accelerates.
    EXPECT_GT(lin.B(fd::euler::V, 3), 0.0);
}
