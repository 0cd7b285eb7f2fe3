// US Standard Atmosphere 1976 against the published tables.
//
// Reference: U.S. Standard Atmosphere, 1976, NOAA-S/T 76-1562 (NOAA, NASA, USAF; U.S. Government
// Printing Office, Washington DC, October 1976).
//  - Part 4, Table I "Geometric altitude, metric units" (p. 53 ff.): T [K] to 3 decimals, p [Pa],
//    rho [kg/m^3] and mu [N s/m^2] to 5 significant figures, a [m/s] to 2 decimals.
//  - Part 1, sec. 1.3: the layer bases H_b, temperatures T_M,b and lapse rates L_M,b (Table 4) and
//    the base pressures P_b that follow from eqs. (33a, 33b), printed as 101325, 22632.06,
//    5474.889, 868.0187, 110.9063, 66.93887, 3.956420 Pa.
// A value matches when it lies within one unit of the last printed digit: the tables are rounded
// to their printed precision (half a unit), and a few printed entries differ by one unit from a
// double-precision evaluation of the defining equations (e.g. 11 km pressure 22699.96 Pa).

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "manta/core/autodiff.hpp"
#include "manta/core/error.hpp"
#include "manta/flightdyn/atmosphere.hpp"

namespace fd = manta::flightdyn;

namespace {

/// One row of Table I (geometric altitude). mu <= 0: not compared.
struct TableRow {
    double z;    // [m]
    double T;    // [K], 3 decimals
    double p;    // [Pa], 5 significant figures
    double rho;  // [kg/m^3], 5 significant figures
    double a;    // [m/s], 2 decimals
    double mu;   // [N s/m^2], 5 significant figures
};

// clang-format off
constexpr TableRow table_one[] = {
    {    0.0, 288.150, 1.01325e5, 1.2250e0,  340.29, 1.7894e-5},
    { 1000.0, 281.651, 8.9876e4,  1.1117e0,  336.43, 1.7579e-5},
    { 2000.0, 275.154, 7.9501e4,  1.0066e0,  332.53, 1.7260e-5},
    { 5000.0, 255.676, 5.4048e4,  7.3643e-1, 320.55, 0.0},
    { 8000.0, 236.215, 3.5651e4,  5.2579e-1, 308.11, 0.0},
    {11000.0, 216.774, 2.2699e4,  3.6480e-1, 295.15, 1.4223e-5},
    {15000.0, 216.650, 1.2111e4,  1.9476e-1, 295.07, 1.4216e-5},
    {20000.0, 216.650, 5.5293e3,  8.8910e-2, 295.07, 1.4216e-5},
    {25000.0, 221.552, 2.5492e3,  4.0084e-2, 298.39, 1.4484e-5},
    {32000.0, 228.490, 8.8906e2,  1.3555e-2, 303.02, 0.0},
};
// clang-format on

/// One unit in the 5th significant figure of v.
double unit_5sf(double v) {
    return std::pow(10.0, std::floor(std::log10(std::abs(v))) - 4.0);
}

}  // namespace

TEST(Atmosphere, MatchesTableOneAtPrintedPrecision) {
    for (const auto& row : table_one) {
        SCOPED_TRACE("geometric altitude " + std::to_string(row.z) + " m");
        const auto s = fd::us1976(row.z);
        EXPECT_NEAR(s.temperature, row.T, 1e-3);
        EXPECT_NEAR(s.pressure, row.p, row.z == 0.0 ? 1e-9 : unit_5sf(row.p));
        EXPECT_NEAR(s.density, row.rho, unit_5sf(row.rho));
        EXPECT_NEAR(s.speed_of_sound, row.a, 1e-2);
        if (row.mu > 0) {
            EXPECT_NEAR(s.dynamic_viscosity, row.mu, unit_5sf(row.mu));
        }
    }
}

