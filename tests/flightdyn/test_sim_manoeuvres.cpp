// Manoeuvres with aerodynamics: a steady coordinated turn of the Ranger 2000 (kinematics),
// energy conservation when no force does work, and agreement of the Euler-angle and quaternion
// state forms through a loop (theta = 90 deg) and along a general 3-D manoeuvre.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "manta/aircraft/aircraft.hpp"
#include "manta/core/frames.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/simulate.hpp"
#include "manta/flightdyn/trim.hpp"
#include "test_sim_models.hpp"

namespace fd = manta::flightdyn;
using manta::core::deg;

namespace {

// Trajectory columns.
enum Col : int { T = 0, X, Y, Z, PHI, THETA, PSI, V, ALPHA, BETA, P, Q, R };

Eigen::Matrix3d dcm(const std::vector<double>& row) {
    return manta::core::dcm_earth_from_body(row[PHI], row[THETA], row[PSI]);
}

}  // namespace

// ------------------------------------------------------------------------- coordinated turn

TEST(Manoeuvre, SteadyCoordinatedTurnOfTheRanger) {
    const std::filesystem::path file =
        std::filesystem::path(MANTA_SOURCE_DIR) / "examples/ranger2000/aircraft.yaml";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " not found";
    const auto def = manta::aircraft::load_aircraft(file);
    fd::FlightModel model = def.flight_model();
    fd::finalize(model);  // alpha-dot terms of the Ranger's tables on

    fd::TrimTarget target;
    target.airspeed = 150.0;
    target.altitude = 3000.0;
    target.turn_rate = deg(10.0);
    const fd::TrimResult trim = fd::trim(model, target);
    ASSERT_LT(trim.residual_norm, 1e-8);

    fd::SimulationOptions opt;
    opt.duration = 30.0;
    opt.dt = 0.01;
    opt.output_interval = 0.1;
    const auto r = fd::simulate(model, trim.state, fd::InputHistory(trim.controls), opt);
    ASSERT_EQ(r.end_reason, fd::EndReason::completed);

    const double psi_dot = target.turn_rate, V0 = target.airspeed, h0 = target.altitude;
    const double radius = V0 / psi_dot;  // level turn: the whole velocity is horizontal
    // Centre of the circle: a radius to the right of the initial ground track.
    const auto& r0 = r.rows.front();
    const Eigen::Vector3d v_earth =
        dcm(r0) * Eigen::Vector3d(r0[V] * std::cos(r0[ALPHA]) * std::cos(r0[BETA]),
                                  r0[V] * std::sin(r0[BETA]),
                                  r0[V] * std::sin(r0[ALPHA]) * std::cos(r0[BETA]));
    ASSERT_NEAR(v_earth.z(), 0.0, 1e-9 * V0);  // level
    const Eigen::Vector2d track = v_earth.head<2>().normalized();
    const Eigen::Vector2d centre =
        Eigen::Vector2d(r0[X], r0[Y]) + radius * Eigen::Vector2d(-track.y(), track.x());

    double worst_psi = 0, worst_radius = 0, worst_h = 0, worst_V = 0, worst_phi = 0,
           worst_rates = 0;
    for (const auto& row : r.rows) {
        const double t = row[T];
        worst_psi = std::max(worst_psi, std::abs(row[PSI] - (r0[PSI] + psi_dot * t)));
        worst_radius = std::max(
            worst_radius, std::abs((Eigen::Vector2d(row[X], row[Y]) - centre).norm() - radius));
        worst_h = std::max(worst_h, std::abs(-row[Z] - h0));
        worst_V = std::max(worst_V, std::abs(row[V] - V0));
        worst_phi = std::max(worst_phi, std::abs(row[PHI] - trim.state[fd::euler::phi]));
        for (int k = 0; k < 3; ++k)
            worst_rates =
                std::max(worst_rates, std::abs(row[P + k] - trim.state[fd::euler::p + k]));
    }
    std::printf(
        "coordinated turn 10 deg/s at 150 m/s: bank %.3f deg, radius %.2f m, trim residual %.1e\n"
        "  worst over 30 s: heading %.2e rad, radius %.2e m, altitude %.2e m, V %.2e m/s, bank "
        "%.2e rad, "
        "rates %.2e rad/s\n",
        trim.state[fd::euler::phi] / deg(1.0), radius, trim.residual_norm, worst_psi, worst_radius,
        worst_h, worst_V, worst_phi, worst_rates);
    // Bank of a coordinated level turn: tan(phi) = V psi_dot / g up to the small alpha, beta
    // terms of Stevens & Lewis eq. 3.6-5; within 1 deg for alpha of a few degrees.
    EXPECT_NEAR(trim.state[fd::euler::phi], std::atan(V0 * psi_dot / model.environment.gravity),
                deg(1.0));
    // Tolerances. The trim residual (<= 1e-8 in SI derivatives) grows at worst as t^2/2 over
    // 30 s: 5e-6 m, 3e-7 m/s, 3e-7 rad. RK4 at 0.01 s has a local error ~ (psi_dot dt)^5 V dt
    // ~ 1e-15 m per step. The turn is a slightly unstable equilibrium (spiral mode), which
    // amplifies both over 30 s by a bounded factor; the bounds below leave 2-3 orders of margin
    // over that budget (measured with the Ranger: 3e-14 rad, 5e-10 m, 0 m, 0 m/s).
    EXPECT_LT(worst_psi, 1e-6);
    EXPECT_LT(worst_radius, 1e-3);
    EXPECT_LT(worst_h, 1e-3);
    EXPECT_LT(worst_V, 1e-5);
    EXPECT_LT(worst_phi, 1e-6);
    EXPECT_LT(worst_rates, 1e-7);
}

