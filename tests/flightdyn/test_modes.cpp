// Modes about a trim point, checked against a linear model derived by hand.
//
// The aircraft is built in code from linear stability derivatives (AeroDatabase::from_derivatives,
// exact under multilinear interpolation): constant drag (CD_k = 0), CG at the moment reference
// point, thrust through the CG, so that every entry of the longitudinal and lateral-directional
// state matrices has a short closed form. The hand derivation linearises the flat-earth force
// equations in wind axes,
//   m dV/dt        = T cos(alpha) - D - m g sin(gamma),
//   m V dalpha/dt  = -T sin(alpha) - L + m V q + m g cos(gamma),      gamma = theta - alpha,
//   Iyy dq/dt      = M,   dtheta/dt = q,
// (Stevens, Lewis & Johnson, *Aircraft Control and Simulation*, 3rd ed., Wiley 2015, ch. 2, the
// wind-axes force equations with beta = phi = 0), and the side-force, rolling and yawing equations
// with the inertia coupling Gamma = Ixx Izz - Ixz^2 (same book; Etkin & Reid, *Dynamics of
// Flight: Stability and Control*, 3rd ed., Wiley 1996, ch. 4). The alpha-dot term of Cm is
// eliminated by substituting dalpha/dt (the classical M~ = M + M_alphadot * Z/(m V) form of
// Etkin & Reid ch. 4). Mode classification follows Etkin & Reid ch. 6.

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <vector>

#include "manta/aero/database.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/atmosphere.hpp"
#include "manta/flightdyn/eom.hpp"
#include "manta/flightdyn/modes.hpp"
#include "manta/flightdyn/trim.hpp"

namespace fd = manta::flightdyn;
namespace aero = manta::aero;
using manta::core::deg;
using cd = std::complex<double>;

