// Trajectory CSV reader (docs/formats.md#trajectory-csv, docs/replay.md "Bad input"): every
// invalid input is one InputError line naming the file, the line and the column.

#include <gtest/gtest.h>

#include <string>

#include "manta/core/error.hpp"
#include "manta/replay/trajectory.hpp"

namespace {

using namespace manta;

const std::string header = "t,x,y,z,phi,theta,psi,V,alpha,beta,p,q,r,elevator,aileron,rudder";
const std::string row0 = "0,0,0,-1000,0,0.05,0,100,0.05,0,0,0,0,-0.02,0,0";
const std::string row1 = "0.1,10,0,-1000,0,0.05,0,100,0.05,0,0,0,0,-0.02,0,0";

std::string error_of(const std::string& text) {
    try {
        (void)replay::parse_trajectory(text, "traj.csv");
    } catch (const InputError& e) {
        const std::string m = e.what();
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;  // one line
        return m;
    }
    ADD_FAILURE() << "no error for:\n" << text;
    return {};
}

TEST(Trajectory, ReadsColumnsMetadataAndIgnoresUnknownColumns) {
    const std::string text =
        "# manoeuvre: test\n# phases: climb, dive\nt,x,y,z,phi,theta,psi,V,alpha,beta,p,q,r,"
        "elevator,aileron,rudder,throttle,phase,gps_quality,pilot\n" +
        row0 + ",0.5,0,3,fine\n" + row1 + ",0.5,1,2,also text\n";
    const replay::Trajectory tr = replay::parse_trajectory(text, "traj.csv");
    ASSERT_EQ(tr.size(), 2u);
    EXPECT_EQ(tr.t[1], 0.1);
    EXPECT_EQ(tr.position[0][1], 10.0);
    EXPECT_EQ(tr.V[0], 100.0);
    EXPECT_EQ(tr.controls[0][0], -0.02);
    EXPECT_EQ(tr.throttle.size(), 2u);
    EXPECT_EQ(tr.phase[1], 1);
    EXPECT_EQ(tr.meta("manoeuvre"), "test");
    ASSERT_EQ(tr.phase_names.size(), 2u);
    EXPECT_EQ(tr.phase_names[1], "dive");
    EXPECT_EQ(tr.line[0], 4);
}

TEST(Trajectory, MissingColumnsAreAllNamed) {
    const std::string m = error_of("t,x,y,z,phi,theta,V,alpha,p,q,r,elevator,aileron\n1,2\n");
    EXPECT_NE(m.find("traj.csv:1"), std::string::npos) << m;
    for (const char* c : {"psi", "beta", "rudder"}) EXPECT_NE(m.find(c), std::string::npos) << m;
}

TEST(Trajectory, NonMonotonicAndDuplicatedTimes) {
    std::string m = error_of(header + "\n" + row1 + "\n" + row0 + "\n");
    EXPECT_NE(m.find("traj.csv:3, column 1 't'"), std::string::npos) << m;
    EXPECT_NE(m.find("goes back"), std::string::npos) << m;
    m = error_of(header + "\n" + row0 + "\n" + row0 + "\n");
    EXPECT_NE(m.find("traj.csv:3, column 1 't'"), std::string::npos) << m;
    EXPECT_NE(m.find("repeats"), std::string::npos) << m;
}

TEST(Trajectory, NanInfAndText) {
    std::string bad = row1;
    bad.replace(bad.find(",100,"), 5, ",nan,");
    std::string m = error_of(header + "\n" + row0 + "\n" + bad + "\n");
    EXPECT_NE(m.find("traj.csv:3, column 8 'V': nan"), std::string::npos) << m;
    bad = row1;
    bad.replace(bad.find(",100,"), 5, ",inf,");
    m = error_of(header + "\n" + row0 + "\n" + bad + "\n");
    EXPECT_NE(m.find("column 8 'V': inf"), std::string::npos) << m;
    bad = row1;
    bad.replace(bad.find(",100,"), 5, ",fast,");
    m = error_of(header + "\n" + row0 + "\n" + bad + "\n");
    EXPECT_NE(m.find("'fast' is not a number"), std::string::npos) << m;
}

TEST(Trajectory, AnglesOutsidePhysicalRanges) {
    // alpha 100 deg, beta -95 deg, theta 2 rad, V <= 0, elevator 2 rad, throttle 1.5.
    const std::vector<std::pair<std::string, std::string>> cases{
        {"0.1,10,0,-1000,0,0.05,0,100,1.75,0,0,0,0,-0.02,0,0", "column 9 'alpha'"},
        {"0.1,10,0,-1000,0,0.05,0,100,0.05,-1.66,0,0,0,-0.02,0,0", "column 10 'beta'"},
        {"0.1,10,0,-1000,0,2,0,100,0.05,0,0,0,0,-0.02,0,0", "column 6 'theta'"},
        {"0.1,10,0,-1000,0,0.05,0,0,0.05,0,0,0,0,-0.02,0,0", "column 8 'V'"},
        {"0.1,10,0,-1000,0,0.05,0,100,0.05,0,0,0,0,2,0,0", "column 14 'elevator'"},
        {"0.1,10,0,-1000,0,0.05,0,100,0.05,0,0,30,0,0,0,0", "column 12 'q'"},
    };
    for (const auto& [row, where] : cases) {
        const std::string m = error_of(header + "\n" + row0 + "\n" + row + "\n");
        EXPECT_NE(m.find("traj.csv:3, " + where), std::string::npos) << m;
        EXPECT_NE(m.find("out of range; expected"), std::string::npos) << m;
    }
}

TEST(Trajectory, TooFewRowsShortRowsAndNoHeader) {
    std::string m = error_of(header + "\n" + row0 + "\n");
    EXPECT_NE(m.find("1 data row(s); expected at least 2"), std::string::npos) << m;
    m = error_of(header + "\n" + row0 + "\n0.1,10,0\n");
    EXPECT_NE(m.find("traj.csv:3"), std::string::npos) << m;
    EXPECT_NE(m.find("column 4 'z'"), std::string::npos) << m;
    m = error_of("# only metadata\n");
    EXPECT_NE(m.find("no header"), std::string::npos) << m;
    m = error_of(header + ",t\n");
    EXPECT_NE(m.find("appears twice"), std::string::npos) << m;
}

TEST(Trajectory, UnreadableFileIsIoError) {
    EXPECT_THROW((void)replay::read_trajectory("/nonexistent/traj.csv"), IoError);
}

}  // namespace