// ----------------------------------------------------------------------- energy conservation

TEST(Manoeuvre, EnergyConservedWhenNoForceDoesWork) {
    // Lift and side force only (CD = 0, no thrust): both are perpendicular to the velocity, so
    // 1/2 m V^2 + m g h is constant. No aerodynamic moments: rotation is torque-free, so the
    // rotational energy 1/2 w.I w is constant too. The aircraft rolls, pitches and yaws freely
    // for 60 s, the lift turning the flight path in all directions.
    manta::aero::LinearDerivatives d;
    d.CL_0 = 0.2;
    d.CL_alpha = 5.0;
    d.CL_q = 4.0;
    d.CL_de = 0.4;
    d.CY_beta = -0.6;
    d.CY_p = 0.1;
    d.CY_r = 0.3;
    d.CY_dr = 0.15;
    auto model = manta::test::ranger_like(d, manta::test::ranger_grids());
    model.engine.static_thrust_sl = 0.0;
    model.mass.inertia(0, 2) = model.mass.inertia(2, 0) = -800.0;  // a product of inertia too
    fd::finalize(model);

    fd::EulerState<double> s = fd::EulerState<double>::Zero();
    s[fd::euler::z] = -8000.0;
    s[fd::euler::V] = 180.0;
    s[fd::euler::alpha] = deg(3.0);
    s[fd::euler::beta] = deg(1.0);
    s[fd::euler::theta] = deg(3.0);
    s[fd::euler::p] = 0.25;
    s[fd::euler::q] = 0.06;
    s[fd::euler::r] = 0.04;
    const auto inputs =
        fd::InputHistory::parse("t,elevator_deg,rudder_deg\n0,0,0\n10,-5,3\n20,5,-3\n30,0,0\n",
                                "energy.csv", fd::Controls<double>{});
    for (auto integ : {fd::Integrator::rk4, fd::Integrator::dopri5}) {
        SCOPED_TRACE(std::string(fd::to_string(integ)));
        fd::SimulationOptions opt;
        opt.duration = 60.0;
        opt.dt = 0.01;
        opt.output_interval = 0.1;
        opt.integrator = integ;
        opt.rtol = 1e-11;
        opt.atol = 1e-9;
        const auto r = fd::simulate(model, s, inputs, opt);
        ASSERT_EQ(r.end_reason, fd::EndReason::completed);
        const double m = model.mass.mass, g = model.environment.gravity;
        auto energy = [&](const std::vector<double>& row) {
            return 0.5 * m * row[V] * row[V] - m * g * row[Z];
        };
        auto rot_energy = [&](const std::vector<double>& row) {
            const Eigen::Vector3d w(row[P], row[Q], row[R]);
            return 0.5 * w.dot(model.mass.inertia * w);
        };
        const double e0 = energy(r.rows.front()), er0 = rot_energy(r.rows.front());
        double worst = 0, worst_rot = 0, h_min = 1e9, h_max = -1e9, v_min = 1e9, v_max = 0;
        for (const auto& row : r.rows) {
            worst = std::max(worst, std::abs(energy(row) / e0 - 1.0));
            worst_rot = std::max(worst_rot, std::abs(rot_energy(row) / er0 - 1.0));
            h_min = std::min(h_min, -row[Z]);
            h_max = std::max(h_max, -row[Z]);
            v_min = std::min(v_min, row[V]);
            v_max = std::max(v_max, row[V]);
        }
        std::printf(
            "energy (%s): altitude %.0f..%.0f m, V %.1f..%.1f m/s; max relative drift: total %.2e, "
            "rotational %.2e\n",
            std::string(fd::to_string(integ)).c_str(), h_min, h_max, v_min, v_max, worst,
            worst_rot);
        // A real manoeuvre: kinetic and potential energy trade by more than 10 %.
        EXPECT_GT(v_max - v_min, 20.0);
        // Integrator tolerance: RK4 at 0.01 s has a local error ~ (|w| dt)^5 ~ 1e-13 relative, and
        // dopri5 is held to rtol 1e-11; over 6000 steps either keeps a first integral to better
        // than 1e-10 (measured: ~1e-13).
        EXPECT_LT(worst, 1e-10);
        EXPECT_LT(worst_rot, 1e-10);
    }
}