namespace {

std::vector<double> grid(double lo, double hi, double step) {
    std::vector<double> g;
    const int n = static_cast<int>(std::lround((hi - lo) / step));
    for (int i = 0; i <= n; ++i) g.push_back(lo + step * i);
    return g;
}

aero::LinearDerivatives derivatives() {
    aero::LinearDerivatives d;
    d.CL_0 = 0.20;
    d.CL_alpha = 5.0;
    d.CL_q = 6.0;
    d.CL_de = 0.40;
    d.CD_0 = 0.03;  // CD_k = 0: drag independent of alpha, so dCD/dalpha = 0 exactly
    d.CY_beta = -0.60;
    d.CY_p = -0.05;
    d.CY_r = 0.30;
    d.CY_dr = 0.15;
    d.Cl_beta = -0.10;
    d.Cl_p = -0.45;
    d.Cl_r = 0.12;
    d.Cl_da = 0.15;
    d.Cl_dr = 0.01;
    d.Cm_0 = 0.03;
    d.Cm_alpha = -0.80;
    d.Cm_q = -15.0;
    d.Cm_alphadot = -6.0;
    d.Cm_de = -1.20;
    d.Cn_beta = 0.12;
    d.Cn_p = -0.03;
    d.Cn_r = -0.18;
    d.Cn_da = -0.01;
    d.Cn_dr = -0.08;
    return d;
}

struct Params {
    double m = 5000.0, S = 20.0, b = 10.0, c = 2.0;
    double Ixx = 8000.0, Iyy = 20000.0, Izz = 26000.0, Ixz = 1000.0;
    double T_sl = 20000.0, n = 0.7, a1 = -0.3, a2 = 0.15;
};

fd::FlightModel model(const Params& p) {
    aero::DerivativeGrids g;
    g.alpha = grid(deg(-10.0), deg(20.0), deg(2.0));
    g.mach = {0.1, 0.9};
    g.beta = grid(deg(-10.0), deg(10.0), deg(5.0));
    g.elevator = grid(deg(-25.0), deg(25.0), deg(5.0));
    g.aileron = grid(deg(-25.0), deg(25.0), deg(5.0));
    g.rudder = grid(deg(-25.0), deg(25.0), deg(5.0));
    aero::DatabaseInfo info;
    info.name = "hand-check derivative model";
    info.source = "linear-derivatives";
    fd::FlightModel m;
    m.name = "modes test";
    m.reference = {p.S, p.b, p.c};
    m.moment_reference_geom = Eigen::Vector3d(5.0, 0.0, 0.0);
    m.mass.name = "test";
    m.mass.mass = p.m;
    m.mass.cg_geom = m.moment_reference_geom;
    m.mass.inertia << p.Ixx, 0.0, -p.Ixz, 0.0, p.Iyy, 0.0, -p.Ixz, 0.0, p.Izz;
    m.engine.type = fd::EngineModel::Type::lapse;
    m.engine.static_thrust_sl = p.T_sl;
    m.engine.density_exponent = p.n;
    m.engine.mach_a1 = p.a1;
    m.engine.mach_a2 = p.a2;
    m.aero = std::make_shared<const aero::AeroDatabase>(
        aero::AeroDatabase::from_derivatives(derivatives(), g, info));
    m.limits.throttle = {0.0, 1.0};
    fd::finalize(m);
    return m;
}

struct Hand {
    Eigen::Matrix4d lon, lat;
};

/// The state matrices by the closed forms in the file comment, at the trim `r`.
Hand hand_matrices(const fd::FlightModel& model, const Params& p, const fd::TrimResult& r) {
    const aero::LinearDerivatives d = derivatives();
    const double g = model.environment.gravity;
    const double V = r.state[fd::euler::V];
    const double h = -r.state[fd::euler::z];
    const double alpha = r.state[fd::euler::alpha];
    const double theta = r.state[fd::euler::theta];
    const double gamma = theta - alpha;
    const auto atm = fd::us1976(h);
    const double rho = atm.density, a = atm.speed_of_sound, M = V / a;
    const double qbar = 0.5 * rho * V * V;
    const double S = p.S, b = p.b, c = p.c, m = p.m;
    // Thrust T = dt T_sl sigma^n (1 + a1 M + a2 M^2) and its speed derivative through M = V / a.
    const double sigma = rho / 1.225;
    const double dt = r.controls.throttle;
    const double T = dt * p.T_sl * std::pow(sigma, p.n) * (1.0 + p.a1 * M + p.a2 * M * M);
    const double T_V = dt * p.T_sl * std::pow(sigma, p.n) * (p.a1 + 2.0 * p.a2 * M) / a;
    const double CL = d.CL_0 + d.CL_alpha * alpha + d.CL_de * r.controls.elevator;
    const double CD = d.CD_0;
    const double sa = std::sin(alpha), ca = std::cos(alpha);

    Hand H;
    Eigen::Matrix4d& A = H.lon;  // (V, alpha, q, theta)
    A.setZero();
    A(0, 0) = (T_V * ca - rho * V * S * CD) / m;
    A(0, 1) = -T * sa / m + g * std::cos(gamma);
    A(0, 2) = 0.0;
    A(0, 3) = -g * std::cos(gamma);
    // dalpha/dt: the terms from differentiating 1/V cancel at trim (the bracket is -g
    // cos(gamma)/V).
    A(1, 0) = (-T_V * sa - rho * V * S * CL) / (m * V);
    A(1, 1) = (-T * ca - qbar * S * d.CL_alpha) / (m * V) + g * std::sin(gamma) / V;
    A(1, 2) = 1.0 - qbar * S * d.CL_q * c / (2.0 * V) / (m * V);
    A(1, 3) = -g * std::sin(gamma) / V;
    // dq/dt = (M_static + M_alphadot dalpha/dt) / Iyy with Cm = 0 at trim (CG at the reference
    // point).
    const double Mad = qbar * S * c * d.Cm_alphadot * c / (2.0 * V) / p.Iyy;
    A(2, 0) = Mad * A(1, 0);
    A(2, 1) = qbar * S * c * d.Cm_alpha / p.Iyy + Mad * A(1, 1);
    A(2, 2) = qbar * S * c * d.Cm_q * c / (2.0 * V) / p.Iyy + Mad * A(1, 2);
    A(2, 3) = Mad * A(1, 3);
    A(3, 2) = 1.0;

    Eigen::Matrix4d& B = H.lat;  // (beta, p, r, phi)
    B.setZero();
    const double b2V = b / (2.0 * V);
    // dbeta/dt = dv/dt / V at beta = 0 with dv/dt = Y/m + g sin(phi) cos(theta) - r u + p w and
    // the body side force Y = qbar S (CY cos(beta) - CD sin(beta)).
    B(0, 0) = qbar * S * (d.CY_beta - CD) / (m * V);
    B(0, 1) = qbar * S * d.CY_p * b2V / (m * V) + sa;
    B(0, 2) = qbar * S * d.CY_r * b2V / (m * V) - ca;
    B(0, 3) = g * std::cos(theta) / V;
    const double Gam = p.Ixx * p.Izz - p.Ixz * p.Ixz;
    const double Lb = qbar * S * b * d.Cl_beta, Lp = qbar * S * b * d.Cl_p * b2V,
                 Lr = qbar * S * b * d.Cl_r * b2V;
    const double Nb = qbar * S * b * d.Cn_beta, Np = qbar * S * b * d.Cn_p * b2V,
                 Nr = qbar * S * b * d.Cn_r * b2V;
    B(1, 0) = (p.Izz * Lb + p.Ixz * Nb) / Gam;
    B(1, 1) = (p.Izz * Lp + p.Ixz * Np) / Gam;
    B(1, 2) = (p.Izz * Lr + p.Ixz * Nr) / Gam;
    B(2, 0) = (p.Ixz * Lb + p.Ixx * Nb) / Gam;
    B(2, 1) = (p.Ixz * Lp + p.Ixx * Np) / Gam;
    B(2, 2) = (p.Ixz * Lr + p.Ixx * Nr) / Gam;
    // dphi/dt = p + tan(theta) (q sin(phi) + r cos(phi)).
    B(3, 1) = 1.0;
    B(3, 2) = std::tan(theta);
    return H;
}

std::vector<cd> sorted(const Eigen::Vector4cd& v) {
    std::vector<cd> s(v.data(), v.data() + 4);
    std::sort(s.begin(), s.end(), [](const cd& x, const cd& y) {
        return x.real() != y.real() ? x.real() < y.real() : x.imag() < y.imag();
    });
    return s;
}

void expect_matrix_near(const Eigen::Matrix4d& got, const Eigen::Matrix4d& want, const char* what) {
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            EXPECT_NEAR(got(i, j), want(i, j), 1e-9 * std::max(1.0, std::abs(want(i, j))))
                << what << "(" << i << ", " << j << ")";
}

class ModesHand : public ::testing::TestWithParam<double> {};

}  // namespace

