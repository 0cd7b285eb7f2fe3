// The replay motion (Ghoreyshi et al., "Simulation of Aircraft Manoeuvres Based On Computational
// Fluid Dynamics", AIAA 2010, sec. II.D): re-integrating the motion file gives the trajectory's
// positions and attitudes back. Trajectories with closed-form paths: a climbing coordinated
// helix (turned motion frame) and a vertical loop through theta = 90 and 180 deg (Euler angles
// kept continuous). Tolerance: the motion is sampled every 0.01 s from rows 0.02 s apart and the
// positions come from integrating the air velocity (Simpson's rule on the C1 cubic interpolant of
// the rows, error O(h^4)); measured 3e-12 m (helix) and 9e-11 m (loop) over 600 and 800 m of
// flight, direction cosines to 4e-16. Bounds: 1e-6 m and 1e-9, far below anything an
// aerodynamic source could notice; body rates from the interpolated angles to 1e-5 rad/s.

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>
#include <sstream>

#include "manta/core/frames.hpp"
#include "manta/replay/motion_builder.hpp"
#include "manta/replay/trajectory.hpp"

namespace {

using namespace manta;
using Eigen::Matrix3d;
using Eigen::Vector3d;
constexpr double pi = std::numbers::pi;

struct Row {
    double t;
    Vector3d x;
    std::array<double, 3> e;
    double V, alpha, beta;
    std::array<double, 3> w;
    double elevator;
};

std::string to_csv(const std::vector<Row>& rows) {
    std::ostringstream s;
    s.precision(17);
    s << "t,x,y,z,phi,theta,psi,V,alpha,beta,p,q,r,elevator,aileron,rudder,mach\n";
    for (const Row& r : rows)
        s << r.t << ',' << r.x.x() << ',' << r.x.y() << ',' << r.x.z() << ',' << r.e[0] << ','
          << r.e[1] << ',' << r.e[2] << ',' << r.V << ',' << r.alpha << ',' << r.beta << ','
          << r.w[0] << ',' << r.w[1] << ',' << r.w[2] << ',' << r.elevator << ",0,0,0.3\n";
    return s.str();
}

/// Principal Euler angles (|theta| <= 90 deg, phi, psi in (-pi, pi]) of an attitude.
std::array<double, 3> principal(const std::array<double, 3>& e) {
    return replay::continuous_euler(manta::core::dcm_body_from_earth(e), nullptr);
}

void check_reintegration(const std::vector<Row>& rows, double pos_tol, double att_tol) {
    const replay::Trajectory tr = replay::parse_trajectory(to_csv(rows), "analytic.csv");
    const replay::ReplayMotion rm = replay::build_motion(tr, 0.01);
    double worst_x = 0.0, worst_c = 0.0;
    for (const Row& r : rows) {
        const replay::EarthPose p = replay::earth_pose(rm, r.t);
        worst_x = std::max(worst_x, (p.position - r.x).norm());
        const Matrix3d a = manta::core::dcm_body_from_earth(p.euler),
                       b = manta::core::dcm_body_from_earth(r.e);
        worst_c = std::max(worst_c, (a - b).cwiseAbs().maxCoeff());
        // The air state the sources see is the trajectory's.
        const replay::AirState s = replay::motion_air_state(rm.motion, rm.v0, r.t);
        EXPECT_NEAR(s.alpha, r.alpha, att_tol) << "t " << r.t;
        EXPECT_NEAR(s.airspeed, r.V, 1e-6 * r.V) << "t " << r.t;
        // Body rates from the motion's Euler angles (a finer check of the angles' smoothness).
        const aero::MotionState m = rm.motion.at(r.t);
        for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(m.omega_body[k], r.w[k], 1e-5) << r.t;
    }
    EXPECT_LT(worst_x, pos_tol);
    EXPECT_LT(worst_c, att_tol);
    std::ostringstream msg;
    msg << std::scientific << "max position error " << worst_x << " m, max direction-cosine error "
        << worst_c;
    ::testing::Test::RecordProperty("reintegration", msg.str());
    std::cout << msg.str() << "\n";
}

TEST(MotionBuilder, ClimbingHelixIsReproduced) {
    // Coordinated climbing turn: bank 30 deg, theta = gamma = 5 deg, alpha = beta = 0, so the
    // body x axis is the velocity; heading rate 0.2 rad/s, 100 m/s, 6 s.
    const double V = 100.0, gamma = 5 * pi / 180, bank = 30 * pi / 180, w = 0.2;
    const double R = V * std::cos(gamma) / w;
    std::vector<Row> rows;
    for (int i = 0; i <= 300; ++i) {
        const double t = 0.02 * i;
        Row r{};
        r.t = t;
        r.x = Vector3d(1000.0 + R * std::sin(w * t), -50.0 + R * (1.0 - std::cos(w * t)),
                       -2000.0 - V * std::sin(gamma) * t);
        r.e = {bank, gamma, std::remainder(w * t, 2 * pi)};
        r.V = V;
        r.w = {-w * std::sin(gamma), w * std::sin(bank) * std::cos(gamma),
               w * std::cos(bank) * std::cos(gamma)};
        r.elevator = -0.01 * std::sin(t);
        rows.push_back(r);
    }
    const replay::Trajectory tr = replay::parse_trajectory(to_csv(rows), "helix.csv");
    const replay::ReplayMotion rm = replay::build_motion(tr, 0.01);
    EXPECT_NEAR(rm.gamma0, gamma, 1e-12);  // the motion frame is turned by the flight path
    EXPECT_NEAR(rm.chi0, 0.0, 1e-12);
    EXPECT_EQ(rm.motion.t.back(), 6.0);
    EXPECT_EQ(*rm.motion.metadata.v0, V);
    EXPECT_EQ(*rm.motion.metadata.mach, 0.3);
    // The elevator mode is the trajectory's deflection.
    EXPECT_NEAR(rm.motion.at(2.0).modes[0], -0.01 * std::sin(2.0), 1e-8);
    check_reintegration(rows, 1e-6, 1e-9);
}

TEST(MotionBuilder, LoopThroughTheVerticalIsReproducedWithContinuousAngles) {
    // Inside loop at constant pitch rate 0.5 rad/s, 100 m/s: theta goes past 90 and 180 deg; the
    // file holds the principal angles (phi and psi jump by 180 deg at the vertical).
    const double V = 100.0, q = 0.5, R = V / q;
    std::vector<Row> rows;
    for (int i = 0; i <= 400; ++i) {
        const double t = 0.02 * i;
        Row r{};
        r.t = t;
        r.x = Vector3d(R * std::sin(q * t), 0.0, -3000.0 - R * (1.0 - std::cos(q * t)));
        r.e = principal({0.0, q * t, 0.0});
        r.V = V;
        r.w = {0.0, q, 0.0};
        rows.push_back(r);
    }
    const replay::Trajectory tr = replay::parse_trajectory(to_csv(rows), "loop.csv");
    const replay::ReplayMotion rm = replay::build_motion(tr, 0.01);
    // Continuous theta in the motion frame: 0.5 t, through 90 and 180 deg.
    for (double t = 0.0; t <= 8.0; t += 0.37) EXPECT_NEAR(rm.motion.at(t).euler[1], q * t, 1e-7);
    check_reintegration(rows, 1e-6, 1e-9);
}

TEST(MotionBuilder, TimeStepFromTheTimeScales) {
    std::vector<Row> rows;
    for (int i = 0; i <= 100; ++i) {
        Row r{};
        r.t = 0.05 * i;
        r.x = Vector3d(100.0 * r.t, 0, -1000);
        r.V = 100;
        r.w = {0.0, 0.0, 0.0};
        r.elevator = 0.0;
        rows.push_back(r);
    }
    // Still: the upper bound.
    replay::Trajectory tr = replay::parse_trajectory(to_csv(rows), "still.csv");
    EXPECT_EQ(replay::choose_time_step(tr).dt, replay::TimeStepRule{}.max_dt);
    // Rolling at 4 rad/s: 0.1 / 4 = 0.025 s.
    for (auto& p : tr.rates[0]) p = 4.0;
    EXPECT_NEAR(replay::choose_time_step(tr).dt, 0.025, 1e-12);
    // The convective bound: one chord of 1 m at 100 m/s, 0.01 s.
    EXPECT_NEAR(replay::choose_time_step(tr, {}, 1.0).dt, 0.01, 1e-15);
    // A fast control step (0.1 rad in 0.05 s over a 0.1 rad range): 0.1 x 0.05 s, bounded below.
    tr.controls[0].back() = 0.1;
    replay::TimeStepRule rule;
    rule.min_dt = 0.01;
    EXPECT_EQ(replay::choose_time_step(tr, rule).dt, 0.01);
}

}  // namespace
