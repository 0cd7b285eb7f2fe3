// Ensembles (simulate_ensemble): each case's result equals simulate's for that case alone (the
// Ranger 2000 of examples/, several speeds, altitudes and input files, both state forms), cases
// that end early (ground, atmosphere, NaN) drop out while the others go on, per-case out-of-table
// counts, the dopri5 path, progress, and the RK4 arithmetic against Boost.Odeint's stepper.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "manta/aircraft/aircraft.hpp"
#include "manta/core/error.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/simulate.hpp"
#include "manta/flightdyn/trim.hpp"
#include "test_sim_models.hpp"

namespace fd = manta::flightdyn;
using manta::core::deg;

namespace {

/// The Ranger 2000 of examples/ranger2000/aircraft.yaml, finalized.
const fd::FlightModel& ranger() {
    static const fd::FlightModel model = [] {
        const std::filesystem::path file =
            std::filesystem::path(MANTA_SOURCE_DIR) / "examples/ranger2000/aircraft.yaml";
        fd::FlightModel m = manta::aircraft::load_aircraft(file).flight_model();
        fd::finalize(m);
        return m;
    }();
    return model;
}

/// A Ranger case trimmed in level flight at V [m/s], altitude [m], with inputs from CSV text
/// (columns absent from it hold the trim controls).
fd::EnsembleCase ranger_case(const std::string& name, double V, double h, const std::string& csv) {
    fd::TrimTarget target;
    target.airspeed = V;
    target.altitude = h;
    const fd::TrimResult trim = fd::trim(ranger(), target);
    return {name, trim.state,
            csv.empty() ? fd::InputHistory(trim.controls)
                        : fd::InputHistory::parse(csv, name + ".csv", trim.controls)};
}

/// Elevator doublet (+-2 deg about -1.5 deg) then a rudder kick.
const char* doublet_csv =
    "t,elevator_deg,rudder_deg\n0,-1.5,0\n1,-1.5,0\n1.1,-3.5,0\n2,-3.5,0\n2.1,0.5,0\n3,0.5,0\n"
    "3.1,-1.5,0\n6,-1.5,0\n6.1,-1.5,4\n7,-1.5,4\n7.1,-1.5,0\n";
/// Aileron step of 6 deg at 1 s, back at 4 s.
const char* roll_csv = "t,aileron_deg\n0,0\n1,0\n1.2,6\n4,6\n4.2,0\n";
/// A hard pull (commanded beyond the -25 deg limit) that takes alpha past the tables' 20 deg.
const char* pull_csv = "t,elevator_deg\n0,-1\n0.5,-1\n1,-30\n3,-30\n3.5,-2\n";
/// A push: nose down into the ground from low altitude.
const char* push_csv = "t,elevator_deg\n0,0\n0.5,6\n";

/// |a - b| / max(1, |b|).
double rel(double a, double b) {
    return std::abs(a - b) / std::max(1.0, std::abs(b));
}

/// `a` (ensemble) equals `b` (simulate) to `tol` relative in every number, exactly in every
/// count and text.
void expect_same(const fd::SimulationResult& a, const fd::SimulationResult& b, double tol) {
    EXPECT_EQ(a.end_reason, b.end_reason);
    EXPECT_EQ(a.end_message, b.end_message);
    EXPECT_EQ(a.steps, b.steps);
    EXPECT_EQ(a.rhs_evaluations, b.rhs_evaluations);
    EXPECT_EQ(a.columns, b.columns);
    EXPECT_EQ(a.metadata, b.metadata);
    EXPECT_NEAR(a.final_time, b.final_time, tol * std::max(1.0, b.final_time));
    ASSERT_EQ(a.rows.size(), b.rows.size());
    double worst = 0.0;
    std::size_t wr = 0, wc = 0;
    for (std::size_t r = 0; r < a.rows.size(); ++r) {
        ASSERT_EQ(a.rows[r].size(), b.rows[r].size());
        for (std::size_t c = 0; c < a.rows[r].size(); ++c) {
            const double d = rel(a.rows[r][c], b.rows[r][c]);
            if (!(d <= worst)) {
                worst = d;
                wr = r;
                wc = c;
            }
        }
    }
    EXPECT_LE(worst, tol) << "worst at row " << wr << " (t = " << b.rows[wr][0] << "), column "
                          << b.columns[wc] << ": " << a.rows[wr][wc] << " vs " << b.rows[wr][wc];
    for (int i = 0; i < fd::euler::size; ++i)
        EXPECT_LE(rel(a.final_state[i], b.final_state[i]), tol) << "final state " << i;
    EXPECT_EQ(a.saturation.input_rows, b.saturation.input_rows);
    EXPECT_EQ(a.saturation.output_samples, b.saturation.output_samples);
    EXPECT_EQ(a.out_of_range.evaluations, b.out_of_range.evaluations);
    ASSERT_EQ(a.out_of_range.entries.size(), b.out_of_range.entries.size())
        << "ensemble:\n"
        << a.out_of_range.summary() << "\nsimulate:\n"
        << b.out_of_range.summary();
    for (std::size_t k = 0; k < a.out_of_range.entries.size(); ++k) {
        const auto &ea = a.out_of_range.entries[k], &eb = b.out_of_range.entries[k];
        EXPECT_EQ(ea.table, eb.table);
        EXPECT_EQ(ea.axis, eb.axis);
        EXPECT_EQ(ea.below, eb.below) << ea.table;
        EXPECT_EQ(ea.above, eb.above) << ea.table;
        EXPECT_LE(rel(ea.lowest, eb.lowest), tol);
        EXPECT_LE(rel(ea.highest, eb.highest), tol);
    }
}

/// Each case simulated alone.
std::vector<fd::SimulationResult> one_by_one(const fd::FlightModel& m,
                                             const std::vector<fd::EnsembleCase>& cases,
                                             const fd::SimulationOptions& opt) {
    std::vector<fd::SimulationResult> out;
    for (const auto& c : cases) out.push_back(fd::simulate(m, c.initial, c.inputs, opt));
    return out;
}

/// Wings level, nose on the horizon, no rates: (x, y, z, phi, theta, psi, V, alpha, beta, p, q, r).
fd::EulerState<double> level_state(double V, double altitude) {
    fd::EulerState<double> s;
    s << 0.0, 0.0, -altitude, 0.0, 0.0, 0.0, V, 0.0, 0.0, 0.0, 0.0, 0.0;
    return s;
}

}  // namespace

