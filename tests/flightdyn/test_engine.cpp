// Engine thrust models: the density-ratio lapse law and the (altitude, Mach, throttle) table.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "manta/core/autodiff.hpp"
#include "manta/core/error.hpp"
#include "manta/flightdyn/atmosphere.hpp"
#include "manta/flightdyn/engine.hpp"

namespace fd = manta::flightdyn;

namespace {

fd::EngineModel lapse_engine() {
    fd::EngineModel e;
    e.type = fd::EngineModel::Type::lapse;
    e.static_thrust_sl = 14000.0;
    e.density_exponent = 0.7;
    e.mach_a1 = -0.3;
    e.mach_a2 = 0.15;
    return e;
}

/// A table that is trilinear in (h, M, throttle): thrust = f(h, M, dt) = c0 + c1 h + c2 M + c3 dt +
/// c4 h M dt.
double trilinear(double h, double M, double dt) {
    return 1000.0 - 0.05 * h + 3000.0 * M + 20000.0 * dt + 0.01 * h * M * dt;
}

fd::EngineModel table_engine() {
    fd::EngineModel e;
    e.type = fd::EngineModel::Type::table;
    e.altitude = {0.0, 3000.0, 6000.0, 12000.0};
    e.mach = {0.0, 0.3, 0.6, 0.9};
    e.throttle = {0.0, 0.5, 1.0};
    for (double h : e.altitude)
        for (double M : e.mach)
            for (double t : e.throttle) e.thrust.push_back(trilinear(h, M, t));
    return e;
}

}  // namespace

TEST(EngineLapse, StaticSeaLevelThrustScalesWithThrottle) {
    const auto e = lapse_engine();
    EXPECT_DOUBLE_EQ(e.thrust_at(0.0, 0.0, 1.0, 1.0), 14000.0);
    EXPECT_DOUBLE_EQ(e.thrust_at(0.0, 0.0, 0.5, 1.0), 7000.0);
    EXPECT_DOUBLE_EQ(e.thrust_at(0.0, 0.0, 0.0, 1.0), 0.0);
    EXPECT_NO_THROW(e.validate("test engine"));
}

TEST(EngineLapse, DensityAndMachLapse) {
    const auto e = lapse_engine();
    const double h = 6000.0;
    const double sigma = fd::us1976(h).density / 1.225;
    for (double M : {0.0, 0.3, 0.6}) {
        const double expected =
            0.8 * 14000.0 * std::pow(sigma, 0.7) * (1.0 - 0.3 * M + 0.15 * M * M);
        EXPECT_NEAR(e.thrust_at(h, M, 0.8, sigma), expected, 1e-9 * expected);
    }
    // Thrust falls with altitude (sigma^0.7 < 1) and, for these coefficients, with Mach below M
    // = 1.
    EXPECT_LT(e.thrust_at(h, 0.3, 1.0, sigma), e.thrust_at(0.0, 0.3, 1.0, 1.0));
    EXPECT_LT(e.thrust_at(0.0, 0.5, 1.0, 1.0), e.thrust_at(0.0, 0.2, 1.0, 1.0));
}

TEST(EngineLapse, RejectsBadCoefficients) {
    auto e = lapse_engine();
    e.static_thrust_sl = -1.0;
    EXPECT_THROW(e.validate("test engine"), manta::InputError);
    e = lapse_engine();
    e.density_exponent = std::nan("");
    EXPECT_THROW(e.validate("test engine"), manta::InputError);
}

TEST(EngineTable, ReproducesTrilinearDataInsideAndExtrapolatesLinearly) {
    const auto e = table_engine();
    ASSERT_NO_THROW(e.validate("table engine"));
    // At grid points, inside cells and outside the table (linear extrapolation of the edge cell:
    // exact for data that are linear in each variable).
    const double pts[][3] = {{0.0, 0.0, 0.0},      {3000.0, 0.3, 0.5},  {4500.0, 0.45, 0.75},
                             {1234.0, 0.81, 0.13}, {15000.0, 0.5, 0.5}, {-500.0, 0.2, 0.9},
                             {7000.0, 1.1, 1.0}};
    for (const auto& p : pts) {
        SCOPED_TRACE("h = " + std::to_string(p[0]) + ", M = " + std::to_string(p[1]) +
                     ", throttle = " + std::to_string(p[2]));
        // Cross term h*M*dt is trilinear, so interpolation is exact everywhere inside.
        EXPECT_NEAR(e.thrust_at(p[0], p[1], p[2], 1.0), trilinear(p[0], p[1], p[2]), 1e-8);
    }
}

TEST(EngineTable, SingleBreakpointAxisIsConstant) {
    fd::EngineModel e;
    e.type = fd::EngineModel::Type::table;
    e.altitude = {0.0};
    e.mach = {0.0, 1.0};
    e.throttle = {0.0, 1.0};
    e.thrust = {0.0, 10000.0, 0.0, 8000.0};  // (M, throttle): (0,0) (0,1) (1,0) (1,1)
    ASSERT_NO_THROW(e.validate("one altitude"));
    EXPECT_NEAR(e.thrust_at(5000.0, 0.5, 1.0, 0.6), 9000.0, 1e-9);
    EXPECT_NEAR(e.thrust_at(-100.0, 0.0, 0.5, 1.0), 5000.0, 1e-9);
}

TEST(EngineTable, ValidationNamesTheProblem) {
    auto e = table_engine();
    e.thrust.pop_back();
    try {
        e.validate("ranger engine");
        FAIL() << "expected InputError";
    } catch (const manta::InputError& err) {
        const std::string msg = err.what();
        EXPECT_NE(msg.find("ranger engine"), std::string::npos) << msg;
        EXPECT_NE(msg.find("47"), std::string::npos) << msg;  // size found
        EXPECT_NE(msg.find("48"), std::string::npos) << msg;  // size expected
    }
    e = table_engine();
    e.mach = {0.0, 0.6, 0.3, 0.9};
    EXPECT_THROW(e.validate("ranger engine"), manta::InputError);
    e = table_engine();
    e.altitude.clear();
    EXPECT_THROW(e.validate("ranger engine"), manta::InputError);
}

TEST(EngineTable, AutomaticDerivativeFollowsTheCell) {
    const auto e = table_engine();
    using manta::core::Dual;
    const Dual h = manta::core::make_dual(4500.0, 3, 0);
    const Dual M = manta::core::make_dual(0.45, 3, 1);
    const Dual t = manta::core::make_dual(0.75, 3, 2);
    const Dual s = manta::core::make_constant(1.0, 3);
    const Dual T = e.thrust_at(h, M, t, s);
    EXPECT_NEAR(T.value(), trilinear(4500.0, 0.45, 0.75), 1e-8);
    EXPECT_NEAR(T.derivatives()[0], -0.05 + 0.01 * 0.45 * 0.75, 1e-10);
    EXPECT_NEAR(T.derivatives()[1], 3000.0 + 0.01 * 4500.0 * 0.75, 1e-8);
    EXPECT_NEAR(T.derivatives()[2], 20000.0 + 0.01 * 4500.0 * 0.45, 1e-8);
}
