/// @file test_solve.cpp
/// A short manoeuvre (level 90-degree turn) solved end to end: convergence, final conditions,
/// path constraints, re-simulation, and the exact derivatives of the transcription.

#include <gtest/gtest.h>

#include <cmath>
#include <span>

#include "manta/aircraft/aircraft.hpp"
#include "manta/manoeuvres/manoeuvre.hpp"
#include "manta/manoeuvres/problem.hpp"

namespace manta::manoeuvres {
namespace {

const std::filesystem::path kDir = std::filesystem::path(MANTA_SOURCE_DIR) / "examples/ranger2000";

TEST(ManoeuvreSolve, ExactDerivativesOfTheTranscription) {
    // The AD derivatives of the 6-DoF dynamics (C1 tables, alpha-dot terms, atmosphere), the
    // path constraints and the events against central finite differences.
    const auto aircraft = aircraft::load_aircraft(kDir / "aircraft.yaml");
    const ManoeuvreSpec spec = load_manoeuvre(kDir / "manoeuvres/immelmann.yaml");
    const ManoeuvreProblem problem(manoeuvre_model(aircraft, spec), spec);
    const auto model = make_model(problem);
    const optimal::DerivativeCheck d =
        optimal::check_derivatives(*model, optimal::Mesh::uniform(2, 5), problem.guess());
    EXPECT_LT(d.gradient_error, 1e-6);
    EXPECT_LT(d.jacobian_error, 1e-5) << "row " << d.worst_row << " col " << d.worst_col;
    EXPECT_LT(d.hessian_error, 1e-4);
}

TEST(ManoeuvreSolve, EntryIsTrimmed) {
    const auto aircraft = aircraft::load_aircraft(kDir / "aircraft.yaml");
    const ManoeuvreSpec spec = load_manoeuvre(kDir / "manoeuvres/level_turn.yaml");
    const ManoeuvreProblem problem(manoeuvre_model(aircraft, spec), spec);
    EXPECT_DOUBLE_EQ(problem.model().mass.mass, 3498.0);
    const Eigen::VectorXd x0 = problem.entry_state();
    const Eigen::VectorXd u0 = problem.entry_controls();
    Eigen::VectorXd xdot(x0.size());
    problem.dynamics<double>(std::span<const double>(x0.data(), x0.size()),
                             std::span<const double>(u0.data(), u0.size()), {}, 0.0,
                             std::span<double>(xdot.data(), xdot.size()));
    // steady: no acceleration, no angular acceleration, level flight north at 150 m/s
    for (int i : {7, 8, 9, 10, 11, 12}) EXPECT_NEAR(xdot[i], 0.0, 1e-8) << i;
    EXPECT_NEAR(xdot[0], 150.0, 1e-8);
    EXPECT_NEAR(xdot[2], 0.0, 1e-8);
}

TEST(ManoeuvreSolve, LevelTurnConverges) {
    const auto aircraft = aircraft::load_aircraft(kDir / "aircraft.yaml");
    const ManoeuvreSpec spec = load_manoeuvre(kDir / "manoeuvres/level_turn.yaml");
    const ManoeuvreProblem problem(manoeuvre_model(aircraft, spec), spec);
    optimal::SolverOptions o;
    o.tolerance = spec.tolerance;
    o.print_level = 0;
    const ManoeuvreResult r = fly(problem, o);
    const optimal::Solution& s = r.solution;
    ASSERT_TRUE(s.converged()) << s.status_text;
    std::printf("level turn: tf %.4f s, %d iterations, %.2f s CPU, resim %.2e\n", s.final_time,
                s.iterations, s.cpu_time, s.resimulation.max_scaled_error);
    const Trajectory t = trajectory(problem, s);
    const ConstraintCheck c = check(problem, t);
    EXPECT_NEAR(c.final_heading_change_deg, 90.0, 1e-3);
    EXPECT_NEAR(c.final_bank_deg, 0.0, 1e-3);
    EXPECT_NEAR(c.final_speed, 150.0, 1e-3);
    EXPECT_NEAR(c.final_altitude, 3000.0, 1e-2);
    EXPECT_LE(c.alpha_max_deg, 12.0 + 1e-4);
    EXPECT_LE(c.load_factor_max, 6.0 + 1e-4);
    EXPECT_LE(c.control_limit_excess, 1e-9);
    // A 90-degree turn at <= 6 g and 150 m/s: turn rate at most g sqrt(n^2 - 1) / V
    // = 0.39 rad/s, so no faster than 4 s; the roll in and out add to it.
    EXPECT_GT(s.final_time, 4.0);
    EXPECT_LT(s.final_time, 30.0);
    // Re-simulating the interpolated bang-bang controls open loop: a few metres and a few
    // hundredths of a rad/s after the turn (measured 0.22 on the scaled states).
    ASSERT_TRUE(s.resimulation.done) << s.resimulation.message;
    EXPECT_LT(s.resimulation.max_scaled_error, 0.5);
}

}  // namespace
}  // namespace manta::manoeuvres
