/// @file test_manoeuvre_file.cpp
/// Manoeuvre files: the examples parse, values land in SI units and radians, and bad files are
/// rejected with one-line messages naming the key.

#include <gtest/gtest.h>

#include <numbers>
#include <string>
#include <vector>

#include "manta/core/error.hpp"
#include "manta/manoeuvres/manoeuvre.hpp"

namespace manta::manoeuvres {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
const std::filesystem::path kDir =
    std::filesystem::path(MANTA_SOURCE_DIR) / "examples/ranger2000/manoeuvres";

TEST(ManoeuvreFile, ExamplesParse) {
    for (const char* f :
         {"level_turn.yaml", "immelmann.yaml", "lazy_eight.yaml", "barrel_roll.yaml"}) {
        EXPECT_NO_THROW((void)load_manoeuvre(kDir / f)) << f;
    }
    const ManoeuvreSpec s = load_manoeuvre(kDir / "immelmann.yaml");
    EXPECT_EQ(s.name, "immelmann");
    EXPECT_DOUBLE_EQ(s.entry_speed, 163.57);
    EXPECT_DOUBLE_EQ(s.entry_altitude, 2986.0);
    EXPECT_TRUE(s.entry_trimmed);
    EXPECT_EQ(s.heading_change.kind, Target::Kind::range);
    EXPECT_NEAR(s.heading_change.lower, std::numbers::pi, 1e-15);
    EXPECT_EQ(s.speed.kind, Target::Kind::entry);
    EXPECT_NEAR(s.alpha[1], 12.0 * kDeg, 1e-15);
    EXPECT_EQ(s.mass_case, "immelmann");
    EXPECT_EQ(s.nodes * s.segments, 60);
    EXPECT_FALSE(s.intermediate.active());
    EXPECT_EQ(s.phase_names, std::vector<std::string>{"manoeuvre"});
}

TEST(ManoeuvreFile, IntermediateConditionAndPhases) {
    // the Lazy Eight's top of the climb (the paper, sec. V): 90 deg of bank at heading 90 deg
    const ManoeuvreSpec s = load_manoeuvre(kDir / "lazy_eight.yaml");
    ASSERT_TRUE(s.intermediate.active());
    EXPECT_DOUBLE_EQ(s.intermediate.fraction, 0.5);
    EXPECT_NEAR(s.intermediate.bank.lower, 90.0 * kDeg, 1e-15);
    EXPECT_NEAR(s.intermediate.heading_change.upper, 90.0 * kDeg, 1e-15);
    EXPECT_EQ(s.intermediate.flight_path_angle.kind, Target::Kind::range);
    EXPECT_EQ(s.intermediate.altitude.kind, Target::Kind::entry);
    EXPECT_FALSE(s.intermediate.speed.active());
    EXPECT_EQ(s.phase_names, (std::vector<std::string>{"climb", "dive"}));
    EXPECT_EQ(s.segments, 4);
    // the paper's envelope as constraints (sec. IV.C: alpha below 6 deg, Mach at most 0.44)
    EXPECT_NEAR(s.alpha[1], 6.0 * kDeg, 1e-15);
    EXPECT_DOUBLE_EQ(s.mach_max, 0.44);
    ASSERT_TRUE(s.bank_range.has_value());
    EXPECT_TRUE(s.speed_path);
}

TEST(ManoeuvreFile, TargetsAndDefaults) {
    const ManoeuvreSpec s = parse_manoeuvre(R"(
name: t
entry: {speed: 100, altitude: 1000}
final:
  altitude: [900, 1100]
  bank_deg: 30
  speed: {entry_offset: [-5, 5]}
)",
                                            "inline");
    EXPECT_EQ(s.altitude.kind, Target::Kind::range);
    EXPECT_DOUBLE_EQ(s.altitude.lower, 900.0);
    EXPECT_DOUBLE_EQ(s.altitude.upper, 1100.0);
    EXPECT_NEAR(s.bank.lower, 30.0 * kDeg, 1e-15);
    EXPECT_EQ(s.speed.kind, Target::Kind::entry);
    EXPECT_DOUBLE_EQ(s.speed.lower, -5.0);
    EXPECT_FALSE(s.heading_change.active());
    EXPECT_TRUE(s.final_rates_zero);
    EXPECT_NEAR(s.alpha[1], 12.0 * kDeg, 1e-15);  // the paper's alpha limit by default
    EXPECT_EQ(s.cost, "minimum_time");
}

TEST(ManoeuvreFile, MachAndBankLimits) {
    // optional path constraints (issue 16): none by default, SI and radians when given
    const ManoeuvreSpec d = parse_manoeuvre("name: t\nentry: {speed: 100, altitude: 1000}\n", "d");
    EXPECT_EQ(d.mach_max, 0.0);
    EXPECT_FALSE(d.bank_range.has_value());
    const ManoeuvreSpec s = parse_manoeuvre(R"(
name: t
entry: {speed: 100, altitude: 1000}
path: {mach_max: 0.44, bank_deg: [-10, 90]}
)",
                                            "inline");
    EXPECT_DOUBLE_EQ(s.mach_max, 0.44);
    ASSERT_TRUE(s.bank_range.has_value());
    EXPECT_NEAR((*s.bank_range)[0], -10.0 * kDeg, 1e-15);
    EXPECT_NEAR((*s.bank_range)[1], 90.0 * kDeg, 1e-15);
}

