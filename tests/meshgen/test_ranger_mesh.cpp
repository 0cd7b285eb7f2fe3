/// @file test_ranger_mesh.cpp
/// The half Ranger 2000 (examples/ranger2000/aircraft.yaml) meshed at sizes 2.5x the coarse
/// level (about 20 s, mostly the CAD): closed with positive volumes, with the expected markers; the
/// files read back with MANTA's readers carry the same markers; the hinge lines of the companion
/// file lie on their markers' nodes and agree with meshmotion's; the marker areas and the span
/// compare with the aircraft file's values.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <set>

#include "manta/aircraft/aircraft.hpp"
#include "manta/core/config.hpp"
#include "manta/mesh/readers.hpp"
#include "manta/meshgen/meshgen.hpp"
#include "manta/meshmotion/control_surfaces.hpp"
#include "ranger_meshing.hpp"

namespace {

namespace fs = std::filesystem;
using namespace manta;
using namespace manta::test::meshgen_support;

const Made& half_su2() {
    static const Made m = make(meshgen::Model::half, "half.su2");
    return m;
}

void check_HalfModelMarkersAndChecks() {
    const auto& m = half_su2();
    expect_sound(m.result);
    const std::set<std::string> expected{"wall",   "elevator", "aileron_right",
                                         "rudder", "farfield", "symmetry"};
    EXPECT_EQ(names(m.mesh.markers()), expected);
    std::set<std::string> in_companion;
    for (const auto& r : m.result.companion.markers) in_companion.insert(r.name);
    EXPECT_EQ(in_companion, expected);
    EXPECT_EQ(m.mesh.n_nodes(), m.result.quality.nodes);
    EXPECT_EQ(m.mesh.n_cells(), m.result.quality.cells);
    // Volume of the half sphere less the half body (the sphere's faceted boundary lies inside it).
    const double r = 5.0 * ranger().reference.span;
    const double sphere = 2.0 / 3.0 * std::numbers::pi * r * r * r;
    EXPECT_NEAR(m.mesh.volume(), sphere - m.result.body_volume, 0.02 * sphere);
    // The fuselage alone holds 8.6 m^3 (docs/ranger2000.md): half of the body is at least 4.3.
    EXPECT_GT(m.result.body_volume, 4.3);
    EXPECT_LT(m.result.body_volume, 7.0);
}

void check_HalfModelSpanAndSymmetry() {
    const auto& m = half_su2();
    double ymin = 1e9, ymax = -1e9;
    for (const auto& name : {"wall", "aileron_right", "elevator", "rudder"})
        for (const auto& p : marker_nodes(m.mesh, name)) {
            ymin = std::min(ymin, p.y());
            ymax = std::max(ymax, p.y());
        }
    EXPECT_NEAR(ymax, 0.5 * 10.46, 0.005 * 10.46);  // Table 1's span
    EXPECT_GT(ymin, -1e-9);
    for (const auto& p : marker_nodes(m.mesh, "symmetry")) ASSERT_NEAR(p.y(), 0.0, 1e-9);
}

void check_ControlSurfaceAreasMatchTheAircraftFile() {
    const auto& m = half_su2();
    const auto& g = ranger().geometry;
    auto area = [&](const std::string& marker) {
        for (const auto& s : m.result.markers)
            if (s.name == marker) return s.area;
        return 0.0;
    };
    // Upper and lower faces of one copy: twice its planform area aft of the hinge, plus the arc
    // length of the airfoil over the chord and the trailing-edge base (a few per cent).
    const double elevator = g.control_surface_area(*g.find_control_surface("elevator")) / 2.0;
    const double aileron = g.control_surface_area(*g.find_control_surface("aileron")) / 2.0;
    const double rudder = g.control_surface_area(*g.find_control_surface("rudder"));
    EXPECT_NEAR(area("elevator") / (2.0 * elevator), 1.0, 0.06);
    EXPECT_NEAR(area("aileron_right") / (2.0 * aileron), 1.0, 0.06);
    // Half model: the rudder's right side only.
    EXPECT_NEAR(area("rudder") / rudder, 1.0, 0.08);
    // Wetted area of the half aircraft: above twice the half planform of the three surfaces
    // (less what the fuselage covers) plus half the fuselage's.
    EXPECT_GT(m.result.wetted_area, 15.5 + 3.6);
    EXPECT_LT(m.result.wetted_area, 45.0);
}

void check_HingeLinesLieOnTheirMarkers() {
    const auto& m = half_su2();
    const auto& g = ranger().geometry;
    const auto& comp = m.result.companion;
    ASSERT_EQ(comp.control_surfaces.size(), 3u);
    for (const auto& cs : comp.control_surfaces) {
        const auto nodes = marker_nodes(m.mesh, cs.marker);
        ASSERT_FALSE(nodes.empty()) << cs.marker;
        const auto* def = g.find_control_surface(cs.control_surface);
        ASSERT_NE(def, nullptr);
        const auto& w = g.surface(def->surface);
        for (int e = 0; e < 2; ++e) {
            const Eigen::Vector3d& p = cs.hinge[static_cast<std::size_t>(e)];
            double d = std::numeric_limits<double>::infinity();
            for (const auto& q : nodes) d = std::min(d, (q - p).norm());
            // The hinge lies on the chord line; the marker's nearest nodes are on its upper and
            // lower surfaces there: half the local thickness plus a surface cell away.
            const double c = std::min(w.tip_chord(), w.root_chord());
            EXPECT_LT(d, 0.12 * c) << cs.marker << " hinge end " << e;
        }
        // Every node of the marker lies aft of its hinge line (within a cell).
        const Eigen::Vector3d a = cs.hinge[0], b = cs.hinge[1];
        for (const auto& q : nodes) {
            const Eigen::Vector3d ab = b - a;
            const double t = std::clamp((q - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
            EXPECT_GT(q.x() - (a + t * ab).x(), -0.03 * w.root_chord()) << cs.marker;
        }
        // meshmotion builds the same hinge, gain and mode from the aircraft file.
        const auto spec = meshmotion::control_surface_from_geometry(g, cs.control_surface,
                                                                    cs.side == "left", cs.marker);
        EXPECT_EQ(spec.mode, cs.mode);
        EXPECT_DOUBLE_EQ(spec.gain, cs.gain);
        EXPECT_LT((spec.hinge[0] - cs.hinge[0]).norm(), 1e-9) << cs.marker;
        EXPECT_LT((spec.hinge[1] - cs.hinge[1]).norm(), 1e-9) << cs.marker;
    }
}

void check_CompanionFileBesideTheMesh() {
    const auto& m = half_su2();
    EXPECT_EQ(m.result.companion_file, scratch("half.mesh.yaml"));
    const auto c = meshgen::read_companion(m.result.companion_file);
    EXPECT_EQ(c.mesh, "half.su2");
    EXPECT_EQ(c.model, "half");
    EXPECT_DOUBLE_EQ(c.reference.area, 15.5 / 2.0);  // half model: half the reference area
    EXPECT_DOUBLE_EQ(c.reference.aircraft_area, 15.5);
    EXPECT_DOUBLE_EQ(c.reference.chord, 1.545);
    EXPECT_DOUBLE_EQ(c.reference.span, 10.46);
    EXPECT_NEAR(c.reference.moment_point.x(), 4.911, 0.001);  // 25 % MAC
    EXPECT_NEAR(c.reference.cg.x(), 4.903, 0.001);            // mtow
    // meshmotion reads the list as it is.
    const auto node =
        core::ConfigNode::parse_file(m.result.companion_file).child("control_surfaces");
    const auto specs = meshmotion::parse_control_surfaces(node);
    EXPECT_EQ(specs.size(), 3u);
    for (const auto& s : specs) EXPECT_GE(m.mesh.find_marker(s.marker), 0) << s.marker;
    // Roles: one far field, one symmetry plane, the rest walls.
    for (const auto& r : c.markers)
        EXPECT_EQ(r.role, r.name == "farfield"   ? "farfield"
                          : r.name == "symmetry" ? "symmetry"
                                                 : "wall");
}

// One mesh for all checks (each test case of a GoogleTest binary runs in its own process under
// ctest, which would mesh it again for each).
TEST(RangerMesh, HalfModel) {
    {
        SCOPED_TRACE("HalfModelMarkersAndChecks");
        check_HalfModelMarkersAndChecks();
    }
    {
        SCOPED_TRACE("HalfModelSpanAndSymmetry");
        check_HalfModelSpanAndSymmetry();
    }
    {
        SCOPED_TRACE("ControlSurfaceAreasMatchTheAircraftFile");
        check_ControlSurfaceAreasMatchTheAircraftFile();
    }
    {
        SCOPED_TRACE("HingeLinesLieOnTheirMarkers");
        check_HingeLinesLieOnTheirMarkers();
    }
    {
        SCOPED_TRACE("CompanionFileBesideTheMesh");
        check_CompanionFileBesideTheMesh();
    }
}

}  // namespace
