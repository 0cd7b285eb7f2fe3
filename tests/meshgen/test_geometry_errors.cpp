/// @file test_geometry_errors.cpp
/// Geometry that cannot be built is refused with one line naming the aircraft file's key and its
/// value: sections out of order, self-intersection (twin fins that overlap), a control surface
/// outside its surface (inside the fuselage: no wetted face), a degenerate airfoil.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <numbers>

#include "manta/aircraft/aircraft.hpp"
#include "manta/core/error.hpp"
#include "manta/meshgen/meshgen.hpp"
#include "ranger_text.hpp"

namespace {

namespace fs = std::filesystem;
using manta::test::ranger_text;
using manta::test::replaced;

fs::path scratch_dir() {
    const fs::path dir =
        fs::temp_directory_path() / ("manta-meshgen-err-" + std::to_string(getpid()));
    fs::create_directories(dir);
    return dir;
}

/// Load the text as an aircraft file (written to disk, so that the error can give its line), run
/// check_buildable and, when `mesh` is set, the CAD of generate_mesh; return the error message.
std::string error_of(const std::string& text, bool mesh = false) {
    const fs::path file = scratch_dir() / "aircraft.yaml";
    {
        std::ofstream f(file);
        f << text;
    }
    try {
        const auto a = manta::aircraft::load_aircraft(file);
        manta::meshgen::check_buildable(a);
        if (mesh) {
            manta::meshgen::MeshOptions o;
            o.size_factor = 4.0;
            (void)manta::meshgen::generate_mesh(a, o, scratch_dir() / "m.su2");
        }
    } catch (const manta::ConfigError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        EXPECT_EQ(e.exit_code(), 2);
        return msg;
    }
    ADD_FAILURE() << "no ConfigError";
    return {};
}

TEST(GeometryErrors, SectionsOutOfOrder) {
    const auto msg =
        error_of(replaced(ranger_text(), "[4.6546, 5.23, 0.27409]", "[4.6546, -1.0, 0.27409]"));
    EXPECT_NE(msg.find("lifting_surfaces[0].sections[1].leading_edge"), std::string::npos) << msg;
}

TEST(GeometryErrors, OverlappingTwinFinsSelfIntersect) {
    auto text = replaced(ranger_text(), "      vertical: true\n      symmetric: false",
                         "      vertical: true\n      symmetric: true");
    text = replaced(text, "      gain: 1.0 ", "      gain_right: 1.0\n      gain_left: 1.0\n ");
    const auto msg = error_of(text);
    EXPECT_NE(msg.find("geometry.lifting_surfaces[2].sections[0].leading_edge"), std::string::npos)
        << msg;
    EXPECT_NE(msg.find("self-intersects"), std::string::npos) << msg;
    EXPECT_NE(msg.find("[7.01, 0, 0.42]"), std::string::npos) << msg;
    EXPECT_NE(msg.find("aircraft.yaml:"), std::string::npos) << msg;  // with the line
}

TEST(GeometryErrors, ControlSurfaceInsideTheFuselage) {
    // Ailerons over 0-8 % of the semi-span (y < 0.42 m) lie inside the fuselage (half width
    // 0.55-0.65 m beside the wing root): no wetted face.
    const auto msg = error_of(
        replaced(ranger_text(), "span_fraction: [0.55, 0.95]", "span_fraction: [0.0, 0.08]"));
    EXPECT_NE(msg.find("geometry.control_surfaces[1].span_fraction"), std::string::npos) << msg;
    EXPECT_NE(msg.find("[0, 0.08]"), std::string::npos) << msg;
}

TEST(GeometryErrors, ControlSurfaceBeyondItsSurface) {
    const auto msg = error_of(
        replaced(ranger_text(), "span_fraction: [0.55, 0.95]", "span_fraction: [0.55, 1.2]"));
    EXPECT_NE(msg.find("control_surfaces[1].span_fraction"), std::string::npos) << msg;
}

TEST(GeometryErrors, DegenerateAirfoil) {
    // A Selig file 0.2 % of the chord thick.
    const fs::path foil = scratch_dir() / "thin.dat";
    {
        std::ofstream f(foil);
        f << "thin plate\n";
        const int n = 20;
        for (int i = n; i >= 0; --i) {
            const double x = 0.5 * (1 - std::cos(std::numbers::pi * i / n));
            f << x << " " << 0.001 * std::sin(std::numbers::pi * x) << "\n";
        }
        for (int i = 1; i <= n; ++i) {
            const double x = 0.5 * (1 - std::cos(std::numbers::pi * i / n));
            f << x << " " << -0.001 * std::sin(std::numbers::pi * x) << "\n";
        }
    }
    const auto msg =
        error_of(replaced(ranger_text(), "airfoil: NACA 0010\n        - leading_edge: [8.275",
                          "airfoil_file: " + foil.string() + "\n        - leading_edge: [8.275"));
    EXPECT_NE(msg.find("geometry.lifting_surfaces[2].sections[0].airfoil_file"), std::string::npos)
        << msg;
    EXPECT_NE(msg.find("degenerate"), std::string::npos) << msg;
    EXPECT_NE(msg.find("thin.dat"), std::string::npos) << msg;
}

TEST(GeometryErrors, TheRangerIsBuildable) {
    const auto a = manta::aircraft::load_aircraft(manta::test::ranger_file);
    EXPECT_NO_THROW(manta::meshgen::check_buildable(a));
}

}  // namespace
