/// @file test_ranger_full_slow.cpp
/// The full Ranger 2000 meshed at sizes 3x the coarse level (about 30 s): closed, positive, the
/// seven markers of the full model, gains and hinge directions of the five control surfaces, the
/// span tip to tip; and a mesh written as CGNS read back with the same markers.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <set>

#include "manta/aircraft/aircraft.hpp"
#include "manta/mesh/readers.hpp"
#include "manta/meshgen/meshgen.hpp"
#include "ranger_meshing.hpp"

namespace {

namespace fs = std::filesystem;
using namespace manta;
using namespace manta::test::meshgen_support;

TEST(RangerMeshFull, FullModel) {
    const Made m = make(meshgen::Model::full, "full.msh", 3.0);
    expect_sound(m.result);
    const std::set<std::string> expected{"wall",          "elevator_right", "elevator_left",
                                         "aileron_right", "aileron_left",   "rudder",
                                         "farfield"};
    EXPECT_EQ(names(m.mesh.markers()), expected);
    const auto& comp = m.result.companion;
    EXPECT_DOUBLE_EQ(comp.reference.area, 15.5);
    ASSERT_EQ(comp.control_surfaces.size(), 5u);
    for (const auto& cs : comp.control_surfaces) {
        if (cs.marker == "aileron_left") {
            EXPECT_DOUBLE_EQ(cs.gain, 1.0);
        }
        if (cs.marker == "aileron_right") {
            EXPECT_DOUBLE_EQ(cs.gain, -1.0);
        }
        // Horizontal hinges run toward +y, the rudder's toward -z.
        if (cs.mode == "rudder") {
            EXPECT_LT(cs.hinge[1].z(), cs.hinge[0].z());
        } else {
            EXPECT_GT(cs.hinge[1].y(), cs.hinge[0].y());
        }
    }
    double ymin = 1e9, ymax = -1e9;
    for (const auto& p : marker_nodes(m.mesh, "wall")) {
        ymin = std::min(ymin, p.y());
        ymax = std::max(ymax, p.y());
    }
    EXPECT_NEAR(ymax, 5.23, 0.05);
    EXPECT_NEAR(ymin, -5.23, 0.05);
}

TEST(RangerMeshFull, CgnsFileReadsBack) {
    const Made m = make(meshgen::Model::half, "half.cgns", 4.0);
    expect_sound(m.result);
    EXPECT_EQ(m.mesh.n_nodes(), m.result.quality.nodes);
    const std::set<std::string> expected{"wall",   "elevator", "aileron_right",
                                         "rudder", "farfield", "symmetry"};
    EXPECT_EQ(names(m.mesh.markers()), expected);
}

}  // namespace
