// Implausible manoeuvre targets (issue 16, defect 12): a final heading change of 488 deg was
// wrapped silently to 128 deg. Angles beyond one turn, speeds beyond 1000 m/s and altitudes
// beyond 30 km are refused, naming the value and the range.
#include <gtest/gtest.h>

#include <numbers>
#include <string>

#include "manta/core/error.hpp"
#include "manta/manoeuvres/manoeuvre.hpp"

namespace {

using manta::manoeuvres::parse_manoeuvre;

std::string error_of(const std::string& final_section) {
    try {
        (void)parse_manoeuvre(
            "name: x\nentry: {speed: 100, altitude: 1000}\nfinal: " + final_section + "\n",
            "m.yaml");
    } catch (const manta::Error& e) {
        return e.what();
    }
    ADD_FAILURE() << "accepted: " << final_section;
    return {};
}

void expect_parts(const std::string& msg, std::initializer_list<std::string> parts) {
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << p << " | " << msg;
}

TEST(ManoeuvreRanges, HeadingChangeBeyondOneTurnRefusedNotWrapped) {
    expect_parts(
        error_of("{heading_change_deg: 488}"),
        {"m.yaml:3", "final.heading_change_deg", "'488'", "out of range", "[-360, 360]", "deg"});
    expect_parts(error_of("{heading_change: [0, 12]}"),
                 {"m.yaml:3", "final.heading_change", "'12'", "[-6.28319, 6.28319]"});
    expect_parts(error_of("{bank_deg: {entry_offset: [-720, 0]}}"),
                 {"final.bank_deg.entry_offset", "'-720'"});
}

TEST(ManoeuvreRanges, SpeedAndAltitudeBounded) {
    expect_parts(error_of("{speed: 3e8}"), {"final.speed", "'3e8'", "[-1000, 1000]", "m/s"});
    expect_parts(error_of("{altitude: [0, 1e7]}"), {"final.altitude", "'1e7'", "30000"});
}

TEST(ManoeuvreRanges, PlausibleTargetsRead) {
    const auto s = parse_manoeuvre(
        "name: x\nentry: {speed: 100, altitude: 1000}\nfinal: {heading_change_deg: 360, "
        "roll_angle_deg: -720, speed: entry, north_change: 0}\n",
        "m.yaml");
    EXPECT_NEAR(s.heading_change.lower, 2.0 * std::numbers::pi, 1e-15);
    EXPECT_NEAR(s.roll_angle.lower, -4.0 * std::numbers::pi, 1e-14);  // accumulated: two rolls
}

}  // namespace
