// Implausible aircraft dimensions (issue 16, defect 12): a 2e9 m fuselage was read and flown.
// Each dimension now has a plausible range (the largest aircraft flown with a wide margin) and a
// value outside it is refused, naming the file, line, key, value and range.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "manta/aircraft/aircraft.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"

namespace {

namespace fs = std::filesystem;
const fs::path ranger_file =
    fs::path(MANTA_SOURCE_DIR) / "examples" / "ranger2000" / "aircraft.yaml";

std::string variant(const std::string& from, const std::string& to) {
    std::string s = manta::core::read_file(ranger_file);
    const auto p = s.find(from);
    EXPECT_NE(p, std::string::npos) << from;
    if (p == std::string::npos) return s;
    return s.replace(p, from.size(), to);
}

std::string load_error(const std::string& text) {
    try {
        (void)manta::aircraft::parse_aircraft(text, "ranger.yaml", ranger_file.parent_path());
    } catch (const manta::ConfigError& e) {
        return e.what();
    }
    ADD_FAILURE() << "accepted";
    return {};
}

void expect_parts(const std::string& msg, std::initializer_list<std::string> parts) {
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << p << " | " << msg;
}

TEST(AircraftPlausible, TheExampleReads) {
    EXPECT_NO_THROW((void)manta::aircraft::load_aircraft(ranger_file));
}

TEST(AircraftPlausible, GiantFuselageRefused) {
    // The fuselage stations and the overall length, both 2e9 m.
    expect_parts(load_error(variant("  length: 10.39 ", "  length: 2e9 ")),
                 {"ranger.yaml:26", "geometry.length", "'2e9'", "out of range", "(0, 1000] [m]"});
    expect_parts(load_error(variant("9.80, 10.39]", "9.80, 2e9]")),
                 {"geometry.fuselage.x[17]", "'2e9'", "[-1000, 1000] [m]"});
}

TEST(AircraftPlausible, ReferenceAndMassBounded) {
    expect_parts(load_error(variant("  span: 10.46 ", "  span: 1e7 ")),
                 {"ranger.yaml:19", "reference.span", "'1e7'", "(0, 1000] [m]"});
    expect_parts(load_error(variant("      mass: 3765.0", "      mass: 3.765e12")),
                 {"mass", "'3.765e12'", "(0, 1e+07] [kg]"});
    expect_parts(load_error(variant("      ixx: 9287.1", "      ixx: 9.2871e19")),
                 {"ixx", "'9.2871e19'", "(0, 1e+10] [kg m^2]"});
}

}  // namespace
