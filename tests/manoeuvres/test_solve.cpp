/// @file test_solve.cpp
/// A short manoeuvre (level 90-degree turn) solved end to end: convergence, final conditions,
/// path constraints, re-simulation, and the exact derivatives of the transcription.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "manta/aircraft/aircraft.hpp"
#include "manta/core/error.hpp"
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

TEST(ManoeuvreSolve, ExactDerivativesWithTheIntermediateCondition) {
    // the Lazy Eight's interior events at the free junction of its two phases
    const auto aircraft = aircraft::load_aircraft(kDir / "aircraft.yaml");
    const ManoeuvreSpec spec = load_manoeuvre(kDir / "manoeuvres/lazy_eight.yaml");
    const ManoeuvreProblem problem(manoeuvre_model(aircraft, spec), spec);
    EXPECT_EQ(problem.info().n_interior_events(), 6);  // bank, heading (sin, cos), gamma, altitude
    EXPECT_EQ(problem.phase_names(), (std::vector<std::string>{"climb", "dive"}));
    EXPECT_EQ(problem.phase_of_segment(1, 4), 0);
    EXPECT_EQ(problem.phase_of_segment(2, 4), 1);
    // alpha, beta, nz, then the file's Mach, true airspeed and bank limits: their derivatives
    // are checked below with the rest
    ASSERT_EQ(problem.info().path.size(), 6U);
    EXPECT_EQ(problem.info().path[3].name, "mach");
    EXPECT_EQ(problem.info().path[4].name, "speed");
    EXPECT_EQ(problem.info().path[5].name, "bank");
    const auto model = make_model(problem);
    optimal::Mesh mesh = optimal::Mesh::uniform(4, 5);
    mesh.free_breaks = true;
    const optimal::DerivativeCheck d = optimal::check_derivatives(*model, mesh, problem.guess());
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

    // the trajectory files: the shared format (docs/manoeuvres.md#trajectory-csv)
    const std::vector<std::string> required{
        "t",    "x", "y", "z", "phi",      "theta",   "psi",    "V",       "alpha",
        "beta", "p", "q", "r", "elevator", "aileron", "rudder", "throttle"};
    ASSERT_GE(t.columns.size(), required.size() + 1);
    for (std::size_t i = 0; i < required.size(); ++i) EXPECT_EQ(t.columns[i], required[i]);
    EXPECT_EQ(t.columns[required.size()], "phase");
    EXPECT_EQ(t.rows.size(), 20U);
    EXPECT_EQ(t.meta("phases"), "manoeuvre");
    EXPECT_EQ(t.meta("mass_case"), "lazy_eight");
    // SI and radians: 90 deg of heading is pi/2 rad, altitude = -z
    EXPECT_NEAR(t.column("psi").back() - t.column("psi").front(), std::numbers::pi / 2, 1e-4);
    EXPECT_NEAR(t.column("z").front(), -3000.0, 1e-9);
    EXPECT_NEAR(t.column("altitude").front(), 3000.0, 1e-9);
    const Trajectory d = dense_trajectory(problem, s, 0.02);
    EXPECT_EQ(d.columns, t.columns);
    const auto td = d.column("t");
    EXPECT_DOUBLE_EQ(td.front(), 0.0);
    EXPECT_DOUBLE_EQ(td.back(), s.final_time);  // closes with the final time
    EXPECT_NEAR(td[1] - td[0], 0.02, 1e-12);
    EXPECT_EQ(td.size(), static_cast<std::size_t>(std::ceil(s.final_time / 0.02 - 1e-9)) + 1);
    // the interpolant goes through the nodes: the dense samples at the ends match them
    EXPECT_NEAR(d.column("V").back(), t.column("V").back(), 1e-9);
    EXPECT_NEAR(d.column("phi").back(), t.column("phi").back(), 1e-9);
    const auto dir = std::filesystem::temp_directory_path() / "manta_test_trajectory";
    std::filesystem::create_directories(dir);
    write_trajectory_csv(d, dir / "trajectory_dense.csv");
    std::ifstream in(dir / "trajectory_dense.csv");
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "# manoeuvre: level_turn_90");
    int meta = 1;
    while (std::getline(in, line) && line.rfind("# ", 0) == 0) ++meta;
    EXPECT_EQ(meta, 6);  // manoeuvre, mass_case, phases, nodes, final_time, step
    EXPECT_EQ(line.rfind("t,x,y,z,phi,theta,psi,V,alpha,beta,p,q,r,elevator,aileron,rudder,"
                         "throttle,phase,",
                         0),
              0U)
        << line;
    std::getline(in, line);
    EXPECT_NE(line.find(",0,"), std::string::npos) << "phase written as an integer: " << line;
    std::filesystem::remove_all(dir);
}

/// A full aileron roll to the left (not from the paper): level entry at 150 m/s, 3 000 m;
/// an accumulated body roll of -360 deg, wings level at the exit; a slow roll rate limit.
constexpr const char* kAileronRoll = R"(
name: aileron_roll
entry: {speed: 150.0, altitude: 3000.0}
final:
  roll_angle_deg: -360
  bank_deg: 0
  heading_change_deg: [-20, 20]
  altitude: {entry_offset: [-300, 300]}
path:
  body_rate_max_deg_s: [60, 60, 60]
  roll_direction: left
mesh: {nodes: 16, coarse_nodes: 0}
guess:
  duration: 8.0
  duration_bounds: [1.0, 60.0]
  waypoints:
    - {fraction: 0.25, bank_deg: -90}
    - {fraction: 0.5, bank_deg: -180}
    - {fraction: 0.75, bank_deg: -270}
    - {fraction: 1.0, bank_deg: -360}
)";

