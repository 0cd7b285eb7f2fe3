/// @file test_companion.cpp
/// The mesh companion file: written and read back, strict reading, its name beside the mesh, and
/// its `control_surfaces:` list read as it is by meshmotion::parse_control_surfaces.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "manta/core/config.hpp"
#include "manta/core/error.hpp"
#include "manta/meshgen/meshgen.hpp"
#include "manta/meshmotion/control_surfaces.hpp"

namespace {

namespace fs = std::filesystem;
using namespace manta::meshgen;

Companion sample() {
    Companion c;
    c.mesh = "ranger.su2";
    c.aircraft = "examples/ranger2000/aircraft.yaml";
    c.aircraft_name = "Ranger 2000";
    c.model = "half";
    c.level = "medium";
    c.markers = {
        {"wall", "wall"}, {"elevator", "wall"}, {"farfield", "farfield"}, {"symmetry", "symmetry"}};
    c.reference.area = 7.75;
    c.reference.aircraft_area = 15.5;
    c.reference.chord = 1.545;
    c.reference.span = 10.46;
    c.reference.moment_point = Eigen::Vector3d(4.911, 0.0, 0.123);
    c.reference.cg_case = "mtow";
    c.reference.cg = Eigen::Vector3d(4.903, 0.0, 0.123);
    CompanionControlSurface e;
    e.mode = "elevator";
    e.marker = "elevator";
    e.hinge = {Eigen::Vector3d(9.0, 0.127, 2.1), Eigen::Vector3d(9.4, 2.0, 2.1)};
    e.gain = 1.0;
    e.control_surface = "elevator";
    e.side = "right";
    c.control_surfaces.push_back(e);
    return c;
}

fs::path scratch(const std::string& name) {
    const fs::path dir =
        fs::temp_directory_path() / ("manta-companion-" + std::to_string(getpid()));
    fs::create_directories(dir);
    return dir / name;
}

TEST(Companion, PathBesideTheMesh) {
    EXPECT_EQ(companion_path("out/ranger.su2"), fs::path("out/ranger.mesh.yaml"));
    EXPECT_EQ(companion_path("ranger.msh"), fs::path("ranger.mesh.yaml"));
    EXPECT_EQ(companion_path("a/b.cgns"), fs::path("a/b.mesh.yaml"));
}

TEST(Companion, RoundTrip) {
    const auto file = scratch("round.mesh.yaml");
    write_companion(file, sample());
    const Companion c = read_companion(file);
    EXPECT_EQ(c.mesh, "ranger.su2");
    EXPECT_EQ(c.aircraft_name, "Ranger 2000");
    EXPECT_EQ(c.model, "half");
    EXPECT_EQ(c.level, "medium");
    ASSERT_EQ(c.markers.size(), 4u);
    EXPECT_EQ(c.markers[1].name, "elevator");
    EXPECT_EQ(c.markers[2].role, "farfield");
    EXPECT_DOUBLE_EQ(c.reference.area, 7.75);
    EXPECT_DOUBLE_EQ(c.reference.aircraft_area, 15.5);
    EXPECT_DOUBLE_EQ(c.reference.chord, 1.545);
    EXPECT_DOUBLE_EQ(c.reference.moment_point.x(), 4.911);
    EXPECT_EQ(c.reference.cg_case, "mtow");
    ASSERT_EQ(c.control_surfaces.size(), 1u);
    EXPECT_EQ(c.control_surfaces[0].mode, "elevator");
    EXPECT_DOUBLE_EQ(c.control_surfaces[0].hinge[1].y(), 2.0);
}

TEST(Companion, MeshMotionReadsTheControlSurfaces) {
    const auto file = scratch("mm.mesh.yaml");
    write_companion(file, sample());
    const auto node = manta::core::ConfigNode::parse_file(file).child("control_surfaces");
    const auto specs = manta::meshmotion::parse_control_surfaces(node);
    ASSERT_EQ(specs.size(), 1u);
    EXPECT_EQ(specs[0].mode, "elevator");
    EXPECT_EQ(specs[0].marker, "elevator");
    EXPECT_DOUBLE_EQ(specs[0].hinge[0].x(), 9.0);
    EXPECT_DOUBLE_EQ(specs[0].gain, 1.0);
}

void expect_error(const std::string& text, const std::string& needle) {
    const auto file = scratch("bad.mesh.yaml");
    {
        std::ofstream f(file);
        f << text;
    }
    try {
        (void)read_companion(file);
        ADD_FAILURE() << "no error for " << needle;
    } catch (const manta::ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}

TEST(Companion, StrictReading) {
    std::string good = format_companion(sample());
    auto replaced = [&](const std::string& from, const std::string& to) {
        std::string s = good;
        s.replace(s.find(from), from.size(), to);
        return s;
    };
    expect_error(replaced("  farfield: farfield", "  farfield: inlet"), "farfield");
    expect_error(replaced("  chord: 1.545", "  chrod: 1.545"), "chrod");
    expect_error(replaced("model: half", "model: quarter"), "quarter");
    expect_error(replaced("    marker: elevator", "    marker: flap"), "flap");
    expect_error(replaced("  area: 7.75", "  area: -1"), "area");
}

}  // namespace