// ------------------------------------------------------------- Euler vs quaternion state forms

namespace {

struct FormComparison {
    double position = 0, V = 0, alpha = 0, beta = 0, attitude = 0, rates = 0, theta_max = -10;
};

FormComparison compare_forms(const fd::FlightModel& model, const fd::EulerState<double>& s,
                             const fd::InputHistory& inputs, double duration) {
    fd::SimulationOptions opt;
    opt.duration = duration;
    opt.integrator = fd::Integrator::dopri5;
    opt.rtol = 1e-11;
    opt.atol = 1e-10;
    opt.dt = 1e-3;
    opt.output_interval = 0.05;
    opt.form = fd::StateForm::euler;
    const auto re = fd::simulate(model, s, inputs, opt);
    opt.form = fd::StateForm::quaternion;
    const auto rq = fd::simulate(model, s, inputs, opt);
    EXPECT_EQ(re.end_reason, fd::EndReason::completed);
    EXPECT_EQ(rq.end_reason, fd::EndReason::completed);
    EXPECT_EQ(re.rows.size(), rq.rows.size());
    FormComparison c;
    for (std::size_t i = 0; i < std::min(re.rows.size(), rq.rows.size()); ++i) {
        const auto &a = re.rows[i], &b = rq.rows[i];
        c.position = std::max(
            c.position,
            (Eigen::Vector3d(a[X], a[Y], a[Z]) - Eigen::Vector3d(b[X], b[Y], b[Z])).norm());
        c.V = std::max(c.V, std::abs(a[V] - b[V]));
        c.alpha = std::max(c.alpha, std::abs(a[ALPHA] - b[ALPHA]));
        c.beta = std::max(c.beta, std::abs(a[BETA] - b[BETA]));
        c.attitude = std::max(c.attitude, (dcm(a) - dcm(b)).cwiseAbs().maxCoeff());
        for (int k = 0; k < 3; ++k) c.rates = std::max(c.rates, std::abs(a[P + k] - b[P + k]));
        c.theta_max = std::max(c.theta_max, a[THETA]);
    }
    std::printf(
        "  Euler vs quaternion over %.0f s: position %.2e m, V %.2e m/s, alpha %.2e, beta %.2e "
        "rad, "
        "DCM %.2e, rates %.2e rad/s; Euler-form theta up to %.1f deg\n",
        duration, c.position, c.V, c.alpha, c.beta, c.attitude, c.rates, c.theta_max / deg(1.0));
    return c;
}

}  // namespace

