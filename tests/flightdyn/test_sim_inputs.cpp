// Simulation driver: control-input files, saturation, options, end conditions, output.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/simulate.hpp"
#include "test_sim_models.hpp"

namespace fd = manta::flightdyn;
using manta::core::deg;

namespace {

fd::Controls<double> trim_controls() {
    fd::Controls<double> u;
    u.elevator = -0.05;
    u.aileron = 0.0;
    u.rudder = 0.01;
    u.throttle = 0.4;
    return u;
}

/// The message of the InputError `f` throws (fails the test if none).
template <class F>
std::string input_error(F&& f) {
    try {
        f();
    } catch (const manta::InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected InputError";
    return {};
}

fd::EulerState<double> level_state(double V, double altitude) {
    fd::EulerState<double> s = fd::EulerState<double>::Zero();
    s[fd::euler::z] = -altitude;
    s[fd::euler::V] = V;
    return s;
}

}  // namespace

TEST(InputHistory, InterpolatesLinearlyAndHoldsOutside) {
    const std::string csv =
        "# doublet\n"
        "t, elevator_deg, throttle\n"
        "1.0, -2.0, 0.5\n"
        "2.0, -6.0, 0.7\n"
        "4.0,  2.0, 0.7\n";
    const auto h = fd::InputHistory::parse(csv, "doublet.csv", trim_controls());
    EXPECT_TRUE(h.has(fd::Channel::elevator));
    EXPECT_TRUE(h.has(fd::Channel::throttle));
    EXPECT_FALSE(h.has(fd::Channel::aileron));
    ASSERT_EQ(h.times().size(), 3u);
    // Before the first row: the first row's value; absent channels: the initial (trim) value.
    EXPECT_NEAR(h.at(0.0).elevator, deg(-2.0), 1e-15);
    EXPECT_EQ(h.at(0.0).rudder, 0.01);
    EXPECT_EQ(h.at(0.0).aileron, 0.0);
    // Between rows: linear.
    EXPECT_NEAR(h.at(1.5).elevator, deg(-4.0), 1e-15);
    EXPECT_NEAR(h.at(1.5).throttle, 0.6, 1e-15);
    EXPECT_NEAR(h.at(3.0).elevator, deg(-2.0), 1e-15);
    // At a row and after the last: the row's value.
    EXPECT_NEAR(h.at(2.0).elevator, deg(-6.0), 1e-15);
    EXPECT_NEAR(h.at(100.0).elevator, deg(2.0), 1e-15);
    EXPECT_EQ(h.at(100.0).rudder, 0.01);
}

TEST(InputHistory, RadianColumnsAndSingleRow) {
    const auto h =
        fd::InputHistory::parse("t,aileron,rudder\n0,0.1,-0.2\n", "one.csv", trim_controls());
    EXPECT_EQ(h.at(-1.0).aileron, 0.1);
    EXPECT_EQ(h.at(5.0).rudder, -0.2);
    EXPECT_EQ(h.at(5.0).elevator, -0.05);
}

TEST(InputHistory, ConstantHistoryHoldsInitialControls) {
    const fd::InputHistory h(trim_controls());
    EXPECT_TRUE(h.times().empty());
    EXPECT_EQ(h.at(12.0).throttle, 0.4);
    EXPECT_EQ(h.source(), "");
}

TEST(InputHistory, ErrorsNameFileLineAndColumn) {
    const auto u = trim_controls();
    // Non-monotonic time: line 4, column 1.
    std::string msg = input_error(
        [&] { (void)fd::InputHistory::parse("t,elevator\n0,0\n1,0\n0.5,0\n", "in.csv", u); });
    EXPECT_NE(msg.find("in.csv:4:1:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("strictly"), std::string::npos) << msg;
    // Duplicate time, after a comment line: t is the second column.
    msg = input_error(
        [&] { (void)fd::InputHistory::parse("# c\nelevator,t\n0,0\n0,1\n0,1\n", "in.csv", u); });
    EXPECT_NE(msg.find("in.csv:5:2:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("duplicates"), std::string::npos) << msg;
    // Unknown column with a suggestion; header on line 1, column 2.
    msg = input_error([&] { (void)fd::InputHistory::parse("t,elevtor\n0,0\n", "in.csv", u); });
    EXPECT_NE(msg.find("in.csv:1:2:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("did you mean 'elevator'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("valid columns"), std::string::npos) << msg;
    // Both forms of one channel.
    msg = input_error(
        [&] { (void)fd::InputHistory::parse("t,rudder,rudder_deg\n0,0,0\n", "in.csv", u); });
    EXPECT_NE(msg.find("in.csv:1:3:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("not both"), std::string::npos) << msg;
    // No time column.
    msg = input_error([&] { (void)fd::InputHistory::parse("elevator\n0\n", "in.csv", u); });
    EXPECT_NE(msg.find("missing column 't'"), std::string::npos) << msg;
    // No rows.
    msg = input_error([&] { (void)fd::InputHistory::parse("t,elevator\n", "in.csv", u); });
    EXPECT_NE(msg.find("no data rows"), std::string::npos) << msg;
    // A bad number is located by the CSV reader.
    msg = input_error(
        [&] { (void)fd::InputHistory::parse("t,elevator\n0,0\n1,abc\n", "in.csv", u); });
    EXPECT_NE(msg.find("in.csv:3"), std::string::npos) << msg;
    EXPECT_NE(msg.find("elevator"), std::string::npos) << msg;
}

TEST(InputHistory, ReadsAFileAndReportsAMissingOne) {
    const auto dir = std::filesystem::temp_directory_path() / "manta_test_sim_inputs";
    std::filesystem::create_directories(dir);
    manta::core::write_file_atomic(dir / "in.csv", "t,throttle\n0,0.2\n10,0.9\n");
    const auto h = fd::InputHistory::read(dir / "in.csv", trim_controls());
    EXPECT_NEAR(h.at(5.0).throttle, 0.55, 1e-15);
    EXPECT_EQ(h.source(), (dir / "in.csv").string());
    EXPECT_THROW((void)fd::InputHistory::read(dir / "absent.csv", trim_controls()), manta::IoError);
}

TEST(Saturation, ClipsAtTheLimits) {
    fd::ControlLimits lim;  // elevator [-25, 15] deg, throttle [0, 1]
    fd::Controls<double> u;
    u.elevator = deg(20.0);
    u.aileron = deg(-5.0);
    u.rudder = deg(-30.0);
    u.throttle = 1.2;
    const auto s = fd::saturate(u, lim);
    EXPECT_EQ(s.controls.elevator, lim.elevator[1]);
    EXPECT_EQ(s.controls.aileron, deg(-5.0));
    EXPECT_EQ(s.controls.rudder, lim.rudder[0]);
    EXPECT_EQ(s.controls.throttle, 1.0);
    EXPECT_TRUE(s.saturated[0]);
    EXPECT_FALSE(s.saturated[1]);
    EXPECT_TRUE(s.saturated[2]);
    EXPECT_TRUE(s.saturated[3]);
}

TEST(Saturation, CountedInInputRowsAndOutputSamples) {
    const auto model = manta::test::rigid_body(1000.0, 1000.0, 2000.0, 2500.0);
    // Elevator beyond +15 deg from t = 1 s to the end; rows at 1 and 2 s are out of limits.
    const auto h =
        fd::InputHistory::parse("t,elevator_deg\n0,0\n1,20\n2,30\n", "sat.csv", trim_controls());
    fd::SimulationOptions opt;
    opt.duration = 3.0;
    opt.dt = 0.01;
    opt.output_interval = 0.1;
    const auto r = fd::simulate(model, level_state(100.0, 3000.0), h, opt);
    EXPECT_EQ(r.saturation.input_rows[0], 2);
    EXPECT_NEAR(r.saturation.first_time[0], 1.0, 1e-15);
    EXPECT_NEAR(r.saturation.first_value[0], deg(20.0), 1e-15);
    // Output samples at t = 0.0 .. 3.0 step 0.1: clipped where the interpolated command exceeds
    // 15 deg, i.e. t > 0.75 s: 0.8 .. 3.0 = 23 samples.
    EXPECT_EQ(r.saturation.output_samples[0], 23);
    // The applied elevator in the trajectory never exceeds the limit.
    for (const auto& row : r.rows) EXPECT_LE(row[13], deg(15.0) + 1e-15);
    const std::string s = r.saturation.summary(model.limits);
    EXPECT_NE(s.find("elevator: 2 input rows"), std::string::npos) << s;
    EXPECT_EQ(r.saturation.total(), 25);
}

TEST(SimulationOptions, ValidateAndParseChoices) {
    fd::SimulationOptions o;
    EXPECT_NO_THROW(o.validate());
    o.dt = 0.0;
    EXPECT_NE(input_error([&] { o.validate(); }).find("dt"), std::string::npos);
    o = {};
    o.duration = -1.0;
    EXPECT_NE(input_error([&] { o.validate(); }).find("duration"), std::string::npos);
    o = {};
    o.integrator = fd::Integrator::dopri5;
    o.rtol = 0.0;
    EXPECT_NE(input_error([&] { o.validate(); }).find("rtol"), std::string::npos);

    EXPECT_EQ(fd::parse_integrator("dopri5"), fd::Integrator::dopri5);
    EXPECT_EQ(fd::parse_state_form("euler"), fd::StateForm::euler);
    std::string msg = input_error([] { (void)fd::parse_integrator("rk5"); });
    EXPECT_NE(msg.find("did you mean 'rk4'"), std::string::npos) << msg;
    msg = input_error([] { (void)fd::parse_state_form("quaternions"); });
    EXPECT_NE(msg.find("did you mean 'quaternion'"), std::string::npos) << msg;
}

TEST(Simulate, OutputRowsColumnsAndMetadata) {
    const auto model = manta::test::rigid_body(1000.0, 1000.0, 2000.0, 2500.0);
    fd::SimulationOptions opt;
    opt.duration = 2.0;
    opt.dt = 0.01;
    opt.output_interval = 0.05;
    opt.aircraft_name = "brick";
    const auto r =
        fd::simulate(model, level_state(100.0, 3000.0), fd::InputHistory(trim_controls()), opt);
    EXPECT_EQ(r.end_reason, fd::EndReason::completed);
    ASSERT_EQ(r.rows.size(), 41u);
    EXPECT_EQ(r.columns, fd::trajectory_columns());
    EXPECT_EQ(r.columns.size(), 26u);
    for (std::size_t i = 0; i < r.rows.size(); ++i) {
        ASSERT_EQ(r.rows[i].size(), r.columns.size());
        EXPECT_NEAR(r.rows[i][0], 0.05 * static_cast<double>(i), 1e-12);
    }
    EXPECT_EQ(r.steps, 200);
    EXPECT_EQ(r.rhs_evaluations, 800);
    EXPECT_NEAR(r.final_time, 2.0, 1e-12);
    bool has_integrator = false, has_version = false, has_aircraft = false;
    for (const auto& m : r.metadata) {
        has_integrator |= m.find("integrator: rk4") != std::string::npos;
        has_version |= m.find("version: manta") != std::string::npos;
        has_aircraft |= m.find("aircraft: brick") != std::string::npos;
    }
    EXPECT_TRUE(has_integrator && has_version && has_aircraft);

    const auto dir = std::filesystem::temp_directory_path() / "manta_test_sim_inputs";
    fd::write_trajectory(dir / "traj.csv", r);
    const auto t = manta::core::read_csv(dir / "traj.csv");
    EXPECT_EQ(t.columns, fd::trajectory_columns());
    ASSERT_EQ(t.rows.size(), r.rows.size());
    EXPECT_EQ(t.rows.back(), r.rows.back());  // exact round trip
    EXPECT_EQ(t.comments.size(), r.metadata.size());
}

TEST(Simulate, Dopri5OutputsOnTheFixedGrid) {
    const auto model = manta::test::rigid_body(1000.0, 1000.0, 2000.0, 2500.0);
    fd::SimulationOptions opt;
    opt.duration = 1.95;
    opt.dt = 0.01;
    opt.output_interval = 0.1;
    opt.integrator = fd::Integrator::dopri5;
    const auto r =
        fd::simulate(model, level_state(100.0, 3000.0), fd::InputHistory(trim_controls()), opt);
    ASSERT_EQ(r.rows.size(), 21u);  // 0, 0.1, ..., 1.9, and the end 1.95
    EXPECT_NEAR(r.rows[19][0], 1.9, 1e-12);
    EXPECT_NEAR(r.rows[20][0], 1.95, 1e-12);
    // Ballistic: z(t) = z0 + g t^2 / 2 with no forces but gravity (quaternion form).
    const double t = 1.95;
    EXPECT_NEAR(r.final_state[fd::euler::z], -3000.0 + 0.5 * model.environment.gravity * t * t,
                1e-7);
    EXPECT_NEAR(r.final_state[fd::euler::x], 100.0 * t, 1e-7);
}

TEST(Simulate, StopsAtTheGround) {
    const auto model = manta::test::rigid_body(1000.0, 1000.0, 2000.0, 2500.0);
    for (auto integ : {fd::Integrator::rk4, fd::Integrator::dopri5}) {
        SCOPED_TRACE(std::string(fd::to_string(integ)));
        fd::SimulationOptions opt;
        opt.duration = 60.0;
        opt.dt = 0.01;
        opt.output_interval = 0.1;
        opt.integrator = integ;
        // Free fall from 100 m: ground at t = sqrt(2 h / g).
        const auto r = fd::simulate(model, level_state(0.0, 100.0), fd::InputHistory(), opt);
        const double t_ground = std::sqrt(2.0 * 100.0 / model.environment.gravity);
        EXPECT_EQ(r.end_reason, fd::EndReason::ground);
        EXPECT_NEAR(r.final_time, t_ground, 1e-6);
        EXPECT_NEAR(r.final_state[fd::euler::z], 0.0, 1e-6);
        EXPECT_NEAR(r.rows.back()[0], r.final_time, 1e-15);
        EXPECT_NE(r.end_message.find("ground"), std::string::npos);
        // Rows are strictly increasing in time.
        for (std::size_t i = 1; i < r.rows.size(); ++i) EXPECT_GT(r.rows[i][0], r.rows[i - 1][0]);
    }
}

TEST(Simulate, StopsWhenLeavingTheAtmosphere) {
    auto model = manta::test::rigid_body(1000.0, 1000.0, 2000.0, 2500.0);
    // Climbing vertically at 800 m/s from 85 km: leaves the model (86 km) within 2 s.
    fd::EulerState<double> s = level_state(800.0, 85000.0);
    s[fd::euler::theta] = deg(89.0);
    fd::SimulationOptions opt;
    opt.duration = 10.0;
    const auto r = fd::simulate(model, s, fd::InputHistory(), opt);
    EXPECT_EQ(r.end_reason, fd::EndReason::left_atmosphere);
    EXPECT_LT(r.final_time, 2.0);
    EXPECT_LE(-r.final_state[fd::euler::z], 86000.0);
    EXPECT_NE(r.end_message.find("US Standard Atmosphere"), std::string::npos) << r.end_message;
}

TEST(Simulate, NonFiniteStateRaisesNumericalErrorAndSavesThePartialResult) {
    // An absurd engine (1e308 N) that the throttle file opens after 2 s: the velocity overflows
    // within a step or two and the state becomes Inf/NaN.
    auto model = manta::test::rigid_body(1000.0, 1000.0, 2000.0, 2500.0);
    model.engine.static_thrust_sl = 1e308;
    const auto h =
        fd::InputHistory::parse("t,throttle\n0,0\n2,0\n3,1\n", "boom.csv", trim_controls());
    fd::SimulationOptions opt;
    opt.duration = 5.0;
    opt.dt = 0.01;
    std::size_t saved_rows = 0;
    std::string saved_end;
    opt.on_abort = [&](const fd::SimulationResult& partial) {
        saved_rows = partial.rows.size();
        for (const auto& m : partial.metadata)
            if (m.rfind("end:", 0) == 0) saved_end = m;
    };
    try {
        (void)fd::simulate(model, level_state(100.0, 3000.0), h, opt);
        FAIL() << "expected NumericalError";
    } catch (const manta::NumericalError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("non-finite"), std::string::npos) << msg;
        EXPECT_NE(msg.find("at t = 2.0"), std::string::npos) << msg;
        EXPECT_NE(msg.find("q0 = "), std::string::npos) << msg;
        EXPECT_NE(msg.find("last finite state"), std::string::npos) << msg;
    }
    EXPECT_GE(saved_rows, 200u);
    EXPECT_NE(saved_end.find("aborted"), std::string::npos) << saved_end;
}

TEST(Simulate, RejectsBadInitialStates) {
    const auto model = manta::test::rigid_body(1000.0, 1000.0, 2000.0, 2500.0);
    fd::SimulationOptions opt;
    opt.form = fd::StateForm::euler;
    EXPECT_THROW((void)fd::simulate(model, level_state(0.0, 3000.0), fd::InputHistory(), opt),
                 manta::InputError);
    auto s = level_state(100.0, 3000.0);
    s[fd::euler::theta] = deg(90.0);
    EXPECT_THROW((void)fd::simulate(model, s, fd::InputHistory(), opt), manta::InputError);
    opt.form = fd::StateForm::quaternion;
    EXPECT_NO_THROW((void)fd::simulate(model, s, fd::InputHistory(), [] {
        fd::SimulationOptions o;
        o.duration = 0.1;
        return o;
    }()));
    EXPECT_THROW((void)fd::simulate(model, level_state(100.0, -10.0), fd::InputHistory(), opt),
                 manta::InputError);
    EXPECT_THROW((void)fd::simulate(model, level_state(100.0, 90000.0), fd::InputHistory(), opt),
                 manta::InputError);
}

TEST(Simulate, ReportsProgress) {
    const auto model = manta::test::rigid_body(1000.0, 1000.0, 2000.0, 2500.0);
    fd::SimulationOptions opt;
    opt.duration = 5.0;
    opt.progress_interval = 0.0;
    int calls = 0;
    double last = -1.0;
    opt.progress = [&](const fd::SimulationProgress& p) {
        ++calls;
        EXPECT_GE(p.t, last);
        last = p.t;
        EXPECT_GE(p.fraction(), 0.0);
        EXPECT_LE(p.fraction(), 1.0 + 1e-12);
    };
    (void)fd::simulate(model, level_state(100.0, 3000.0), fd::InputHistory(), opt);
    EXPECT_GT(calls, 10);
    EXPECT_NEAR(last, 5.0, 1e-12);
}
