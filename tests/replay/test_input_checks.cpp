// A replay's inputs compared before any flow solution starts (replay/input_checks.hpp,
// docs/replay.md "Bad input"):
//  - a mesh companion or a tables folder of another aircraft (other reference values) is a
//    one-line InputError naming the file, the value and the aircraft file's; the same reference
//    under another name is a warning;
//  - a half model for a trajectory with sideslip, roll or yaw rate, aileron or rudder is an
//    error naming the column, its largest value and its time; a longitudinal one passes;
//  - a control the trajectory moves without a control surface, a flow.mach other than the entry
//    Mach number, no reference values at all: errors; an explicit other reference: a warning;
//  - Mach beyond the tables' range: a warning within 0.1, an error beyond; alpha beyond the
//    static table, a control without a table, another aircraft's trajectory: warnings.

#include <gtest/gtest.h>

#include <numbers>
#include <sstream>
#include <string>

#include "manta/core/error.hpp"
#include "manta/replay/input_checks.hpp"

namespace {

using namespace manta;
constexpr double deg = std::numbers::pi / 180.0;

struct Lateral {
    double beta = 0.0, p = 0.0, r = 0.0, aileron = 0.0, rudder = 0.0, elevator = 0.0;
};

/// Level flight at 150 m/s, Mach 0.45 (its column) with `mach_step` per row, 1 s in 0.1 s
/// rows; the lateral values (and the elevator) at the row t = 0.5 s, 0 elsewhere.
replay::Trajectory flight(const Lateral& l = {}, double mach_step = 0.0,
                          const std::string& aircraft = "Test jet") {
    std::ostringstream s;
    s.precision(17);
    s << "# aircraft: " << aircraft
      << "\nt,x,y,z,phi,theta,psi,V,alpha,beta,p,q,r,elevator,aileron,rudder,mach\n";
    for (int i = 0; i <= 10; ++i) {
        const bool at = i == 5;
        s << 0.1 * i << ',' << 15.0 * i << ",0,-3000,0," << 2 * deg << ",0,150," << 2 * deg << ','
          << (at ? l.beta : 0.0) << ',' << (at ? l.p : 0.0) << ",0," << (at ? l.r : 0.0) << ','
          << (at ? l.elevator : 0.0) << ',' << (at ? l.aileron : 0.0) << ','
          << (at ? l.rudder : 0.0) << ',' << 0.45 + mach_step * i << '\n';
    }
    return replay::parse_trajectory(s.str(), "traj.csv");
}

replay::AircraftFacts aircraft() {
    return {"jet.yaml", "Test jet", {15.5, 1.545, 10.46, {4.911, 0.0, 0.12}}};
}

/// The Euler set-up of a full mesh of the aircraft, its companion agreeing, an elevator.
replay::EulerFacts euler_setup() {
    replay::EulerFacts e;
    e.mesh = "jet.su2";
    e.config = "cfd.yaml";
    replay::CompanionFacts c;
    c.file = "jet.mesh.yaml";
    c.aircraft_name = "Test jet";
    c.reference = aircraft().reference;
    c.control_modes = {"elevator"};
    e.companion = c;
    e.reference = aircraft().reference;
    e.control_modes = {"elevator"};
    return e;
}

/// The one-line message of the InputError `f` throws ("" if none).
template <class F>
std::string error_of(F&& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return {};
}

bool one_line(const std::string& s) {
    return !s.empty() && s.find('\n') == std::string::npos;
}

aero::AeroDatabase tables(std::vector<double> mach, bool elevator, const std::string& name) {
    aero::LinearDerivatives d;
    d.CL_0 = 0.2;
    d.CL_alpha = 5.0;
    d.CD_0 = 0.02;
    d.CL_de = 0.4;
    aero::DerivativeGrids g;
    g.alpha = {-4 * deg, 0.0, 4 * deg, 8 * deg};
    g.mach = std::move(mach);
    g.beta = {0.0};
    if (elevator) g.elevator = {-10 * deg, 0.0, 10 * deg};
    return aero::AeroDatabase::from_derivatives(d, g, {name, "", "test"});
}

TEST(InputChecksTest, TheAgreeingSetUpPasses) {
    EXPECT_TRUE(replay::check_euler_setup(euler_setup(), aircraft(), flight({.elevator = 2 * deg}))
                    .empty());
    const aero::AeroDatabase db = tables({0.3, 0.6}, true, "Test jet (Euler)");
    replay::TablesFacts t{"tables", &db, {}};
    EXPECT_TRUE(replay::check_tables(t, aircraft(), flight({.elevator = 2 * deg})).empty());
}

TEST(InputChecksTest, MeshCompanionOfAnotherAircraft) {
    replay::EulerFacts e = euler_setup();
    e.companion->aircraft_name = "Other jet";
    e.companion->reference.area = 20.0;
    const std::string m =
        error_of([&] { (void)replay::check_euler_setup(e, aircraft(), flight()); });
    EXPECT_TRUE(one_line(m)) << m;
    EXPECT_NE(m.find("jet.su2: a mesh of the aircraft 'Other jet'"), std::string::npos) << m;
    EXPECT_NE(m.find("jet.mesh.yaml has reference area 20 m^2"), std::string::npos) << m;
    EXPECT_NE(m.find("jet.yaml ('Test jet': area 15.5 m^2"), std::string::npos) << m;
    // Chord, span and moment point count too; the 10 digits a companion keeps do not.
    e = euler_setup();
    e.companion->reference.chord = 1.6;
    EXPECT_NE(error_of([&] {
                  (void)replay::check_euler_setup(e, aircraft(), flight());
              }).find("reference chord 1.6 m"),
              std::string::npos);
    e = euler_setup();
    e.companion->reference.moment_point[0] = 5.2;
    EXPECT_NE(error_of([&] {
                  (void)replay::check_euler_setup(e, aircraft(), flight());
              }).find("moment point [5.2, 0, 0.12] m"),
              std::string::npos);
    e = euler_setup();
    e.companion->reference.moment_point[0] = 4.911000000123;
    EXPECT_TRUE(replay::check_euler_setup(e, aircraft(), flight()).empty());
    // Another name, the same reference values: a warning.
    e = euler_setup();
    e.companion->aircraft_name = "Test jet mk2";
    const auto w = replay::check_euler_setup(e, aircraft(), flight());
    ASSERT_EQ(w.size(), 1u);
    EXPECT_NE(w[0].find("warning: jet.su2: a mesh of the aircraft 'Test jet mk2'"),
              std::string::npos)
        << w[0];
}

TEST(InputChecksTest, HalfModelRefusesLateralMotion) {
    replay::EulerFacts e = euler_setup();
    e.half_model = true;
    e.companion->half_model = true;
    e.reference.area = 15.5 / 2;  // what a half model's solver divides by
    e.control_modes = {"elevator", "aileron", "rudder"};
    EXPECT_TRUE(replay::check_euler_setup(e, aircraft(), flight({.elevator = 1 * deg})).empty());
    const struct {
        Lateral l;
        const char* what;
    } cases[] = {{{.beta = 1 * deg}, "sideslip 1 deg at t = 0.5 s"},
                 {{.p = 0.2}, "roll rate p 11.5 deg/s at t = 0.5 s"},
                 {{.r = -0.1}, "yaw rate r -5.73 deg/s at t = 0.5 s"},
                 {{.aileron = 3 * deg}, "aileron deflection 3 deg at t = 0.5 s"},
                 {{.rudder = -2 * deg}, "rudder deflection -2 deg at t = 0.5 s"}};
    for (const auto& c : cases) {
        const std::string m =
            error_of([&] { (void)replay::check_euler_setup(e, aircraft(), flight(c.l)); });
        EXPECT_TRUE(one_line(m)) << m;
        EXPECT_NE(m.find("jet.su2: a half model (jet.mesh.yaml: model: half)"), std::string::npos)
            << m;
        EXPECT_NE(m.find(c.what), std::string::npos) << m;
        EXPECT_NE(m.find("expected a full-model mesh"), std::string::npos) << m;
    }
    // Round-off of a longitudinal simulation is no lateral motion.
    EXPECT_TRUE(
        replay::check_euler_setup(e, aircraft(), flight({.beta = 1e-20, .p = 1e-18, .r = -1e-18}))
            .empty());
}

TEST(InputChecksTest, ControlWithoutSurfaceMachAndReference) {
    replay::EulerFacts e = euler_setup();
    e.control_modes.clear();
    std::string m = error_of(
        [&] { (void)replay::check_euler_setup(e, aircraft(), flight({.elevator = -2 * deg})); });
    EXPECT_TRUE(one_line(m)) << m;
    EXPECT_NE(m.find("traj.csv: the control mode 'elevator' deflects (up to -2 deg at t = 0.5 s) "
                     "and cfd.yaml with the mesh companion jet.mesh.yaml has no control surface"),
              std::string::npos)
        << m;
    e = euler_setup();
    e.mach = 0.3;
    m = error_of([&] { (void)replay::check_euler_setup(e, aircraft(), flight()); });
    EXPECT_NE(m.find("cfd.yaml: flow.mach 0.3; the trajectory traj.csv enters at Mach 0.45"),
              std::string::npos)
        << m;
    e.mach = 0.45;
    EXPECT_TRUE(replay::check_euler_setup(e, aircraft(), flight()).empty());
    // No reference anywhere: the solver's defaults (area 0: the projected wall) are an error;
    // an explicit other reference in the configuration a warning.
    e = euler_setup();
    e.companion.reset();
    e.reference = {0.0, 1.0, 1.0, {0.0, 0.0, 0.0}};
    m = error_of([&] { (void)replay::check_euler_setup(e, aircraft(), flight()); });
    EXPECT_TRUE(one_line(m)) << m;
    EXPECT_NE(m.find("cfd.yaml: no reference values for the mesh jet.su2 (no `reference:` "
                     "section and no mesh companion file; the solver's reference area 0 m^2)"),
              std::string::npos)
        << m;
    e.reference_given = true;
    e.ignored_flow_keys = {"alpha"};
    const auto w = replay::check_euler_setup(e, aircraft(), flight());
    ASSERT_EQ(w.size(), 2u);
    EXPECT_NE(w[0].find("warning: cfd.yaml: reference: reference area 0 m^2"), std::string::npos)
        << w[0];
    EXPECT_NE(w[1].find("flow.alpha is not used by the replay"), std::string::npos) << w[1];
}

TEST(InputChecksTest, TablesOfAnotherAircraftOrMach) {
    const aero::AeroDatabase db = tables({0.3, 0.4}, true, "Test jet (Euler)");
    replay::TablesFacts t{"tab", &db, {}};
    replay::CompanionFacts c;
    c.file = "tab/mesh/jet_full_coarse.mesh.yaml";
    c.aircraft_name = "Other jet";
    c.reference = aircraft().reference;
    c.reference.span = 9.0;
    t.mesh_companions = {c};
    std::string m = error_of([&] { (void)replay::check_tables(t, aircraft(), flight()); });
    EXPECT_TRUE(one_line(m)) << m;
    EXPECT_NE(m.find("tab: tables of the aircraft 'Other jet' (their mesh companion "
                     "tab/mesh/jet_full_coarse.mesh.yaml has reference span 9 m)"),
              std::string::npos)
        << m;
    t.mesh_companions.clear();
    // Mach 0.45 against 0.3 to 0.4: slightly beyond, a warning; 0.45 to 0.75 (Mach 0.75 at
    // the end) beyond 0.1 of it, an error naming the row.
    auto w = replay::check_tables(t, aircraft(), flight());
    ASSERT_EQ(w.size(), 1u);
    EXPECT_NE(w[0].find("warning: traj.csv: Mach 0.45 at t = 0 s (traj.csv:3) is outside the "
                        "tables' Mach range 0.3 to 0.4 of tab by 0.05"),
              std::string::npos)
        << w[0];
    m = error_of([&] { (void)replay::check_tables(t, aircraft(), flight({}, 0.03)); });
    EXPECT_TRUE(one_line(m)) << m;
    EXPECT_NE(m.find("Mach 0.75 at t = 1 s (traj.csv:13) is outside the tables' Mach range 0.3 "
                     "to 0.4 of tab by 0.35; expected a trajectory within 0.1"),
              std::string::npos)
        << m;
    // A database named for another aircraft, no elevator table, another aircraft's trajectory,
    // alpha beyond the table: warnings.
    const aero::AeroDatabase other = tables({0.3, 0.6}, false, "F-16 tables");
    t.database = &other;
    Lateral big;
    big.elevator = 2 * deg;
    replay::Trajectory tr = flight(big, 0.0, "F-16");
    tr.alpha[3] = 9 * deg;
    w = replay::check_tables(t, aircraft(), tr);
    ASSERT_EQ(w.size(), 4u);
    EXPECT_NE(w[0].find("a trajectory of the aircraft 'F-16'"), std::string::npos) << w[0];
    EXPECT_NE(w[1].find("the database 'F-16 tables' does not name the aircraft 'Test jet'"),
              std::string::npos)
        << w[1];
    EXPECT_NE(w[2].find("alpha 9 deg at t = 0.3 s is outside the tables' range -4 to 8 deg"),
              std::string::npos)
        << w[2];
    EXPECT_NE(w[3].find("the elevator deflects (up to 2 deg at t = 0.5 s) and tab has no elevator "
                        "table"),
              std::string::npos)
        << w[3];
    // A trajectory naming an aircraft file (manta optimise) is not compared: often a copy.
    EXPECT_EQ(
        replay::check_tables(t, aircraft(), flight(big, 0.0, "out/inputs/aircraft.yaml")).size(),
        2u);
    // The aircraft's own model (no --tables): no name check.
    t.file.clear();
    EXPECT_EQ(replay::check_tables(t, aircraft(), flight()).size(), 0u);
}

}  // namespace