TEST(StateFormAgreement, LoopThroughVerticalWithWingsLevel) {
    // Pull-up from 200 m/s at full throttle: elevator ramps to -8 deg in 1 s and holds; the
    // aircraft goes over the top. With phi = beta = p = r = 0 the Euler form passes theta =
    // 90 deg (psi_dot = r / cos(theta) = 0), beyond which its theta exceeds 90 deg while the
    // quaternion form's extracted angles flip (phi = psi = 180 deg): compare the attitude as a DCM.
    const auto model = manta::test::ranger_like();
    fd::EulerState<double> s = fd::EulerState<double>::Zero();
    s[fd::euler::z] = -3000.0;
    s[fd::euler::V] = 200.0;
    s[fd::euler::alpha] = deg(1.0);
    s[fd::euler::theta] = deg(1.0);
    fd::Controls<double> u0;
    u0.throttle = 1.0;
    u0.elevator = deg(-1.0);
    const auto inputs = fd::InputHistory::parse("t,elevator_deg\n0,-1\n1,-8\n", "loop.csv", u0);
    const FormComparison c = compare_forms(model, s, inputs, 20.0);
    EXPECT_GT(c.theta_max, deg(150.0)) << "the manoeuvre should go over the top";
    // Both forms integrate the same equations with dopri5 at rtol 1e-11: they agree to the
    // integrators' global errors, which the short-period dynamics amplify to ~1e-8 relative over
    // 20 s (measured: 4e-6 m, 4e-7 m/s, 6e-9 rad/s; the bounds leave
    // a factor 10 or more for other compilers and libm versions).
    EXPECT_LT(c.position, 1e-4);
    EXPECT_LT(c.V, 1e-5);
    EXPECT_LT(c.alpha, 1e-7);
    EXPECT_LT(c.beta, 1e-12);
    EXPECT_LT(c.attitude, 1e-7);
    EXPECT_LT(c.rates, 1e-7);
}

TEST(StateFormAgreement, GeneralThreeDimensionalManoeuvre) {
    // Rolling pull-up with rudder: all twelve states move, theta stays below 60 deg.
    const auto model = manta::test::ranger_like();
    fd::EulerState<double> s = fd::EulerState<double>::Zero();
    s[fd::euler::z] = -3000.0;
    s[fd::euler::V] = 170.0;
    s[fd::euler::alpha] = deg(2.0);
    s[fd::euler::theta] = deg(2.0);
    s[fd::euler::psi] = deg(30.0);
    fd::Controls<double> u0;
    u0.throttle = 0.8;
    u0.elevator = deg(-1.5);
    const auto inputs = fd::InputHistory::parse(
        "t,elevator_deg,aileron_deg,rudder_deg\n0,-1.5,0,0\n1,-4,5,2\n3,-4,5,2\n4,-2,-6,-3\n7,-2,-"
        "6,-3\n8,-1.5,0,0\n",
        "roll.csv", u0);
    const FormComparison c = compare_forms(model, s, inputs, 15.0);
    EXPECT_LT(c.theta_max, deg(60.0));
    EXPECT_LT(c.position, 1e-4);
    EXPECT_LT(c.V, 1e-5);
    EXPECT_LT(c.alpha, 1e-7);
    EXPECT_LT(c.beta, 1e-7);
    EXPECT_LT(c.attitude, 1e-7);
    EXPECT_LT(c.rates, 1e-7);
}