TEST(ManoeuvreSolve, RollDirectionRollsOneWay) {
    // path.roll_direction: left bounds the body roll rate to p <= 0 at every node, so the
    // accumulated roll angle falls monotonically to its final -360 deg
    const auto aircraft = aircraft::load_aircraft(kDir / "aircraft.yaml");
    const ManoeuvreSpec spec = parse_manoeuvre(kAileronRoll, "aileron_roll.yaml");
    ASSERT_EQ(spec.roll_direction, -1);
    const ManoeuvreProblem problem(manoeuvre_model(aircraft, spec), spec);
    EXPECT_EQ(problem.info().states[flightdyn::quat::p].upper, 0.0);
    EXPECT_LT(problem.info().states[flightdyn::quat::p].lower, 0.0);
    optimal::SolverOptions o;
    o.tolerance = spec.tolerance;
    o.print_level = 0;
    const optimal::Solution s = fly(problem, o).solution;
    ASSERT_TRUE(s.converged()) << s.status_text;
    const Trajectory t = trajectory(problem, s);
    const auto p = t.column("p");
    const auto roll = t.column("roll_angle");
    constexpr double kTol = 1e-6;  // IPOPT's bound relaxation (bound_relax_factor 1e-8)
    for (std::size_t i = 0; i < p.size(); ++i) {
        EXPECT_LE(p[i], kTol) << "node " << i;
        if (i > 0) {
            EXPECT_LE(roll[i], roll[i - 1] + kTol) << "node " << i;
        }
    }
    EXPECT_NEAR(roll.back(), -2.0 * std::numbers::pi, 1e-6);
    // between the nodes too: the dense samples of the Lagrange polynomials
    const auto rd = dense_trajectory(problem, s, 0.02).column("roll_angle");
    for (std::size_t i = 1; i < rd.size(); ++i) {
        EXPECT_LE(rd[i], rd[i - 1] + 1e-4) << "sample " << i;
    }
    const ConstraintCheck c = check(problem, t);
    EXPECT_NEAR(c.final_bank_deg, 0.0, 1e-3);
    // to the right: p >= 0 at every node (the bound only; the solve is the mirror image)
    std::string right = kAileronRoll;
    const std::string left = "roll_direction: left";
    right.replace(right.find(left), left.size(), "roll_direction: right");
    const ManoeuvreSpec rs = parse_manoeuvre(right, "aileron_roll_right.yaml");
    const ManoeuvreProblem rp(manoeuvre_model(aircraft, rs), rs);
    EXPECT_EQ(rp.info().states[flightdyn::quat::p].lower, 0.0);
    EXPECT_GT(rp.info().states[flightdyn::quat::p].upper, 0.0);
    // either way (the default): the symmetric body-rate bound
    std::string either = kAileronRoll;
    either.replace(either.find(left), left.size(), "roll_direction: either");
    const ManoeuvreSpec es = parse_manoeuvre(either, "aileron_roll_either.yaml");
    const ManoeuvreProblem ep(manoeuvre_model(aircraft, es), es);
    EXPECT_EQ(ep.info().states[flightdyn::quat::p].lower,
              -ep.info().states[flightdyn::quat::p].upper);
}

TEST(ManoeuvreSolve, RollDirectionAgainstTheEntryRollRate) {
    // a given entry already rolling right cannot be held to a roll to the left: one line
    const auto aircraft = aircraft::load_aircraft(kDir / "aircraft.yaml");
    std::string text = kAileronRoll;
    const std::string entry = "entry: {speed: 150.0, altitude: 3000.0}";
    text.replace(text.find(entry), entry.size(),
                 "entry: {speed: 150.0, altitude: 3000.0, condition: given, alpha_deg: 2, "
                 "p_deg: 10}");
    const ManoeuvreSpec spec = parse_manoeuvre(text, "rolling.yaml");
    try {
        const ManoeuvreProblem problem(manoeuvre_model(aircraft, spec), spec);
        FAIL() << "accepted";
    } catch (const InputError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("rolling.yaml"), std::string::npos) << m;
        EXPECT_NE(m.find("roll_direction"), std::string::npos) << m;
        EXPECT_NE(m.find("10"), std::string::npos) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
}

TEST(ManoeuvreSolve, TablesOverrideTheAircraftsAeroModel) {
    // `manta optimise --tables DB`: a database file replaces the aircraft's aero model. The
    // aircraft's own database written to a file and read back (exact round trip) is the model
    // flown, and gives the same optimum.
    const auto aircraft = aircraft::load_aircraft(kDir / "aircraft.yaml");
    const ManoeuvreSpec spec = load_manoeuvre(kDir / "manoeuvres/level_turn.yaml");
    const flightdyn::FlightModel own = manoeuvre_model(aircraft, spec);
    const auto file = std::filesystem::temp_directory_path() / "manta_test_tables.db";
    own.aero->write(file);
    const auto tables = std::make_shared<const aero::AeroDatabase>(aero::AeroDatabase::read(file));
    std::filesystem::remove(file);
    const ManoeuvreProblem a(own, spec);
    const ManoeuvreProblem b(manoeuvre_model(aircraft, spec, tables), spec);
    EXPECT_EQ(b.model().aero.get(), tables.get());
    optimal::SolverOptions o;
    o.tolerance = spec.tolerance;
    o.resimulate = false;
    const ManoeuvreResult ra = fly(a, o);
    const ManoeuvreResult rb = fly(b, o);
    ASSERT_TRUE(ra.solution.converged());
    ASSERT_TRUE(rb.solution.converged());
    EXPECT_NEAR(rb.solution.final_time, ra.solution.final_time, 1e-9);
}

}  // namespace
}  // namespace manta::manoeuvres
