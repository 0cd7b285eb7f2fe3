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
#include "ranger_text.hpp"

namespace {

namespace fs = std::filesystem;
using namespace manta;

fs::path scratch(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("manta-meshgen-" + std::to_string(getpid()));
    fs::create_directories(dir);
    return dir / name;
}

const aircraft::AircraftDefinition& ranger() {
    static const auto a = aircraft::load_aircraft(test::ranger_file);
    return a;
}

struct Made {
    meshgen::MeshResult result;
    mesh::Mesh mesh{"none"};
};

Made make(meshgen::Model model, const std::string& file, double factor = 2.5) {
    meshgen::MeshOptions o;
    o.model = model;
    o.size_factor = factor;
    Made m;
    m.result = meshgen::generate_mesh(ranger(), o, scratch(file));
    m.mesh = mesh::read_mesh(m.result.mesh_file);
    return m;
}

std::set<std::string> names(const std::vector<std::string>& v) {
    return {v.begin(), v.end()};
}

/// Nodes of a marker in a mesh read back.
std::vector<Eigen::Vector3d> marker_nodes(const mesh::Mesh& m, const std::string& marker) {
    const int k = m.find_marker(marker);
    std::set<mesh::Index> ids;
    for (mesh::Index f = 0; f < m.n_faces(); ++f)
        if (m.face_marker(f) == k)
            for (auto v : m.face(f)) ids.insert(v);
    std::vector<Eigen::Vector3d> out;
    for (auto v : ids) out.push_back(m.node(v));
    return out;
}

void expect_sound(const meshgen::MeshResult& r) {
    const auto& q = r.quality;
    std::printf(
        "%s: %lld nodes, %lld cells, dihedral %.2f-%.2f deg, %lld slivers, volume ratio "
        "%.1f, CAD %.1f s, mesh %.1f s, total %.1f s\n",
        r.mesh_file.filename().c_str(), q.nodes, q.cells, q.min_dihedral_deg, q.max_dihedral_deg,
        q.slivers, q.max_volume_ratio, r.seconds_cad, r.seconds_mesh, r.seconds_total);
    EXPECT_TRUE(q.surface_closed) << q.open_edges << " open edges, " << q.unmarked_faces
                                  << " unmarked faces";
    EXPECT_TRUE(q.volume_positive) << "smallest cell " << q.min_cell_volume;
    EXPECT_GT(q.min_dihedral_deg, 0.0);
    // Slivers (a dihedral angle below 5 or above 175 deg): under 1 % of the cells.
    EXPECT_LT(q.slivers, q.cells / 100);
    EXPECT_GT(q.nodes, 1000);
    // The cells fill the far field less the body.
    EXPECT_GT(r.body_volume, 0.0);
}

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
