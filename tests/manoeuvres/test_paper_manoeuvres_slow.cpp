/// @file test_paper_manoeuvres_slow.cpp
/// The paper's three manoeuvres (Ghoreyshi, Badcock, Da Ronch et al., "Simulation of aircraft
/// manoeuvres based on computational fluid dynamics", AIAA 2010, sec. V, Figs. 9-15) solved as
/// time-optimal control problems from the example files: each converges, meets its final and
/// intermediate conditions and path constraints, and falls inside the envelope of the paper's
/// figures (issue 16, docs/manoeuvres.md#the-paper-s-manoeuvres): duration, altitude band, the
/// largest angle of attack and Mach number the paper reports, heading change or roll, and an
/// a-posteriori re-simulation error below 0.05 (scaled).
/// Label `slow`: up to about two minutes of CPU per manoeuvre on a 2-core machine.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "manta/aircraft/aircraft.hpp"
#include "manta/manoeuvres/manoeuvre.hpp"
#include "manta/manoeuvres/problem.hpp"

namespace manta::manoeuvres {
namespace {

const std::filesystem::path kDir = std::filesystem::path(MANTA_SOURCE_DIR) / "examples/ranger2000";
constexpr double kDeg = 3.14159265358979323846 / 180.0;

struct Flown {
    ManoeuvreSpec spec;
    optimal::Solution solution;
    ConstraintCheck check;
    Trajectory trajectory;  ///< at the LGL nodes
};

Flown fly_file(const std::string& file) {
    static const auto aircraft = aircraft::load_aircraft(kDir / "aircraft.yaml");
    Flown f;
    f.spec = load_manoeuvre(kDir / "manoeuvres" / file);
    const ManoeuvreProblem problem(manoeuvre_model(aircraft, f.spec), f.spec);
    optimal::SolverOptions o;
    o.tolerance = f.spec.tolerance;
    f.solution = fly(problem, o).solution;
    f.trajectory = trajectory(problem, f.solution);
    f.check = check(problem, f.trajectory);
    std::printf(
        "%s: tf %.3f s, %d iterations, %.1f s CPU, violation %.2e, resim %.3f, altitude "
        "%.0f-%.0f m, alpha max %.2f deg, Mach max %.3f, nz %.2f-%.2f\n",
        f.spec.name.c_str(), f.solution.final_time, f.solution.iterations, f.solution.cpu_time,
        f.solution.max_violation, f.solution.resimulation.max_scaled_error, f.check.altitude_min,
        f.check.altitude_max, f.check.alpha_max_deg, f.check.mach_max, f.check.load_factor_min,
        f.check.load_factor_max);
    return f;
}

/// The envelope of a manoeuvre read off the paper's figures (issue 16).
struct Envelope {
    double duration_min, duration_max;  ///< [s]
    double altitude_min, altitude_max;  ///< [m]
    double alpha_max_deg;
    double mach_max;
    double resimulation_max = 0.05;  ///< scaled re-simulation error
};

void expect_inside(const Flown& f, const Envelope& e) {
    ASSERT_TRUE(f.solution.converged()) << f.solution.status_text;
    // the file's own constraints
    EXPECT_LE(f.check.alpha_max_deg, f.spec.alpha[1] / kDeg + 1e-3);
    EXPECT_LE(f.check.load_factor_max, f.spec.load_factor[1] + 1e-3);
    EXPECT_GE(f.check.load_factor_min, f.spec.load_factor[0] - 1e-3);
    EXPECT_LE(f.check.control_limit_excess, 1e-8);
    EXPECT_NEAR(f.check.final_bank_deg, 0.0, 1e-2);
    EXPECT_NEAR(f.check.final_speed, f.spec.entry_speed, 1e-2);
    EXPECT_GE(f.check.final_altitude, f.spec.entry_altitude - 0.1);
    // the paper's envelope
    EXPECT_GE(f.solution.final_time, e.duration_min);
    EXPECT_LE(f.solution.final_time, e.duration_max);
    EXPECT_GE(f.check.altitude_min, e.altitude_min);
    EXPECT_LE(f.check.altitude_max, e.altitude_max);
    EXPECT_LE(f.check.alpha_max_deg, e.alpha_max_deg + 1e-3);
    EXPECT_LE(f.check.mach_max, e.mach_max + 1e-4);
    // the controls re-simulated open loop stay on the collocated path
    ASSERT_TRUE(f.solution.resimulation.done) << f.solution.resimulation.message;
    EXPECT_LT(f.solution.resimulation.max_scaled_error, e.resimulation_max);
}

/// Index of the junction node (last node of the first phase).
std::size_t junction(const Flown& f) {
    const auto phase = f.trajectory.column("phase");
    std::size_t j = 0;
    while (j + 1 < phase.size() && phase[j + 1] == 0.0) ++j;
    return j;
}

TEST(PaperManoeuvres, Immelmann) {
    // Fig. 12: 0-40 s time axis, altitude axis 2 800-4 400 m, alpha <= 12 deg (sec. V); the
    // replay of Fig. 15 spans 20 s of it. Mach: Table 4's flight-test range ends at 0.75.
    const Flown f = fly_file("immelmann.yaml");
    expect_inside(f, {20.0, 25.0, 2800.0, 4400.0, 12.0, 0.75});
    EXPECT_NEAR(std::abs(f.check.final_heading_change_deg), 180.0, 1e-2);
    EXPECT_GT(f.check.altitude_max, f.spec.entry_altitude + 400.0);  // a half loop
}

TEST(PaperManoeuvres, LazyEight) {
    // Figs. 10 and 13: 0-60 s time axis (the replay 50 s), altitude axis 2 800-4 400 m; "the
    // angle of attack remains below six degrees with a maximum Mach number of 0.44" (sec. IV.C)
    // The re-simulation error was 0.29 before the file limited the body rates (a dive rolling
    // at up to 68 deg/s, bank and sideslip switching between their bounds) and the mesh tied
    // each phase's segments to the junction (docs/manoeuvres.md#results). With the top 1 225 m
    // above the entry and |beta| <= 1 deg (the file since issue 16's demo tables): 53.04 s,
    // re-simulation 0.018 measured (56.16 s and 0.031 on the demo's vortex-lattice tables).
    const Flown f = fly_file("lazy_eight.yaml");
    expect_inside(f, {50.0, 60.0, 2800.0, 4400.0, 6.0, 0.44});
    EXPECT_NEAR(std::abs(f.check.final_heading_change_deg), 180.0, 1e-2);
    EXPECT_NEAR(f.check.final_altitude, f.spec.entry_altitude, 0.1);
    // the top of the climb: 90 deg of bank at heading 90 deg, level, at the file's altitude gain
    const std::size_t j = junction(f);
    ASSERT_LT(j + 1, f.trajectory.rows.size()) << "no dive phase";
    EXPECT_NEAR(f.trajectory.column("phi")[j] / kDeg, 90.0, 1e-2);
    EXPECT_NEAR((f.trajectory.column("psi")[j] - f.trajectory.column("psi")[0]) / kDeg, 90.0, 1e-2);
    EXPECT_NEAR(f.trajectory.column("gamma")[j] / kDeg, 0.0, 1e-2);
    EXPECT_GE(f.trajectory.column("altitude")[j],
              f.spec.entry_altitude + f.spec.intermediate.altitude.lower - 1e-3);
    EXPECT_NEAR(f.trajectory.column("t")[j], f.solution.breaks[f.solution.breaks.size() / 2], 1e-9);
    // a climbing then diving turn banked one way (0-90 deg): the heading turns back by no more
    // than the sideslip allows where the wings are level (1.5 deg measured)
    // the lazy rates of the file: roll at most 12 deg/s, pitch and yaw at most 20 deg/s
    for (const auto& [name, limit] :
         {std::pair<const char*, double>{"p", 12.0}, {"q", 20.0}, {"r", 20.0}}) {
        for (double v : f.trajectory.column(name)) EXPECT_LE(std::abs(v) / kDeg, limit + 1e-3);
    }
    // coordinated flight, the slip ball centred: |beta| <= 1 deg at every node
    for (double v : f.trajectory.column("beta")) EXPECT_LE(std::abs(v) / kDeg, 1.0 + 1e-3);
    const auto psi = f.trajectory.column("psi");
    double top = psi.front();
    for (std::size_t i = 1; i < psi.size(); ++i) {
        top = std::max(top, psi[i]);
        EXPECT_LE(top - psi[i], 6.0 * kDeg) << "node " << i;
    }
}

TEST(PaperManoeuvres, BarrelRoll) {
    // Figs. 11 and 14: 0-60 s time axis (the replay 50 s), altitude axis 6 000-7 000 m; "the
    // angle of attack during manoeuvre time remains below eight degrees" (sec. IV.C); a full
    // roll, inverted near the highest point (sec. V). Mach: Table 4's range.
    const Flown f = fly_file("barrel_roll.yaml");
    expect_inside(f, {45.0, 60.0, 6000.0, 7000.0, 8.0, 0.75});
    const double roll = f.trajectory.column("roll_angle").back() / kDeg;
    EXPECT_LE(roll, -340.0 + 1e-2);
    EXPECT_GE(roll, -380.0 - 1e-2);
    // one way (path.roll_direction: left): p <= 0 at every node, and the accumulated roll
    // never turns back by more than the collocation's wiggle where p holds at 0 (the degree-19
    // polynomial of the roll state: 0.41 deg measured; the file before the key rolled -461 deg
    // left and +121 deg back right)
    const auto p = f.trajectory.column("p");
    for (std::size_t i = 0; i < p.size(); ++i) EXPECT_LE(p[i], 1e-6) << "node " << i;
    double lowest = 0.0, back = 0.0;
    for (double a : f.trajectory.column("roll_angle")) {
        lowest = std::min(lowest, a);
        back = std::max(back, a - lowest);
    }
    std::printf("barrel roll: largest roll back %.3f deg\n", back / kDeg);
    EXPECT_LE(back / kDeg, 0.5);
    const std::size_t j = junction(f);
    EXPECT_NEAR(std::abs(f.trajectory.column("phi")[j] / kDeg), 180.0, 1e-2);  // inverted
    EXPECT_GE(f.trajectory.column("altitude")[j],
              f.spec.entry_altitude + f.spec.intermediate.altitude.lower - 1e-3);
}

}  // namespace
}  // namespace manta::manoeuvres