TEST(Atmosphere, LayerBaseValuesAtGeopotentialAltitudes) {
    struct Base {
        double h, T, p;
    };
    // Part 1 sec. 1.3 (Table 4 and eqs. 33a/b), pressures as printed (7 significant figures).
    const Base bases[] = {{0.0, 288.15, 101325.0},     {11000.0, 216.65, 22632.06},
                          {20000.0, 216.65, 5474.889}, {32000.0, 228.65, 868.0187},
                          {47000.0, 270.65, 110.9063}, {51000.0, 270.65, 66.93887},
                          {71000.0, 214.65, 3.956420}, {84852.0, 186.946, 0.0}};
    for (const auto& b : bases) {
        SCOPED_TRACE("geopotential altitude " + std::to_string(b.h) + " m'");
        const auto s = fd::us1976_geopotential(b.h);
        EXPECT_NEAR(s.temperature, b.T, 1e-3);
        if (b.p > 0) {
            EXPECT_NEAR(s.pressure, b.p, b.p * 1e-6);
        }
        // Equation of state and speed of sound as defined by the standard (eqs. 42, 50).
        EXPECT_NEAR(s.density, s.pressure / (fd::us1976_constants::gas_constant * s.temperature),
                    1e-15);
        EXPECT_NEAR(s.speed_of_sound, std::sqrt(1.4 * 8314.32 / 28.9644 * s.temperature), 1e-9);
    }
}

TEST(Atmosphere, ContinuousAtLayerBoundaries) {
    for (std::size_t i = 1; i < fd::us1976_constants::layers.size(); ++i) {
        const double h = fd::us1976_constants::layers[i].h_base;
        SCOPED_TRACE("boundary at " + std::to_string(h) + " m'");
        const double eps = 1e-6;  // m'
        const auto below = fd::us1976_geopotential(h - eps);
        const auto above = fd::us1976_geopotential(h + eps);
        EXPECT_NEAR(below.temperature, above.temperature, 1e-7);
        EXPECT_NEAR(below.pressure / above.pressure, 1.0, 1e-9);
        EXPECT_NEAR(below.density / above.density, 1.0, 1e-9);
        // Each layer's own formula evaluated at its top equals the next layer's base pressure.
        const auto& lo = fd::us1976_constants::layers[i - 1];
        const auto& hi = fd::us1976_constants::layers[i];
        EXPECT_NEAR(lo.t_base + lo.lapse * (hi.h_base - lo.h_base), hi.t_base, 1e-9);
    }
}

TEST(Atmosphere, GeometricGeopotentialRoundTrip) {
    for (double z : {-5000.0, 0.0, 3000.0, 11000.0, 47000.0, 86000.0}) {
        EXPECT_NEAR(fd::geometric_from_geopotential(fd::geopotential_from_geometric(z)), z, 1e-8);
    }
    // 86 km geometric is the top of the model, 84.852 km' (Part 1, sec. 1.2).
    EXPECT_NEAR(fd::geopotential_from_geometric(86000.0), 84852.0, 0.1);
}

TEST(Atmosphere, RejectsAltitudesOutsideTheModel) {
    EXPECT_THROW((void)fd::us1976_geopotential(84852.5), manta::InputError);
    EXPECT_THROW((void)fd::us1976_geopotential(-5000.5), manta::InputError);
    EXPECT_THROW((void)fd::us1976(90000.0), manta::InputError);
    EXPECT_THROW((void)fd::us1976(std::nan("")), manta::InputError);
    EXPECT_NO_THROW((void)fd::us1976_geopotential(84852.0));
    EXPECT_NO_THROW((void)fd::us1976_geopotential(-5000.0));
    try {
        (void)fd::us1976_geopotential(1e5);
        FAIL() << "expected InputError";
    } catch (const manta::InputError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("outside"), std::string::npos) << msg;
        EXPECT_NE(msg.find("84852"), std::string::npos) << msg;
    }
}

TEST(Atmosphere, AutomaticDerivativeMatchesFiniteDifference) {
    // d(rho)/dh and d(a)/dh in three layers (troposphere, isothermal, inversion).
    for (double z : {3000.0, 15000.0, 40000.0}) {
        const manta::core::Dual zd = manta::core::make_dual(z, 1, 0);
        const auto s = fd::us1976(zd);
        const double h = 0.5;
        const double drho = (fd::us1976(z + h).density - fd::us1976(z - h).density) / (2 * h);
        const double dT = (fd::us1976(z + h).temperature - fd::us1976(z - h).temperature) / (2 * h);
        EXPECT_NEAR(s.density.derivatives()[0], drho, 1e-6 * std::abs(drho) + 1e-14);
        EXPECT_NEAR(s.temperature.derivatives()[0], dT, 1e-9);
    }
}