// The batched right-hand side equals the one-state one to rounding (eom.hpp, 1e-13), so over
// 12 s of flight the trajectories agree to 1e-9 relative; counts and texts exactly.
TEST(Ensemble, EachCaseEqualsSimulateAloneInBothForms) {
    const std::vector<fd::EnsembleCase> cases = {
        ranger_case("doublet_150_3000", 150.0, 3000.0, doublet_csv),
        ranger_case("roll_120_2000", 120.0, 2000.0, roll_csv),
        ranger_case("pull_200_5000", 200.0, 5000.0, pull_csv),
        ranger_case("trim_180_8000", 180.0, 8000.0, ""),
    };
    for (const auto form : {fd::StateForm::quaternion, fd::StateForm::euler}) {
        SCOPED_TRACE(std::string(fd::to_string(form)));
        fd::SimulationOptions opt;
        opt.duration = 12.0;
        opt.dt = 0.01;  // a row every step: every output row's counts are attributed too
        opt.form = form;
        const auto ens = fd::simulate_ensemble(ranger(), cases, opt);
        const auto ref = one_by_one(ranger(), cases, opt);
        ASSERT_EQ(ens.size(), cases.size());
        for (std::size_t i = 0; i < cases.size(); ++i) {
            SCOPED_TRACE(cases[i].name);
            EXPECT_EQ(ens[i].end_reason, fd::EndReason::completed);
            expect_same(ens[i], ref[i], 1e-9);
        }
        // The cases differ, and the attribution is per case: only the pull leaves the tables
        // (alpha beyond 20 deg) and saturates the elevator.
        EXPECT_GT(std::abs(ens[0].final_state[fd::euler::V] - ens[1].final_state[fd::euler::V]),
                  1.0);
        EXPECT_EQ(ens[0].out_of_range.total(), 0u);
        EXPECT_EQ(ens[1].out_of_range.total(), 0u);
        EXPECT_GT(ens[2].out_of_range.total(), 0u);
        EXPECT_GT(ens[2].saturation.input_rows[0], 0);
        EXPECT_GT(ens[2].saturation.output_samples[0], 0);
        EXPECT_EQ(ens[0].saturation.total(), 0);
        // One table evaluation per right-hand side and one per output row.
        EXPECT_EQ(ens[1].out_of_range.evaluations,
                  static_cast<std::uint64_t>(ens[1].rhs_evaluations) + ens[1].rows.size());
    }
}

