// Implausible values in the motion file and the aero database (issue 16, defects 5 and 12): each
// was read and used silently (theta 1e19 rad gave CL 2e36 with exit status 0; an elevator of 5
// rad, degrees typed as radians, passed; a coefficient of 1e19 was tabulated). Each is now refused
// with a one-line message naming the value and the plausible range.
#include <gtest/gtest.h>

#include <functional>
#include <numbers>
#include <string>

#include "manta/aero/database.hpp"
#include "manta/aero/motion.hpp"
#include "manta/core/error.hpp"

namespace {

using manta::aero::Motion;
using manta::aero::parse_motion;

std::string input_error(const std::function<void()>& f) {
    try {
        f();
    } catch (const manta::Error& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected an error";
    return {};
}

void expect_parts(const std::string& msg, std::initializer_list<std::string> parts) {
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << p << " | " << msg;
}

const std::string header =
    "t,x_ref,y_ref,z_ref,phi,theta,psi,mode_elevator,mode_aileron,mode_rudder\n";

std::string motion_with(const std::string& second_row) {
    return header + "0,0,0,0,0,0,0,0,0,0\n" + second_row + "\n";
}

TEST(MotionRanges, HugePitchAngleRefused) {
    expect_parts(
        input_error([] { (void)parse_motion(motion_with("1,0,0,0,0,1e19,0,0,0,0"), "m.csv"); }),
        {"m.csv:3", "column 'theta'", "1e+19 rad", "plausible range [-100, 100] rad"});
}

TEST(MotionRanges, ElevatorInDegreesSuspected) {
    const std::string msg =
        input_error([] { (void)parse_motion(motion_with("1,0,0,0,0,0,0,5,0,0"), "m.csv"); });
    expect_parts(msg, {"m.csv:3", "mode_elevator", "value 5 rad", "control deflection",
                       "degrees typed as radians", "286.5 deg"});
}

TEST(MotionRanges, HugePositionAndTimeRefused) {
    expect_parts(
        input_error([] { (void)parse_motion(motion_with("1,2e9,0,0,0,0,0,0,0,0"), "m.csv"); }),
        {"m.csv:3", "column 'x_ref'", "plausible range", "m"});
    expect_parts(
        input_error([] { (void)parse_motion(motion_with("1e12,0,0,0,0,0,0,0,0,0"), "m.csv"); }),
        {"m.csv:3", "column 't'", "plausible range"});
}

TEST(MotionRanges, UnwrappedHeadingOfSeveralTurnsAccepted) {
    // A sustained turn: psi passes 2 pi (three turns); deflections of 0.4 rad.
    const Motion m = parse_motion(motion_with("10,0,0,0,0.5,0.1,18.85,0.4,-0.4,0.2"), "m.csv");
    EXPECT_DOUBLE_EQ(m.angles[2][1], 18.85);
}

TEST(MotionRanges, ProgrammaticMotionsAreCheckedToo) {
    Motion m = parse_motion(motion_with("1,0,0,0,0,0,0,0,0,0"), "m.csv");
    m.angles[0][1] = 1e19;
    expect_parts(input_error([&] { m.validate("built"); }), {"built: row 2", "column 'phi'"});
}

TEST(MotionRanges, AircraftLimitsChecked) {
    // Ranger 2000 limits (the paper's Table 3): elevator -25..15 deg.
    const double d = std::numbers::pi / 180.0;
    const std::vector<manta::aero::ModeLimit> limits{{"elevator", -25 * d, 15 * d},
                                                     {"rudder", -17.5 * d, 17.5 * d}};
    const Motion ok = parse_motion(motion_with("1,0,0,0,0,0,0,0.2,0,-0.3"), "m.csv");
    EXPECT_NO_THROW(manta::aero::check_mode_limits(ok, limits, "m.csv"));
    const Motion over = parse_motion(motion_with("1,0,0,0,0,0,0,0.4,0,0"), "m.csv");
    expect_parts(input_error([&] { manta::aero::check_mode_limits(over, limits, "m.csv"); }),
                 {"m.csv", "mode 'elevator' = 0.4 rad at t = 1 s", "aircraft's limits",
                  "[-25.0, 15.0] deg"});
    const Motion slip = parse_motion(motion_with("1,0,0,0,0,0,0,1.5,0,0"), "m.csv");
    expect_parts(input_error([&] { manta::aero::check_mode_limits(slip, limits, "m.csv"); }),
                 {"mode 'elevator' = 1.5 rad", "degrees typed as radians"});
}

TEST(MotionRanges, NonUtf8Refused) {
    expect_parts(input_error([] {
                     (void)parse_motion("# caf\xE9\n" + motion_with("1,0,0,0,0,0,0,0,0,0"),
                                        "m.csv");
                 }),
                 {"m.csv:1", "not valid UTF-8", "0xE9", "byte offset 5"});
}

const std::string database =
    "manta_aero_database: 1\n"
    "info: {name: small, source: hand, description: test}\n"
    "force_axes: wind\n"
    "tables:\n"
    "  - name: static\n"
    "    kind: static\n"
    "    axes:\n"
    "      - {name: alpha, AXIS}\n"
    "    columns: [CL, CD, Cm]\n"
    "    data:\n"
    "      - [-0.1, 0.02, 0.01]\n"
    "      - [ROW]\n";

std::string db(const std::string& axis, const std::string& row) {
    std::string s = database;
    s.replace(s.find("AXIS"), 4, axis);
    s.replace(s.find("ROW"), 3, row);
    return s;
}

TEST(DatabaseRanges, PlausibleDatabaseRead) {
    EXPECT_NO_THROW((void)manta::aero::AeroDatabase::from_text(
        db("values_deg: [-4, 4]", "0.5, 0.03, -0.01"), "db.yaml"));
}

TEST(DatabaseRanges, HugeCoefficientRefused) {
    expect_parts(input_error([] {
                     (void)manta::aero::AeroDatabase::from_text(
                         db("values_deg: [-4, 4]", "1e19, 0.03, -0.01"), "db.yaml");
                 }),
                 {"db.yaml:12", "1e19", "column 'CL'", "implausible", "[-100, 100]"});
}

TEST(DatabaseRanges, HypersonicMachBreakpointRefused) {
    std::string text = db("values_deg: [-4, 4]", "0.5, 0.03, -0.01");
    text.replace(text.find("      - {name: alpha"), 0,
                 "      - {name: mach, values: [0.2, 1e6]}\n");
    expect_parts(input_error([&] { (void)manta::aero::AeroDatabase::from_text(text, "db.yaml"); }),
                 {"db.yaml:8", "'1e6'", "Mach number in [0, 10]"});
}

}  // namespace
