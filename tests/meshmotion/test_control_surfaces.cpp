/// @file test_control_surfaces.cpp
/// Control surfaces from a `control_surfaces:` list and from the Ranger 2000's aircraft file
/// (examples/ranger2000/aircraft.yaml): hinge lines, their orientation for the sign conventions
/// of docs/conventions.md, gains, and the one-line configuration errors.

#include <gtest/gtest.h>

#include <string>

#include "manta/core/config.hpp"
#include "manta/core/error.hpp"
#include "manta/meshmotion/control_surfaces.hpp"

namespace {

using manta::meshmotion::parse_control_surfaces;

manta::core::ConfigNode list(const std::string& yaml) {
    return manta::core::ConfigNode::parse_string(yaml, "cfd.yaml").child("control_surfaces");
}

std::string error_of(const std::string& yaml,
                     const manta::geometry::AircraftGeometry* aircraft = nullptr) {
    try {
        (void)parse_control_surfaces(list(yaml), aircraft);
    } catch (const manta::Error& e) {
        return e.what();
    }
    return "";
}

manta::geometry::AircraftGeometry ranger() {
    const std::string file = MANTA_SOURCE_DIR "/examples/ranger2000/aircraft.yaml";
    manta::core::ConfigMap top(manta::core::ConfigNode::parse_file(file));
    manta::core::ConfigMap g = top.map("geometry");
    return manta::geometry::parse_geometry(g, MANTA_SOURCE_DIR "/examples/ranger2000");
}

TEST(ControlSurfaces, ParsesExplicitHingeLines) {
    const auto specs = parse_control_surfaces(list(R"(
control_surfaces:
  - {mode: elevator, marker: flap, hinge: [[0.75, 1, 0], [0.75, 2, 0]]}
  - mode: aileron
    marker: aileron_right
    hinge: [[0.7, 3, 0], [0.7, 1.5, 0.1]]
    gain: -1
    hinge_blend: 0.02
    edge_blend: 0.05
    cutoff: 2
    hinge_tolerance: 0.1
)"));
    ASSERT_EQ(specs.size(), 2U);
    EXPECT_EQ(specs[0].mode, "elevator");
    EXPECT_EQ(specs[0].marker, "flap");
    EXPECT_EQ(specs[0].hinge[1].y(), 2.0);
    EXPECT_EQ(specs[0].gain, 1.0);
    EXPECT_FALSE(specs[0].cutoff.has_value());
    EXPECT_NE(specs[0].source.find("cfd.yaml:3"), std::string::npos) << specs[0].source;
    EXPECT_EQ(specs[1].gain, -1.0);
    EXPECT_EQ(specs[1].hinge[1].z(), 0.1);
    EXPECT_EQ(*specs[1].hinge_blend, 0.02);
    EXPECT_EQ(*specs[1].edge_blend, 0.05);
    EXPECT_EQ(*specs[1].cutoff, 2.0);
    EXPECT_EQ(*specs[1].hinge_tolerance, 0.1);
}

TEST(ControlSurfaces, BadEntriesAreOneLineErrorsNamingTheKey) {
    std::string msg = error_of("control_surfaces:\n  - {mode: elevator, marker: f}\n");
    EXPECT_NE(msg.find("hinge"), std::string::npos) << msg;
    msg = error_of("control_surfaces:\n  - {mode: elevator, marker: f, hinge: [[0, 0, 0]]}\n");
    EXPECT_NE(msg.find("two points"), std::string::npos) << msg;
    msg = error_of(
        "control_surfaces:\n  - {mode: elevator, marker: f, hinge: [[0, 0, 0], [0, 0, 0]]}\n");
    EXPECT_NE(msg.find("two equal points"), std::string::npos) << msg;
    msg = error_of(
        "control_surfaces:\n  - {mode: e, marker: f, hinge: [[0, 0, 0], [0, 1, 0]], hinje: 1}\n");
    EXPECT_NE(msg.find("hinje"), std::string::npos) << msg;
    msg = error_of("control_surfaces:\n  - {control_surface: aileron, marker: a}\n");
    EXPECT_NE(msg.find("needs an aircraft file"), std::string::npos) << msg;
    msg = error_of("control_surfaces: {mode: elevator}\n");
    EXPECT_NE(msg.find("is not a list"), std::string::npos) << msg;
    for (const std::string& m : {msg}) EXPECT_EQ(m.find('\n'), std::string::npos);
}

TEST(ControlSurfaces, RangerHingeLinesFollowTheSignConventions) {
    const auto g = ranger();
    const auto specs = parse_control_surfaces(list(R"(
control_surfaces:
  - {control_surface: elevator, side: right, marker: elevator_right}
  - {control_surface: elevator, side: left, marker: elevator_left}
  - {control_surface: aileron, side: right, marker: aileron_right}
  - {control_surface: aileron, side: left, marker: aileron_left}
  - {control_surface: rudder, marker: rudder}
)"),
                                              &g);
    ASSERT_EQ(specs.size(), 5U);
    auto dir = [](const manta::meshmotion::ControlSurfaceSpec& s) {
        return (s.hinge[1] - s.hinge[0]).normalized();
    };
    // Trailing edge down: right-handed about +y on both sides of horizontal surfaces.
    for (int i = 0; i < 4; ++i) EXPECT_GT(dir(specs[static_cast<std::size_t>(i)]).y(), 0.9) << i;
    EXPECT_EQ(specs[0].mode, "elevator");
    EXPECT_EQ(specs[0].gain, 1.0);
    EXPECT_EQ(specs[1].gain, 1.0);
    // Positive aileron: right trailing edge up (gain -1), left down (+1), paper Fig. 3.
    EXPECT_EQ(specs[2].mode, "aileron");
    EXPECT_EQ(specs[2].gain, -1.0);
    EXPECT_EQ(specs[3].gain, 1.0);
    EXPECT_LT(specs[3].hinge[0].y(), 0.0);
    // The mirrored copy's hinge is the defined copy's mirrored in y.
    EXPECT_DOUBLE_EQ(specs[3].hinge[0].y(), -specs[2].hinge[1].y());
    EXPECT_DOUBLE_EQ(specs[3].hinge[0].x(), specs[2].hinge[1].x());
    // Trailing edge toward -y on the fin: right-handed about -z.
    EXPECT_EQ(specs[4].mode, "rudder");
    EXPECT_LT(dir(specs[4]).z(), -0.9);
    // The rudder's hinge lies at 67 % of the fin's chord: a point rotated positively about it
    // moves toward -y when it is aft of the hinge.
    const Eigen::Vector3d e = dir(specs[4]);
    const Eigen::Vector3d aft = specs[4].hinge[0] + Eigen::Vector3d(0.3, 0.0, 0.0);
    EXPECT_LT(e.cross(aft - specs[4].hinge[0]).y(), 0.0);
    // A fin has no mirrored copy; an unknown name lists the known ones.
    std::string msg =
        error_of("control_surfaces:\n  - {control_surface: rudder, side: left, marker: r}\n", &g);
    EXPECT_NE(msg.find("not symmetric"), std::string::npos) << msg;
    msg = error_of("control_surfaces:\n  - {control_surface: flap, marker: r}\n", &g);
    EXPECT_NE(msg.find("elevator, aileron, rudder"), std::string::npos) << msg;
    EXPECT_NE(msg.find("cfd.yaml:2"), std::string::npos) << msg;
}

}  // namespace