TEST(Ensemble, ACaseThatReachesTheGroundDropsOutAndTheOthersGoOn) {
    const std::vector<fd::EnsembleCase> cases = {
        ranger_case("level", 150.0, 3000.0, ""),
        ranger_case("push_low", 150.0, 150.0, push_csv),
        ranger_case("roll", 140.0, 1000.0, roll_csv),
    };
    fd::SimulationOptions opt;
    opt.duration = 15.0;
    opt.dt = 0.01;
    opt.output_interval = 0.1;
    const auto ens = fd::simulate_ensemble(ranger(), cases, opt);
    const auto ref = one_by_one(ranger(), cases, opt);
    ASSERT_EQ(ens.size(), 3u);
    EXPECT_EQ(ens[1].end_reason, fd::EndReason::ground);
    EXPECT_LT(ens[1].final_time, 8.0);
    EXPECT_NEAR(ens[1].final_state[fd::euler::z], 0.0, 1e-6);  // the crossing is located
    EXPECT_NE(ens[1].end_message.find("reached the ground"), std::string::npos);
    for (const std::size_t i : {0u, 2u}) {
        EXPECT_EQ(ens[i].end_reason, fd::EndReason::completed);
        EXPECT_DOUBLE_EQ(ens[i].final_time, 15.0);
        EXPECT_EQ(ens[i].rows.size(), 151u);
    }
    for (std::size_t i = 0; i < 3; ++i) {
        SCOPED_TRACE(cases[i].name);
        expect_same(ens[i], ref[i], 1e-9);
    }
}

TEST(Ensemble, ANanIsRecordedInItsCaseAndDoesNotStopTheOthers) {
    // The absurd engine of test_sim_inputs.cpp (1e308 N): the case whose throttle opens at 2 s
    // overflows; the one at zero throttle flies on.
    auto model = manta::test::rigid_body(1000.0, 1000.0, 2000.0, 2500.0);
    model.engine.static_thrust_sl = 1e308;
    fd::Controls<double> idle;
    const std::vector<fd::EnsembleCase> cases = {
        {"boom", level_state(100.0, 3000.0),
         fd::InputHistory::parse("t,throttle\n0,0\n2,0\n3,1\n", "boom.csv", idle)},
        {"calm", level_state(100.0, 3000.0), fd::InputHistory(idle)},
    };
    fd::SimulationOptions opt;
    opt.duration = 5.0;
    opt.dt = 0.01;
    bool aborted = false;
    opt.on_abort = [&](const fd::SimulationResult&) { aborted = true; };
    const auto ens = fd::simulate_ensemble(model, cases, opt);
    EXPECT_FALSE(aborted);  // the ensemble returns the partial result instead
    ASSERT_EQ(ens.size(), 2u);
    EXPECT_EQ(ens[0].end_reason, fd::EndReason::numerical_error);
    EXPECT_NE(ens[0].end_message.find("non-finite"), std::string::npos) << ens[0].end_message;
    EXPECT_NE(ens[0].end_message.find("last finite state"), std::string::npos);
    EXPECT_EQ(fd::to_string(ens[0].end_reason), "numerical_error");
    EXPECT_GE(ens[0].rows.size(), 200u);
    EXPECT_LT(ens[0].final_time, 3.0);
    bool aborted_line = false;
    for (const auto& m : ens[0].metadata)
        aborted_line |= m.rfind("end: aborted (non-finite state at t = 2.", 0) == 0;
    EXPECT_TRUE(aborted_line);
    EXPECT_EQ(ens[1].end_reason, fd::EndReason::completed);
    EXPECT_EQ(ens[1].rows.size(), 501u);

    // The same as simulate: its on_abort result and its error text, and the calm case.
    fd::SimulationResult partial;
    fd::SimulationOptions o = opt;
    o.on_abort = [&](const fd::SimulationResult& r) { partial = r; };
    try {
        (void)fd::simulate(model, cases[0].initial, cases[0].inputs, o);
        ADD_FAILURE() << "expected NumericalError";
    } catch (const manta::NumericalError& e) {
        EXPECT_EQ(ens[0].end_message, e.what());
    }
    expect_same(ens[0], partial, 1e-12);
    expect_same(ens[1], fd::simulate(model, cases[1].initial, cases[1].inputs, opt), 1e-12);
}

