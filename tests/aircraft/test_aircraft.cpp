// Tests of src/aircraft: the Ranger 2000 example reproduces the paper's numbers, invalid
// variations give the right one-line errors, and every mass case makes a flight model that trims.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <string>

#include "manta/aircraft/aircraft.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/flightdyn/atmosphere.hpp"
#include "manta/flightdyn/modes.hpp"
#include "manta/flightdyn/trim.hpp"

namespace {

namespace fs = std::filesystem;
using manta::aircraft::AircraftDefinition;
constexpr double deg = std::numbers::pi / 180.0;

const fs::path ranger_file =
    fs::path(MANTA_SOURCE_DIR) / "examples" / "ranger2000" / "aircraft.yaml";

const AircraftDefinition& ranger() {
    static const AircraftDefinition a = manta::aircraft::load_aircraft(ranger_file);
    return a;
}

const std::string& ranger_text() {
    static const std::string t = manta::core::read_file(ranger_file);
    return t;
}

void expect_parts(const std::string& msg, std::initializer_list<std::string> parts) {
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "not one line: " << msg;
    for (const auto& p : parts)
        EXPECT_NE(msg.find(p), std::string::npos) << "missing '" << p << "' in: " << msg;
}

/// The Ranger text with `from` (which must occur exactly once) replaced by `to`.
std::string variant(const std::string& from, const std::string& to) {
    std::string s = ranger_text();
    const auto p = s.find(from);
    EXPECT_NE(p, std::string::npos) << "not in the example: " << from;
    if (p == std::string::npos) return s;
    EXPECT_EQ(s.find(from, p + 1), std::string::npos) << "occurs more than once: " << from;
    return s.replace(p, from.size(), to);
}

/// ConfigError message of loading `text` as "ranger.yaml".
std::string load_error(const std::string& text, const fs::path& base = ranger_file.parent_path()) {
    try {
        (void)manta::aircraft::parse_aircraft(text, "ranger.yaml", base);
    } catch (const manta::ConfigError& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "expected ConfigError, got: " << e.what();
        return {};
    }
    ADD_FAILURE() << "expected ConfigError, nothing thrown";
    return {};
}

// ------------------------------------------------------------------------------------ the paper's
// numbers

TEST(Ranger, GeneralDimensionsTable1) {
    const auto& a = ranger();
    EXPECT_EQ(a.name, "Ranger 2000");
    EXPECT_EQ(a.file, ranger_file);
    EXPECT_DOUBLE_EQ(a.reference.area, 15.5);
    EXPECT_DOUBLE_EQ(a.reference.span, 10.46);
    EXPECT_DOUBLE_EQ(a.reference.chord, 1.545);
    EXPECT_DOUBLE_EQ(a.geometry.length, 10.39);
    EXPECT_DOUBLE_EQ(a.geometry.height, 3.58);
    const auto& w = a.geometry.surface("wing");
    EXPECT_NEAR(w.planform_area(), 15.5, 1e-3);
    EXPECT_NEAR(w.span(), 10.46, 1e-12);
    EXPECT_NEAR(w.taper_ratio(), 0.519, 1e-3);
    // A straight-tapered wing with Table 1's S, b and taper has a 1.531 m MAC (Table 1: 1.545 m).
    EXPECT_NEAR(w.mean_aerodynamic_chord(), 1.545, 0.01 * 1.545);
    EXPECT_NEAR(w.aspect_ratio(), 10.46 * 10.46 / 15.5, 1e-3);
    EXPECT_NEAR(w.tip_chord(), 1.03, 0.02);  // Fig. 1
    EXPECT_EQ(w.sections.front().airfoil.designation().text, "NACA 64-215");
    EXPECT_EQ(w.sections.back().airfoil.designation().text, "NACA 64-212");
    EXPECT_NEAR(w.dihedral(0), 3.0 * deg, 1e-4);
    // Unswept quarter-chord line.
    const auto qc_root = w.sections.front().leading_edge.x() + 0.25 * w.root_chord();
    const auto qc_tip = w.sections.back().leading_edge.x() + 0.25 * w.tip_chord();
    EXPECT_NEAR(qc_tip, qc_root, 1e-3);
    EXPECT_NEAR(a.geometry.surface("horizontal_tail").span(), 4.22, 1e-12);  // Fig. 1
    EXPECT_TRUE(a.geometry.surface("fin").vertical);
    EXPECT_FALSE(a.geometry.fuselage.empty());
    EXPECT_NEAR(a.geometry.fuselage.stations.back().x, 10.39, 1e-12);
}

TEST(Ranger, TailVolumesAndArmFromFigure1) {
    const auto& a = ranger();
    const auto& w = a.geometry.surface("wing");
    const auto& h = a.geometry.surface("horizontal_tail");
    const auto& f = a.geometry.surface("fin");
    const double x_wing = w.mac_leading_edge().x() + 0.25 * w.mean_aerodynamic_chord();
    const double x_tail = h.mac_leading_edge().x() + 0.25 * h.mean_aerodynamic_chord();
    EXPECT_NEAR(x_tail - x_wing, 3.90, 0.02);  // Fig. 1's 3.90 m read as the tail arm
    const double l_h = x_tail - a.moment_reference_geom.x();
    const double vh = h.planform_area() * l_h / (15.5 * 1.545);
    EXPECT_NEAR(vh, 0.59, 0.01);
    const double l_v =
        f.mac_leading_edge().x() + 0.25 * f.mean_aerodynamic_chord() - a.moment_reference_geom.x();
    EXPECT_NEAR(f.planform_area() * l_v / (15.5 * 10.46), 0.052, 0.002);
    // Top of the T-tail 3.58 m above the ground with the datum 1.48 m up.
    EXPECT_NEAR(h.sections.front().leading_edge.z() + 1.48, 3.58, 1e-12);
}

TEST(Ranger, MassCasesTable2AndFigures10To12) {
    const auto& a = ranger();
    ASSERT_EQ(a.mass_cases.size(), 5u);
    EXPECT_EQ(a.default_mass_case, "mtow");
    struct Expected {
        const char* name;
        double mass, cg_fraction, ixx, iyy, izz;
    };
    const Expected cases[] = {
        {"mtow", 3765.0, 0.2446, 9287.1, 13584.1, 21237.6},
        {"oew", 2586.0, 0.2278, 4600.9, 13462.3, 16474.6},
        {"lazy_eight", 3498.0, 0.24077, 9287.1, 13584.1, 21237.6},
        {"barrel_roll", 3653.0, 0.24297, 9287.1, 13584.1, 21237.6},
        {"immelmann", 3629.0, 0.24265, 9287.1, 13584.1, 21237.6},
    };
    const Eigen::Vector3d mac_le = a.geometry.surface("wing").mac_leading_edge();
    for (const auto& e : cases) {
        const auto& m = a.mass_case(e.name);
        EXPECT_DOUBLE_EQ(m.mass, e.mass) << e.name;
        EXPECT_NEAR(m.cg_geom.x(), mac_le.x() + e.cg_fraction * 1.545, 1e-12) << e.name;
        EXPECT_DOUBLE_EQ(m.cg_geom.y(), 0.0);
        EXPECT_NEAR(m.cg_geom.z(), mac_le.z(), 1e-12);  // vertical CG not given: on the MAC
        EXPECT_DOUBLE_EQ(m.inertia(0, 0), e.ixx) << e.name;
        EXPECT_DOUBLE_EQ(m.inertia(1, 1), e.iyy) << e.name;
        EXPECT_DOUBLE_EQ(m.inertia(2, 2), e.izz) << e.name;
        EXPECT_DOUBLE_EQ(m.inertia(0, 2), 0.0) << e.name;
    }
    // CG of the manoeuvre cases: 24.077 % MAC lies at x = 4.897 m from the nose.
    EXPECT_NEAR(a.mass_case("lazy_eight").cg_geom.x(), 4.897, 1e-3);
    // Moment reference at 25 % MAC, aft of every CG.
    EXPECT_NEAR(a.moment_reference_geom.x(), mac_le.x() + 0.25 * 1.545, 1e-12);
    for (const auto& m : a.mass_cases)
        EXPECT_LT(m.cg_geom.x(), a.moment_reference_geom.x()) << m.name;
}

TEST(Ranger, EngineLimitsEnvelope) {
    const auto& a = ranger();
    EXPECT_EQ(a.engine.type, manta::flightdyn::EngineModel::Type::lapse);
    EXPECT_DOUBLE_EQ(a.engine.static_thrust_sl, 14190.0);
    EXPECT_FALSE(a.engine.has_position);
    EXPECT_TRUE(a.engine_angular_momentum.isZero());
    EXPECT_NEAR(a.limits.elevator[0], -25 * deg, 1e-15);
    EXPECT_NEAR(a.limits.elevator[1], 15 * deg, 1e-15);
    EXPECT_NEAR(a.limits.aileron[0], -25 * deg, 1e-15);
    EXPECT_NEAR(a.limits.rudder[1], 17.5 * deg, 1e-15);
    EXPECT_DOUBLE_EQ(a.limits.throttle[1], 1.0);
    EXPECT_DOUBLE_EQ(a.envelope.max_mach, 0.70);
    EXPECT_DOUBLE_EQ(a.envelope.dive_mach, 0.75);
    EXPECT_DOUBLE_EQ(a.envelope.ceiling, 9449.0);
    EXPECT_NEAR(a.envelope.alpha[0], -7 * deg, 1e-15);
    EXPECT_NEAR(a.envelope.alpha[1], 36 * deg, 1e-15);
    EXPECT_NEAR(a.envelope.beta[1], 20 * deg, 1e-15);
    EXPECT_DOUBLE_EQ(a.environment.gravity, 9.80665);
}

TEST(Ranger, ModeLimitsAreTheControlLimits) {
    // The limits a motion file's modes are checked against (vlm-unsteady): Table 3 of the paper.
    const auto l = ranger().mode_limits();
    ASSERT_EQ(l.size(), 3U);
    EXPECT_EQ(l[0].name, "elevator");
    EXPECT_NEAR(l[0].lower, -25 * deg, 1e-15);
    EXPECT_NEAR(l[0].upper, 15 * deg, 1e-15);
    EXPECT_EQ(l[1].name, "aileron");
    EXPECT_NEAR(l[1].lower, -25 * deg, 1e-15);
    EXPECT_NEAR(l[1].upper, 15 * deg, 1e-15);
    EXPECT_EQ(l[2].name, "rudder");
    EXPECT_NEAR(l[2].lower, -17.5 * deg, 1e-15);
    EXPECT_NEAR(l[2].upper, 17.5 * deg, 1e-15);
}

TEST(Ranger, ControlSurfacesFollowThePaperSigns) {
    const auto& g = ranger().geometry;
    const auto* ail = g.find_control_surface("aileron");
    ASSERT_NE(ail, nullptr);
    EXPECT_EQ(ail->control, manta::geometry::Control::aileron);
    // Positive aileron: left trailing edge down (+), right trailing edge up (-).
    EXPECT_GT(ail->deflection(0.1, /*mirrored (left)=*/true), 0.0);
    EXPECT_LT(ail->deflection(0.1, false), 0.0);
    EXPECT_DOUBLE_EQ(ail->span_fraction[0], 0.55);
    EXPECT_DOUBLE_EQ(ail->span_fraction[1], 0.95);
    const auto* ele = g.find_control_surface("elevator");
    ASSERT_NE(ele, nullptr);
    EXPECT_DOUBLE_EQ(ele->deflection(0.1, true), ele->deflection(0.1, false));
    EXPECT_NEAR(1 - ele->hinge_chord_fraction, 0.32, 1e-12);
    const auto* rud = g.find_control_surface("rudder");
    ASSERT_NE(rud, nullptr);
    EXPECT_EQ(rud->surface, "fin");
    ASSERT_TRUE(rud->limits.has_value());
    EXPECT_NEAR((*rud->limits)[0], -17.5 * deg, 1e-15);
    EXPECT_GT(g.control_surface_area(*ail), 0.5);
}

TEST(Ranger, AeroModelIsLabelledAndHasTheRightSigns) {
    const auto& a = ranger();
    ASSERT_TRUE(a.aero);
    EXPECT_NE(a.aero_label.find("typical of a jet trainer, not Ranger data"), std::string::npos)
        << a.aero_label;
    EXPECT_EQ(a.aero->info().source, "linear-derivatives");
    using Q = manta::aero::AeroQuery<double>;
    const auto eval = [&](const Q& q) {
        return a.aero->evaluate(q, manta::aero::Interpolation::multilinear);
    };
    Q base;
    base.mach = 0.3;
    base.alpha = 2 * deg;
    const auto c0 = eval(base);
    Q q = base;
    q.aileron = 5 * deg;
    EXPECT_GT(eval(q).Cl - c0.Cl, 0.0) << "positive aileron must roll the right wing down";
    EXPECT_LT(eval(q).Cn - c0.Cn, 0.0) << "adverse yaw";
    q = base;
    q.rudder = 5 * deg;
    EXPECT_LT(eval(q).Cn - c0.Cn, 0.0) << "rudder trailing edge left yaws the nose left";
    EXPECT_GT(eval(q).CY - c0.CY, 0.0) << "and pushes the fin to the right";
    q = base;
    q.elevator = 5 * deg;
    EXPECT_LT(eval(q).Cm - c0.Cm, 0.0) << "elevator trailing edge down pitches nose down";
    q = base;
    q.alpha = 4 * deg;
    EXPECT_LT(eval(q).Cm - c0.Cm, 0.0) << "statically stable";
    q = base;
    q.beta = 5 * deg;
    EXPECT_GT(eval(q).Cn - c0.Cn, 0.0) << "weathercock stable";
    EXPECT_LT(eval(q).Cl - c0.Cl, 0.0) << "dihedral effect";
    // CL_alpha at the reference Mach 0.3: lift is -CZ at small angles.
    Q a0 = base, a1 = base;
    a0.alpha = 0.0;
    a1.alpha = 2 * deg;
    const double cl0 = -eval(a0).CZ;
    const double cl1 = eval(a1).CX * std::sin(2 * deg) - eval(a1).CZ * std::cos(2 * deg);
    EXPECT_NEAR(cl0, 0.15, 1e-9);
    EXPECT_NEAR((cl1 - cl0) / (2 * deg), 5.0, 1e-6);
}

/// Level-flight trim by hand from the tables: CL = W / (q S), Cm = 0 about the CG; returns
/// (alpha, elevator, throttle) at V, altitude h for a mass case.
std::array<double, 3> hand_trim(const AircraftDefinition& a, const std::string& mass_case, double V,
                                double h) {
    const auto atm = manta::flightdyn::us1976(h);
    const double qbar = 0.5 * atm.density * V * V;
    const auto& m = a.mass_case(mass_case);
    const double S = a.reference.area, c = a.reference.chord;
    const double cl_needed = m.mass * a.environment.gravity / (qbar * S);
    const double dx = a.moment_reference_geom.x() - m.cg_geom.x();  // MRP aft of the CG [m]
    manta::aero::AeroQuery<double> q;
    q.mach = V / atm.speed_of_sound;
    const auto coeffs = [&](double alpha, double de) {
        q.alpha = alpha;
        q.elevator = de;
        const auto b = a.aero->evaluate(q, manta::aero::Interpolation::multilinear);
        const double cl = b.CX * std::sin(alpha) - b.CZ * std::cos(alpha);
        const double cd = -b.CX * std::cos(alpha) - b.CZ * std::sin(alpha);
        // Normal force -CZ at the MRP, dx aft of the CG, pitches the nose down.
        const double cm = b.Cm + b.CZ * dx / c;
        return std::array<double, 3>{cl, cm, cd};
    };
    double alpha = 0.0, de = 0.0;
    for (int it = 0; it < 30; ++it) {
        const auto f = coeffs(alpha, de);
        const double e = 1e-6;
        const auto fa = coeffs(alpha + e, de), fd = coeffs(alpha, de + e);
        const double j11 = (fa[0] - f[0]) / e, j12 = (fd[0] - f[0]) / e, j21 = (fa[1] - f[1]) / e,
                     j22 = (fd[1] - f[1]) / e;
        const double r1 = f[0] - cl_needed, r2 = f[1], det = j11 * j22 - j12 * j21;
        alpha -= (j22 * r1 - j12 * r2) / det;
        de -= (-j21 * r1 + j11 * r2) / det;
    }
    const double drag = coeffs(alpha, de)[2] * qbar * S;
    const double thrust_full =
        a.engine.thrust_at(h, q.mach, 1.0, atm.density / manta::flightdyn::us1976(0.0).density);
    return {alpha, de, drag / thrust_full};
}

TEST(Ranger, TrimsInLevelFlightAt150MetresPerSecondAnd3000Metres) {
    const auto& a = ranger();
    for (const auto& m : a.mass_cases) {
        const auto t = hand_trim(a, m.name, 150.0, 3000.0);
        EXPECT_GT(t[0], -1 * deg) << m.name;
        EXPECT_LT(t[0], 3 * deg) << m.name;
        EXPECT_LT(std::abs(t[1]), 3 * deg) << m.name << " elevator " << t[1] / deg;
        EXPECT_GT(t[2], 0.1) << m.name;
        EXPECT_LT(t[2], 0.6) << m.name << " throttle " << t[2];
    }
}

TEST(Ranger, FlightDynamicsTrimAgreesForEveryMassCase) {
    const auto& a = ranger();
    for (const auto& m : a.mass_cases) {
        const auto model = a.flight_model(m.name);
        manta::flightdyn::TrimTarget target;
        target.airspeed = 150.0;
        target.altitude = 3000.0;
        const auto r = manta::flightdyn::trim(model, target);
        const auto hand = hand_trim(a, m.name, 150.0, 3000.0);
        EXPECT_NEAR(r.state[manta::flightdyn::euler::alpha], hand[0], 0.05 * deg) << m.name;
        EXPECT_NEAR(r.controls.elevator, hand[1], 0.05 * deg) << m.name;
        EXPECT_NEAR(r.controls.throttle, hand[2], 0.01) << m.name;
        EXPECT_LT(r.controls.throttle, 1.0);
    }
}

TEST(Ranger, EveryModeIsStableAt150MetresPerSecondAnd3000Metres) {
    // A sanity check of the typical-trainer derivative set: short period, phugoid, Dutch roll,
    // roll and spiral all decay, with a short period and Dutch roll of the usual frequencies.
    const auto model = ranger().flight_model("lazy_eight");
    manta::flightdyn::TrimTarget target;
    target.airspeed = 150.0;
    target.altitude = 3000.0;
    const auto r = manta::flightdyn::trim(model, target);
    const auto modes =
        manta::flightdyn::analyse_modes(manta::flightdyn::linearise(model, r.state, r.controls));
    for (const auto& m : modes.longitudinal) EXPECT_TRUE(m.is_stable()) << m.name;
    for (const auto& m : modes.lateral) EXPECT_TRUE(m.is_stable()) << m.name;
    ASSERT_FALSE(modes.longitudinal.empty());
    EXPECT_EQ(modes.longitudinal.front().name, "short period");
    EXPECT_GT(modes.longitudinal.front().natural_frequency, 2.0);
    EXPECT_LT(modes.longitudinal.front().natural_frequency, 8.0);
    EXPECT_GT(modes.longitudinal.front().damping_ratio, 0.3);
    ASSERT_FALSE(modes.lateral.empty());
    EXPECT_EQ(modes.lateral.front().name, "Dutch roll");
    EXPECT_GT(modes.lateral.front().damping_ratio, 0.08);
}

TEST(Ranger, FlightModelOfEachMassCase) {
    const auto& a = ranger();
    for (const auto& m : a.mass_cases) {
        const auto f = a.flight_model(m.name);
        EXPECT_EQ(f.name, "Ranger 2000");
        EXPECT_EQ(f.mass.name, m.name);
        EXPECT_DOUBLE_EQ(f.mass.mass, m.mass);
        EXPECT_EQ(f.mass.cg_geom, m.cg_geom);
        EXPECT_EQ(f.mass.inertia, m.inertia);
        EXPECT_EQ(f.aero, a.aero);
        EXPECT_DOUBLE_EQ(f.reference.area, 15.5);
        EXPECT_EQ(f.moment_reference_geom, a.moment_reference_geom);
        EXPECT_DOUBLE_EQ(f.engine.static_thrust_sl, 14190.0);
        EXPECT_DOUBLE_EQ(f.limits.rudder[1], a.limits.rudder[1]);
    }
    EXPECT_EQ(a.flight_model().mass.name, "mtow");
    try {
        (void)a.flight_model("imelman");
        FAIL() << "no error";
    } catch (const manta::InputError& e) {
        expect_parts(e.what(),
                     {"Ranger 2000", "no mass case 'imelman'", "did you mean 'immelmann'?",
                      "mtow, oew, lazy_eight, barrel_roll, immelmann"});
    }
}

TEST(Ranger, InMemoryTextGivesTheSameAircraft) {
    const auto a = manta::aircraft::parse_aircraft(ranger_text(), "embedded");
    EXPECT_EQ(a.name, ranger().name);
    EXPECT_EQ(a.moment_reference_geom, ranger().moment_reference_geom);
    EXPECT_EQ(a.mass_cases.size(), ranger().mass_cases.size());
    EXPECT_EQ(a.aero->tables().size(), ranger().aero->tables().size());
}

// ------------------------------------------------------------------------------------ variants

TEST(AircraftFormatDoc, MinimalExampleLoads) {
    // The minimal example of docs/aircraft-format.md is kept valid by this test.
    const std::string doc =
        manta::core::read_file(fs::path(MANTA_SOURCE_DIR) / "docs" / "aircraft-format.md");
    const auto section = doc.find("## Minimal example");
    ASSERT_NE(section, std::string::npos);
    const auto begin = doc.find("```yaml\n", section);
    ASSERT_NE(begin, std::string::npos);
    const auto end = doc.find("```", begin + 8);
    const std::string yaml = doc.substr(begin + 8, end - begin - 8);
    const auto a = manta::aircraft::parse_aircraft(yaml, "docs/aircraft-format.md");
    EXPECT_EQ(a.name, "Minimal trainer");
    EXPECT_NEAR(a.geometry.surface("wing").planform_area(), 12.0, 1e-12);
    EXPECT_EQ(a.geometry.find_control_surface("elevator")->control,
              manta::geometry::Control::elevator);
    manta::flightdyn::TrimTarget target;
    target.airspeed = 70.0;
    target.altitude = 1000.0;
    const auto r = manta::flightdyn::trim(a.flight_model(), target);
    EXPECT_LT(r.controls.throttle, 1.0);
}

TEST(AircraftVariants, ExplicitCoordinatesAndOptionalSections) {
    std::string t =
        variant("  moment_reference_mac_fraction: 0.25\n", "  moment_reference: [4.9, 0.0, 0.1]\n");
    const auto p = t.find("      cg_mac_fraction: 0.2446");
    t.replace(p, std::string("      cg_mac_fraction: 0.2446").size(),
              "      cg: [4.88, 0.0, 0.1]\n      ixz: 500");
    for (const char* section : {"controls:", "environment:", "envelope:"}) {
        const auto s = t.find(std::string("\n") + section);
        const auto e = t.find("\n\n", s + 1);
        t.erase(s + 1, e - s);
    }
    const auto a = manta::aircraft::parse_aircraft(t, "variant.yaml", ranger_file.parent_path());
    EXPECT_EQ(a.moment_reference_geom, Eigen::Vector3d(4.9, 0.0, 0.1));
    EXPECT_EQ(a.mass_case("mtow").cg_geom, Eigen::Vector3d(4.88, 0.0, 0.1));
    EXPECT_DOUBLE_EQ(a.mass_case("mtow").inertia(0, 2), -500.0);  // I = [[Ixx,.,-Ixz],...]
    EXPECT_DOUBLE_EQ(a.mass_case("mtow").inertia(2, 0), -500.0);
    const manta::flightdyn::ControlLimits defaults;
    EXPECT_EQ(a.limits.elevator, defaults.elevator);
    EXPECT_DOUBLE_EQ(a.environment.gravity, 9.80665);
    EXPECT_DOUBLE_EQ(a.envelope.max_mach, 0.0);
}

TEST(AircraftVariants, TableEngine) {
    const std::string engine = R"(engine:
  type: table
  altitude: [0, 5000]
  mach: [0, 0.8]
  throttle: [0, 1]
  thrust:
    - [0, 14190]
    - [0, 11000]
    - [0, 8000]
    - [0, 6500]
  position: [6.0, 0.0, 0.1]
  angular_momentum: [30, 0, 0]
)";
    const auto s = ranger_text().find("engine:\n");
    const auto e = ranger_text().find("\n\n", s);
    std::string t = ranger_text();
    t.replace(s, e - s + 1, engine);
    const auto a = manta::aircraft::parse_aircraft(t, "table.yaml", ranger_file.parent_path());
    EXPECT_EQ(a.engine.type, manta::flightdyn::EngineModel::Type::table);
    EXPECT_EQ(a.engine.thrust.size(), 8u);
    EXPECT_DOUBLE_EQ(a.engine.thrust[1], 14190.0);
    EXPECT_TRUE(a.engine.has_position);
    EXPECT_DOUBLE_EQ(a.engine_angular_momentum.x(), 30.0);
    EXPECT_NEAR(a.engine.thrust_at(0.0, 0.0, 1.0, 1.0), 14190.0, 1e-9);