TEST_P(ModesHand, StateMatricesAndEigenvaluesMatchTheHandDerivation) {
    const Params p;
    const fd::FlightModel m = model(p);
    fd::TrimTarget t;
    t.airspeed = 150.0;
    t.altitude = 3000.0;
    t.climb_angle = GetParam();
    const fd::TrimResult r = fd::trim(m, t);
    ASSERT_LT(r.residual_norm, 1e-10);
    const fd::LinearModel lin = fd::linearise(m, r.state, r.controls);
    const fd::ModesResult modes = fd::analyse_modes(lin);
    const Hand H = hand_matrices(m, p, r);
    expect_matrix_near(modes.A_longitudinal, H.lon, "A_lon");
    expect_matrix_near(modes.A_lateral, H.lat, "A_lat");

    // Eigenvalues of the hand matrices (Eigen) against those of the linearised model.
    const auto want_lon = sorted(Eigen::EigenSolver<Eigen::Matrix4d>(H.lon).eigenvalues());
    const auto want_lat = sorted(Eigen::EigenSolver<Eigen::Matrix4d>(H.lat).eigenvalues());
    const auto got_lon = sorted(modes.eigenvalues_longitudinal);
    const auto got_lat = sorted(modes.eigenvalues_lateral);
    for (int i = 0; i < 4; ++i) {
        EXPECT_NEAR(std::abs(got_lon[i] - want_lon[i]), 0.0,
                    1e-8 * std::max(1.0, std::abs(want_lon[i])));
        EXPECT_NEAR(std::abs(got_lat[i] - want_lat[i]), 0.0,
                    1e-8 * std::max(1.0, std::abs(want_lat[i])));
    }

    // Classification: two stable oscillations longitudinally, Dutch roll + roll + spiral.
    ASSERT_EQ(modes.longitudinal.size(), 2u);
    const auto& sp = modes.longitudinal[0];
    const auto& ph = modes.longitudinal[1];
    EXPECT_EQ(sp.name, "short period");
    EXPECT_EQ(ph.name, "phugoid");
    EXPECT_GT(sp.natural_frequency, 5.0 * ph.natural_frequency);
    EXPECT_TRUE(sp.is_stable());
    EXPECT_GT(sp.damping_ratio, 0.2);
    // Lanchester's phugoid, omega_n = sqrt(2) g / V (Etkin & Reid ch. 6), holds to ~20 % here.
    EXPECT_NEAR(ph.natural_frequency, std::sqrt(2.0) * m.environment.gravity / 150.0,
                0.2 * std::sqrt(2.0) * m.environment.gravity / 150.0);
    ASSERT_EQ(modes.lateral.size(), 3u);
    EXPECT_EQ(modes.lateral[0].name, "Dutch roll");
    EXPECT_EQ(modes.lateral[1].name, "roll");
    EXPECT_EQ(modes.lateral[2].name, "spiral");
    EXPECT_TRUE(modes.lateral[0].oscillatory);
    EXPECT_GT(std::abs(modes.lateral[1].eigenvalue.real()),
              10.0 * std::abs(modes.lateral[2].eigenvalue.real()));
    EXPECT_TRUE(modes.lateral[1].is_stable());

    // The subsystems' eigenvalues are close to eigenvalues of the full 12-state matrix: the
    // short period within 0.1 %; the phugoid within 10 %, as the density gradient couples it to
    // altitude (the full matrix has the altitude state; about 6 % here).
    for (const cd& l : got_lon) {
        double best = 1e300;
        for (int i = 0; i < 12; ++i) best = std::min(best, std::abs(modes.eigenvalues_full[i] - l));
        EXPECT_LT(best, (std::abs(l) > 1.0 ? 1e-3 : 0.1) * std::abs(l)) << l;
    }
}