TEST(Ensemble, LeavingTheAtmosphereEndsOnlyThatCase) {
    const auto model = manta::test::rigid_body(1000.0, 1000.0, 2000.0, 2500.0);
    fd::EulerState<double> up = level_state(800.0, 85000.0);
    up[fd::euler::theta] = deg(89.0);
    const std::vector<fd::EnsembleCase> cases = {
        {"glide", level_state(150.0, 5000.0), fd::InputHistory()},
        {"escape", up, fd::InputHistory()},
    };
    fd::SimulationOptions opt;
    opt.duration = 4.0;
    for (const auto form : {fd::StateForm::quaternion, fd::StateForm::euler}) {
        opt.form = form;
        const auto ens = fd::simulate_ensemble(model, cases, opt);
        const auto ref = one_by_one(model, cases, opt);
        EXPECT_EQ(ens[0].end_reason, fd::EndReason::completed);
        EXPECT_EQ(ens[1].end_reason, fd::EndReason::left_atmosphere);
        EXPECT_LT(ens[1].final_time, 2.0);
        for (std::size_t i = 0; i < 2; ++i) expect_same(ens[i], ref[i], 1e-12);
    }
}

TEST(Ensemble, Dopri5RunsTheCasesOneAfterAnotherWithSimulate) {
    const std::vector<fd::EnsembleCase> cases = {
        ranger_case("a", 150.0, 3000.0, doublet_csv),
        ranger_case("b", 110.0, 1500.0, roll_csv),
    };
    fd::SimulationOptions opt;
    opt.duration = 6.0;
    opt.integrator = fd::Integrator::dopri5;
    opt.rtol = opt.atol = 1e-9;
    opt.output_interval = 0.1;
    opt.progress_interval = 0.0;
    std::vector<fd::SimulationProgress> seen;
    opt.progress = [&](const fd::SimulationProgress& p) { seen.push_back(p); };
    const auto ens = fd::simulate_ensemble(ranger(), cases, opt);
    opt.progress = nullptr;
    const auto ref = one_by_one(ranger(), cases, opt);
    for (std::size_t i = 0; i < 2; ++i) {
        SCOPED_TRACE(cases[i].name);
        EXPECT_EQ(ens[i].rows, ref[i].rows);  // the same computation
        expect_same(ens[i], ref[i], 0.0);
    }
    ASSERT_FALSE(seen.empty());
    for (std::size_t k = 1; k < seen.size(); ++k) EXPECT_GE(seen[k].t, seen[k - 1].t);
    EXPECT_EQ(seen.back().n_cases, 2u);
    EXPECT_EQ(seen.back().cases_ended, 2u);
    EXPECT_DOUBLE_EQ(seen.back().fraction(), 1.0);
}

