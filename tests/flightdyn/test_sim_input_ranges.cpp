// Control-input CSV plausibility (issue 16, defect 5): an elevator of 5 rad (degrees typed as
// radians) was saturated silently; a deflection beyond 90 deg is refused naming file, line,
// column, value and range. Text that is not UTF-8 is refused where it is read (defect 4).
#include <gtest/gtest.h>

#include <string>

#include "manta/core/error.hpp"
#include "manta/flightdyn/simulate.hpp"

namespace {

namespace fd = manta::flightdyn;

std::string error_of(const std::string& csv) {
    try {
        (void)fd::InputHistory::parse(csv, "in.csv", fd::Controls<double>{});
    } catch (const manta::InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "accepted: " << csv;
    return {};
}

TEST(SimInputRanges, ElevatorInDegreesAsRadiansRefused) {
    const std::string msg = error_of("t,elevator\n0,0\n1,5\n");
    for (const char* p : {"in.csv:3:2", "column 'elevator'", "value 5", "[-1.5708, 1.5708] rad",
                          "degrees typed as radians", "elevator_deg"})
        EXPECT_NE(msg.find(p), std::string::npos) << p << " | " << msg;
    const std::string deg = error_of("t,rudder_deg\n0,0\n1,120\n");
    EXPECT_NE(deg.find("[-90, 90] deg"), std::string::npos) << deg;
}

TEST(SimInputRanges, PlausibleInputsRead) {
    const auto h = fd::InputHistory::parse("t,elevator,aileron_deg,throttle\n0,0.1,-20,0.5\n",
                                           "in.csv", fd::Controls<double>{});
    EXPECT_DOUBLE_EQ(h.at(0.0).elevator, 0.1);
}

TEST(SimInputRanges, NonUtf8Refused) {
    const std::string msg = error_of("# \xFF\nt,elevator\n0,0\n");
    EXPECT_NE(msg.find("in.csv:1"), std::string::npos) << msg;
    EXPECT_NE(msg.find("not valid UTF-8"), std::string::npos) << msg;
}

}  // namespace