INSTANTIATE_TEST_SUITE_P(LevelAndClimb, ModesHand, ::testing::Values(0.0, deg(3.0)));

TEST(Modes, MakeModeProperties) {
    const fd::Mode m = fd::make_mode(cd(-1.0, -2.0));
    EXPECT_TRUE(m.oscillatory);
    EXPECT_EQ(m.eigenvalue, cd(-1.0, 2.0));  // reported with Im > 0
    EXPECT_DOUBLE_EQ(m.natural_frequency, std::sqrt(5.0));
    EXPECT_DOUBLE_EQ(m.damping_ratio, 1.0 / std::sqrt(5.0));
    EXPECT_DOUBLE_EQ(m.period, std::numbers::pi);
    EXPECT_DOUBLE_EQ(m.time_to_half, std::numbers::ln2);
    EXPECT_TRUE(std::isinf(m.time_to_double));
    const fd::Mode u = fd::make_mode(cd(0.05, 0.0));
    EXPECT_FALSE(u.oscillatory);
    EXPECT_FALSE(u.is_stable());
    EXPECT_DOUBLE_EQ(u.damping_ratio, -1.0);
    EXPECT_DOUBLE_EQ(u.time_to_double, std::numbers::ln2 / 0.05);
    EXPECT_TRUE(std::isinf(u.time_to_half));
    EXPECT_TRUE(std::isinf(u.period));
}