    std::string bad = t;
    bad.replace(bad.find("    - [0, 6500]\n"), std::string("    - [0, 6500]\n").size(), "");
    expect_parts(load_error(bad), {"ranger.yaml:", "engine.thrust", "has 3 rows",
                                   "4 rows (one per altitude and Mach pair"});
    bad = t;
    bad.replace(bad.find("[0, 8000]"), 9, "[0, 8000, 1]");
    expect_parts(load_error(bad), {"engine.thrust[2]", "has 3 entries", "a list of 2 numbers"});
    bad = t;
    bad.replace(bad.find("mach: [0, 0.8]"), 14, "mach: [0.8, 0]");
    expect_parts(load_error(bad), {"engine.mach[1]", "value '0'", "strictly increasing"});
    bad = t;
    bad.replace(bad.find("  type: table\n"), 14, "  type: table\n  static_thrust: 100\n");
    expect_parts(load_error(bad), {"engine.static_thrust", "belongs to engine type 'lapse'"});
}

TEST(AircraftVariants, AeroDatabaseFile) {
    const fs::path dir =
        fs::temp_directory_path() / ("manta_aircraft_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    ranger().aero->write(dir / "ranger_aero.yaml");
    const auto s = ranger_text().find("\naero:\n");
    std::string t = ranger_text().substr(0, s + 1) + "aero:\n  database: ranger_aero.yaml\n";
    const auto a = manta::aircraft::parse_aircraft(t, "db.yaml", dir);
    ASSERT_TRUE(a.aero);
    EXPECT_EQ(a.aero->to_text(), ranger().aero->to_text());
    EXPECT_EQ(a.aero_label, ranger().aero_label);  // the database's description
    expect_parts(
        load_error(ranger_text().substr(0, s + 1) + "aero:\n  database: missing.yaml\n", dir),
        {"ranger.yaml:", "key 'aero.database'", "missing.yaml", "could not be read"});
    fs::remove_all(dir);
}

struct BadCase {
    const char* from;
    const char* to;
    std::vector<std::string> parts;
};

TEST(AircraftErrors, OneLineMessagesNameTheProblem) {
    const std::vector<BadCase> cases{
        {"schema_version: 1",
         "schema_version: 2",
         {"ranger.yaml:8", "key 'schema_version'", "value '2'", "is not a supported schema version",
          "expected 1"}},
        {"reference:\n", "refrence:\n", {"unknown key 'refrence'", "did you mean 'reference'?"}},
        {"  area: 15.5 ",
         "  area: 25.5 ",
         {"key 'reference.area'", "value '25.5'", "differs by 65 % from the planform area 15.5 m^2",
          "within 20 %"}},
        {"  span: 10.46 ",
         "  span: 20.0 ",
         {"key 'reference.span'", "differs by 91 % from the span 10.46 m"}},
        {"  area: 15.5 ",
         "  area: 15.5 m2 ",
         {"key 'reference.area'", "value '15.5 m2'", "carries a unit"}},
        {"  area: 15.5 ",
         "  aera: 15.5 ",
         {"missing required key 'reference.area'", "found 'aera'"}},
        {"  wing: wing ",
         "  wing: wnig ",
         {"key 'reference.wing'", "is not a lifting surface", "did you mean 'wing'?"}},
        {"  moment_reference_mac_fraction: 0.25\n",
         "",
         {"missing required key 'reference.moment_reference'", "moment_reference_mac_fraction"}},
        {"  moment_reference_mac_fraction: 0.25\n",
         "  moment_reference_mac_fraction: 0.25\n  moment_reference: [4.9, 0, 0]\n",
         {"reference.moment_reference_mac_fraction", "duplicates 'moment_reference'", "not both"}},
        {"  moment_reference_mac_fraction: 0.25\n",
         "  moment_reference: [14.9, 0, 0]\n",
         {"key 'reference.moment_reference'", "x = 14.9 m, outside the aircraft",
          "0 <= x <= 10.39 m"}},
        {"  moment_reference_mac_fraction: 0.25\n",
         "  moment_reference: [4.9, 0]\n",
         {"key 'reference.moment_reference'", "has 2 entries", "a list of 3 numbers"}},
        {"      mass: 3765.0",
         "      mass: -3765.0",
         {"key 'mass.cases[0].mass'", "value '-3765.0'", "is out of range", "(0, 1e+07] [kg]"}},
        {"      mass: 3765.0", "      mass: 3765 kg", {"mass.cases[0].mass", "carries a unit"}},
        {"      cg_mac_fraction: 0.2446 ",
         "      cg_mac_fraction: 4.0 ",
         {"mass.cases[0].cg_mac_fraction", "value '4.0'", "a number in [-0.5, 1.5]"}},
        {"      cg_mac_fraction: 0.2446 ",
         "      cg: [11.0, 0, 0] ",
         {"key 'mass.cases[0].cg'", "centre of gravity at x = 11 m, outside the aircraft"}},
        {"      izz: 16474.6",
         "      izz: 26474.6",
         {"key 'mass.cases[1].izz'", "value '26474.6'", "exceeds the sum 18063.2",
          "triangle inequalities"}},
        {"      izz: 16474.6",
         "      izz: 16474.6\n      ixz: 9000",
         {"key 'mass.cases[1].ixz'", "not positive definite", "principal moment is positive"}},
        {"      ixx: 4600.9",
         "      ixx: 0",
         {"mass.cases[1].ixx", "value '0'", "(0, 1e+10] [kg m^2]"}},
        {"  default_case: mtow",
         "  default_case: mtwo",
         {"key 'mass.default_case'", "value 'mtwo'", "is not a mass case", "did you mean 'mtow'?"}},
        {"    - name: oew",
         "    - name: mtow",
         {"key 'mass.cases[1].name'", "value 'mtow'", "is used by an earlier mass case"}},
        {"  type: lapse",
         "  type: turbofan",
         {"key 'engine.type'", "value 'turbofan'", "one of lapse, table"}},
        {"  static_thrust: 14190.0 ",
         "  static_thrust_lbf: 3190.0 ",
         {"missing required key 'engine.static_thrust'"}},
        {"  mach_a1: -0.3",
         "  mach_a1: -2.0",
         {"key 'engine.mach_a1'", "gives no thrust at M = 0.55"}},
        {"  thrust_angle_deg: 0.0",
         "  thrust_angle_deg: 0.0\n  altitude: [0, 1000]",
         {"key 'engine.altitude'", "belongs to engine type 'table'"}},
        {"  thrust_angle_deg: 0.0",
         "  thrust_angle: 10",
         {"key 'engine.thrust_angle'", "looks like degrees", "thrust_angle_deg"}},
        {"  elevator_deg: [-25.0, 15.0]",
         "  elevator_deg: [15.0, -25.0]",
         {"key 'controls.elevator_deg'", "lower bound above its upper bound"}},
        {"  rudder_deg: [-17.5, 17.5]",
         "  rudder_deg: [5, 5]",
         {"key 'controls.rudder_deg'", "equal lower and upper bounds"}},
        {"  aileron_deg: [-25.0, 15.0]",
         "  aileron: [-25.0, 15.0]",
         {"key 'controls.aileron'", "in radians but looks like degrees", "aileron_deg"}},
        {"  throttle: [0.0, 1.0]",
         "  throttle: [1.0, 0.0]",
         {"key 'controls.throttle'", "lower bound not below"}},
        {"  throttle: [0.0, 1.0]",
         "  throttle: [0.0, 1.5]",
         {"controls.throttle[1]", "a number in [0, 1]"}},
        {"  gravity: 9.80665 ", "  gravity: 0 ", {"environment.gravity", "a number > 0 [m/s^2]"}},
        {"  dive_mach: 0.75",
         "  dive_mach: 0.65",
         {"key 'envelope.dive_mach'", "is below max_mach = 0.7"}},
        {"  ceiling: 9449.0",
         "  ceiling_ft: 31000",
         {"missing required key 'envelope.ceiling'", "found 'ceiling_ft'",
          "MANTA reads 'ceiling' in SI units"}},
        {"  linear_derivatives:\n",
         "  linear_derivatives:\n    CL_beta: 0.1\n",
         {"key 'aero.linear_derivatives.CL_beta'", "unknown key 'CL_beta'", "did you mean"}},
        {"    CL_alpha: 5.0 ",
         "    CL_alfa: 5.0 ",
         {"missing required key 'aero.linear_derivatives.CL_alpha'", "found 'CL_alfa'"}},
        {"    CD_0: 0.022", "    CD_0: -0.022", {"aero.linear_derivatives.CD_0", "is negative"}},
        {"  linear_derivatives:\n",
         "  database: x.yaml\n  linear_derivatives:\n",
         {"aero.linear_derivatives", "duplicates 'database'", "not both"}},
        {"    alpha_deg: [-6, -4,",
         "    alpha_deg: [-6, -6,",
         {"key 'aero.grids.alpha_deg[1]'", "value '-6'", "does not exceed the previous entry",
          "strictly increasing"}},
        {"    alpha_deg: [-6, -4, -2, 0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20]",
         "    alpha: [-6, -4, -2, 0, 2, 4, 6, 8, 10]",
         {"key 'aero.grids.alpha[7]'", "value '8'", "in radians but looks like degrees",
          "alpha_deg"}},
        {"    alpha_deg: [-6, -4, -2, 0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20]",
         "    alpha_deg: [5]",
         {"key 'aero.grids.alpha_deg'", "has 1 entry", "at least 2 breakpoints"}},
        {"    mach: [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7]",
         "    mach: [0.1, 0.5, 1.0]",
         {"key 'aero.grids.mach'", "reaches M = 1 with prandtl_glauert: true", "below 0.95"}},
        {"    rudder_deg: [",
         "    ruder_deg: [",
         {"missing required key 'aero.grids.rudder'", "found 'ruder_deg'"}},
        {"      airfoil: NACA 64-212",
         "      airfoil: NACA 64-2122",
         {"ranger.yaml:", "geometry.lifting_surfaces[0].sections[1].airfoil",
          "is not a valid NACA designation"}},
        {"      span_fraction: [0.55, 0.95]",
         "      span_fraction: [0.95, 0.55]",
         {"geometry.control_surfaces[1].span_fraction", "inboard < outboard"}},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.to);
        const std::string msg = load_error(variant(c.from, c.to));
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        for (const auto& p : c.parts)
            EXPECT_NE(msg.find(p), std::string::npos) << "missing '" << p << "' in: " << msg;
    }
}

TEST(AircraftErrors, WingNeededForMacFractions) {
    // Without a surface called 'wing' the %MAC keys cannot be placed.
    std::string t = variant("    - name: wing\n", "    - name: main_wing\n");
    t = t.replace(t.find("  wing: wing "), 13, "             ");
    t = t.replace(t.find("      surface: wing\n"), 20, "      surface: main_wing\n");
    expect_parts(load_error(t), {"key 'reference.moment_reference_mac_fraction'",
                                 "needs a lifting surface named 'wing'"});
}

TEST(AircraftErrors, FileProblems) {
    EXPECT_THROW((void)manta::aircraft::load_aircraft("/nonexistent/aircraft.yaml"),
                 manta::IoError);
    expect_parts(load_error("name: [\n"), {"ranger.yaml:", "YAML syntax error"});
    expect_parts(load_error("- a\n"), {"ranger.yaml:1", "is not a mapping"});
    expect_parts(load_error("schema_version: 1\n"), {"missing required key 'name'"});
}

}  // namespace