TEST(ManoeuvreFile, RollDirection) {
    // a one-way roll (path.roll_direction): either way by default, left p <= 0, right p >= 0
    const ManoeuvreSpec d = parse_manoeuvre("name: t\nentry: {speed: 100, altitude: 1000}\n", "d");
    EXPECT_EQ(d.roll_direction, 0);
    const auto dir = [](const std::string& v) {
        return parse_manoeuvre(
                   "name: t\nentry: {speed: 100, altitude: 1000}\npath: {roll_direction: " + v +
                       "}\n",
                   "inline")
            .roll_direction;
    };
    EXPECT_EQ(dir("left"), -1);
    EXPECT_EQ(dir("right"), 1);
    EXPECT_EQ(dir("either"), 0);
    // the Barrel Roll of the paper rolls to the left through a full turn (sec. V)
    EXPECT_EQ(load_manoeuvre(kDir / "barrel_roll.yaml").roll_direction, -1);
}

/// The message of the ConfigError/InputError thrown by parsing `text`.
std::string error_of(const std::string& text) {
    try {
        (void)parse_manoeuvre(text, "bad.yaml");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(ManoeuvreFile, Errors) {
    EXPECT_NE(error_of("name: x\n").find("entry"), std::string::npos);
    const std::string typo =
        error_of("name: x\nentry: {speed: 100, altitude: 1000}\nfinal: {hedding_change_deg: 90}\n");
    EXPECT_NE(typo.find("hedding_change_deg"), std::string::npos) << typo;
    EXPECT_NE(typo.find("bad.yaml"), std::string::npos) << typo;
    const std::string order =
        error_of("name: x\nentry: {speed: 100, altitude: 1000}\nfinal: {altitude: [1100, 900]}\n");
    EXPECT_NE(order.find("altitude"), std::string::npos) << order;
    const std::string both =
        error_of("name: x\nentry: {speed: 100, altitude: 1000}\nfinal: {bank: 0.1, bank_deg: 5}\n");
    EXPECT_NE(both.find("bank"), std::string::npos) << both;
    const std::string speed = error_of("name: x\nentry: {speed: -3, altitude: 1000}\n");
    EXPECT_NE(speed.find("speed"), std::string::npos) << speed;
    const std::string guess =
        error_of("name: x\nentry: {speed: 100, altitude: 1000}\nguess: {duration: 500}\n");
    EXPECT_NE(guess.find("duration"), std::string::npos) << guess;
    const std::string wp = error_of(
        "name: x\nentry: {speed: 100, altitude: 1000}\nguess:\n  waypoints:\n"
        "    - {fraction: 0.5}\n    - {fraction: 0.4}\n");
    EXPECT_NE(wp.find("fraction"), std::string::npos) << wp;
    const std::string phases =
        error_of("name: x\nentry: {speed: 100, altitude: 1000}\nphases: [a, b]\n");
    EXPECT_NE(phases.find("phases"), std::string::npos) << phases;
    const std::string inter = error_of(
        "name: x\nentry: {speed: 100, altitude: 1000}\nintermediate: {bank_deg: 90, fraction: "
        "2}\n");
    EXPECT_NE(inter.find("fraction"), std::string::npos) << inter;
    const std::string mach =
        error_of("name: x\nentry: {speed: 100, altitude: 1000}\npath: {mach_max: 0}\n");
    EXPECT_NE(mach.find("mach_max"), std::string::npos) << mach;
    // phi = atan2(c32, c33) jumps at +-180 deg: a bank range reaching it is refused
    const std::string bank =
        error_of("name: x\nentry: {speed: 100, altitude: 1000}\npath: {bank_deg: [0, 180]}\n");
    EXPECT_NE(bank.find("bank_deg"), std::string::npos) << bank;
    // a roll direction that is not left, right or either: one line naming the key and value
    for (const char* v : {"up", "-1", "[left, right]", "''"}) {
        const std::string dir = error_of(
            std::string("name: x\nentry: {speed: 100, altitude: 1000}\npath: {roll_direction: ") +
            v + "}\n");
        EXPECT_NE(dir.find("roll_direction"), std::string::npos) << v << ": " << dir;
        EXPECT_NE(dir.find("bad.yaml"), std::string::npos) << v << ": " << dir;
        EXPECT_EQ(dir.find('\n'), std::string::npos) << v << ": " << dir;
    }
    const std::string dir_value = error_of(
        "name: x\nentry: {speed: 100, altitude: 1000}\npath: {roll_direction: clockwise}\n");
    EXPECT_NE(dir_value.find("clockwise"), std::string::npos) << dir_value;
    EXPECT_NE(dir_value.find("left"), std::string::npos) << dir_value;
}

}  // namespace
}  // namespace manta::manoeuvres