TEST(Modes, ClassifiesSplitRoots) {
    // Short period split into two real roots (e.g. an aft CG), phugoid oscillatory.
    Eigen::Vector4cd lon;
    lon << cd(-4.0, 0.0), cd(-0.8, 0.0), cd(-0.01, 0.08), cd(-0.01, -0.08);
    auto modes = fd::classify_longitudinal(lon);
    ASSERT_EQ(modes.size(), 3u);
    EXPECT_EQ(modes[0].name, "short period (real)");
    EXPECT_EQ(modes[1].name, "short period (real)");
    EXPECT_EQ(modes[2].name, "phugoid");
    EXPECT_DOUBLE_EQ(modes[0].eigenvalue.real(), -4.0);
    // Phugoid split, short period oscillatory.
    lon << cd(-2.0, 3.0), cd(-2.0, -3.0), cd(-0.05, 0.0), cd(0.02, 0.0);
    modes = fd::classify_longitudinal(lon);
    ASSERT_EQ(modes.size(), 3u);
    EXPECT_EQ(modes[0].name, "short period");
    EXPECT_EQ(modes[1].name, "phugoid (real)");
    EXPECT_EQ(modes[2].name, "phugoid (real)");
    // All real.
    lon << cd(-5.0, 0.0), cd(-0.03, 0.0), cd(-2.0, 0.0), cd(0.01, 0.0);
    modes = fd::classify_longitudinal(lon);
    ASSERT_EQ(modes.size(), 4u);
    EXPECT_EQ(modes[0].name, "short period (real)");
    EXPECT_DOUBLE_EQ(modes[0].eigenvalue.real(), -5.0);
    EXPECT_EQ(modes[3].name, "phugoid (real)");
    EXPECT_DOUBLE_EQ(modes[3].eigenvalue.real(), 0.01);

    Eigen::Vector4cd lat;
    lat << cd(-0.01, 0.0), cd(-0.2, 2.0), cd(-3.0, 0.0), cd(-0.2, -2.0);
    modes = fd::classify_lateral(lat);
    ASSERT_EQ(modes.size(), 3u);
    EXPECT_EQ(modes[0].name, "Dutch roll");
    EXPECT_EQ(modes[0].eigenvalue, cd(-0.2, 2.0));
    EXPECT_EQ(modes[1].name, "roll");
    EXPECT_DOUBLE_EQ(modes[1].eigenvalue.real(), -3.0);
    EXPECT_EQ(modes[2].name, "spiral");
    EXPECT_DOUBLE_EQ(modes[2].eigenvalue.real(), -0.01);
    // Dutch roll split into real roots.
    lat << cd(-4.0, 0.0), cd(-1.5, 0.0), cd(-0.7, 0.0), cd(0.02, 0.0);
    modes = fd::classify_lateral(lat);
    ASSERT_EQ(modes.size(), 4u);
    EXPECT_EQ(modes[0].name, "Dutch roll (real)");
    EXPECT_EQ(modes[2].name, "roll");
    EXPECT_DOUBLE_EQ(modes[2].eigenvalue.real(), -4.0);
    EXPECT_EQ(modes[3].name, "spiral");
    // Roll and spiral coupled into a second oscillation.
    lat << cd(-0.2, 2.0), cd(-0.2, -2.0), cd(-0.5, 0.3), cd(-0.5, -0.3);
    modes = fd::classify_lateral(lat);
    ASSERT_EQ(modes.size(), 2u);
    EXPECT_EQ(modes[0].name, "Dutch roll");
    EXPECT_EQ(modes[1].name, "roll-spiral (coupled)");
}

TEST(Modes, SubsystemPicksTheRightStates) {
    Eigen::Matrix<double, 12, 12> A;
    for (int i = 0; i < 12; ++i)
        for (int j = 0; j < 12; ++j) A(i, j) = 100.0 * i + j;
    auto entry = [](int i, int j) {
        return 100.0 * static_cast<double>(i) + static_cast<double>(j);
    };
    const Eigen::Matrix4d lon = fd::subsystem(A, fd::longitudinal_states);
    EXPECT_EQ(lon(0, 0), entry(fd::euler::V, fd::euler::V));
    EXPECT_EQ(lon(1, 2), entry(fd::euler::alpha, fd::euler::q));
    EXPECT_EQ(lon(3, 0), entry(fd::euler::theta, fd::euler::V));
    const Eigen::Matrix4d lat = fd::subsystem(A, fd::lateral_states);
    EXPECT_EQ(lat(0, 3), entry(fd::euler::beta, fd::euler::phi));
    EXPECT_EQ(lat(2, 1), entry(fd::euler::r, fd::euler::p));
}