TEST(Ensemble, ProgressCoversTheWholeEnsemble) {
    const auto model = manta::test::rigid_body(1000.0, 1000.0, 2000.0, 2500.0);
    // Free fall from 50 m reaches the ground at 3.2 s; the two others fly the full 5 s.
    const std::vector<fd::EnsembleCase> cases = {
        {"high", level_state(100.0, 3000.0), fd::InputHistory()},
        {"drop", level_state(0.0, 50.0), fd::InputHistory()},
        {"higher", level_state(100.0, 6000.0), fd::InputHistory()},
    };
    fd::SimulationOptions opt;
    opt.duration = 5.0;
    opt.progress_interval = 0.0;
    std::vector<fd::SimulationProgress> seen;
    opt.progress = [&](const fd::SimulationProgress& p) { seen.push_back(p); };
    const auto ens = fd::simulate_ensemble(model, cases, opt);
    EXPECT_EQ(ens[1].end_reason, fd::EndReason::ground);
    ASSERT_GT(seen.size(), 10u);
    for (std::size_t k = 1; k < seen.size(); ++k) {
        EXPECT_GE(seen[k].t, seen[k - 1].t);
        EXPECT_GE(seen[k].cases_ended, seen[k - 1].cases_ended);
    }
    for (const auto& p : seen) {
        EXPECT_EQ(p.n_cases, 3u);
        EXPECT_DOUBLE_EQ(p.duration, 15.0);  // case-seconds
        EXPECT_LE(p.fraction(), 1.0 + 1e-12);
    }
    // Reports come every 32 steps (t = 0.32 k). Before the drop lands (3.19 s) three cases run:
    // done = 3 t; after it, it counts in full: done = 5 + 2 t.
    int after_drop = 0;
    for (std::size_t k = 0; k + 1 < seen.size(); ++k) {
        const auto& p = seen[k];
        const double t = p.cases_ended == 0 ? p.t / 3.0 : (p.t - 5.0) / 2.0;
        EXPECT_NEAR(t, 0.32 * std::round(t / 0.32), 1e-9) << p.t << " " << p.cases_ended;
        EXPECT_EQ(p.cases_ended, t < 3.19 ? 0u : 1u) << t;
        after_drop += p.cases_ended == 1 ? 1 : 0;
    }
    EXPECT_GE(after_drop, 3);
    EXPECT_EQ(seen.back().cases_ended, 3u);
    EXPECT_DOUBLE_EQ(seen.back().fraction(), 1.0);
}

TEST(Ensemble, RejectsABadCaseByNameBeforeRunningAndAcceptsNone) {
    const auto model = manta::test::rigid_body(1000.0, 1000.0, 2000.0, 2500.0);
    const std::vector<fd::EnsembleCase> cases = {
        {"fine", level_state(100.0, 3000.0), fd::InputHistory()},
        {"underground", level_state(100.0, -20.0), fd::InputHistory()},
    };
    fd::SimulationOptions opt;
    opt.duration = 1.0;
    int calls = 0;
    opt.progress = [&](const fd::SimulationProgress&) { ++calls; };
    try {
        (void)fd::simulate_ensemble(model, cases, opt);
        ADD_FAILURE() << "expected InputError";
    } catch (const manta::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("case 'underground'"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("ground altitude"), std::string::npos) << e.what();
    }
    EXPECT_EQ(calls, 0);
    EXPECT_TRUE(fd::simulate_ensemble(model, {}, opt).empty());
    opt.dt = -1.0;
    EXPECT_THROW((void)fd::simulate_ensemble(model, cases, opt), manta::InputError);
}

// simulate's RK4 (a lock-step run of one) applies Boost.Odeint's runge_kutta4 tableau in the
// same order of operations: the same trajectory to the last bit.
TEST(Ensemble, LockstepRk4IsOdeintsRungeKutta4Bitwise) {
    const fd::FlightModel& m = ranger();
    fd::TrimTarget target;
    target.airspeed = 150.0;
    target.altitude = 3000.0;
    const auto trim = fd::trim(m, target);
    const auto inputs = fd::InputHistory::parse(doublet_csv, "doublet.csv", trim.controls);
    fd::SimulationOptions opt;
    opt.duration = 3.0;
    opt.dt = 0.01;
    const auto r = fd::simulate(m, trim.state, inputs, opt);

    using State = std::array<double, fd::quat::size>;
    const auto sys = [&](const State& x, State& dxdt, double t) {
        const fd::QuatState<double> s = Eigen::Map<const fd::QuatState<double>>(x.data());
        const auto u = fd::saturate(inputs.at(t), m.limits).controls;
        Eigen::Map<fd::QuatState<double>>(dxdt.data()) = fd::quaternion_rhs(m, s, u);
    };
    State x;
    Eigen::Map<fd::QuatState<double>>(x.data()) = fd::to_quaternion_state(trim.state);
    boost::numeric::odeint::runge_kutta4<State> rk4;
    for (int n = 0; n < 300; ++n) {  // the driver's grid: t0 = n dt, the last step ends on T
        const double t0 = n * opt.dt, t1 = n + 1 == 300 ? opt.duration : (n + 1) * opt.dt;
        rk4.do_step(sys, x, t0, t1 - t0);
    }
    const fd::EulerState<double> e =
        fd::to_euler_state(Eigen::Map<const fd::QuatState<double>>(x.data()));
    for (int i = 0; i < fd::euler::size; ++i) EXPECT_EQ(r.final_state[i], e[i]) << i;
}
