#pragma once
/// @file ranger_meshing.hpp
/// Helpers of the Ranger meshing tests (test_ranger_mesh.cpp, test_ranger_full_slow.cpp): a scratch
/// folder per process, the Ranger aircraft, a mesh made and read back, marker nodes, and the
/// checks every generated mesh must pass.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "manta/aircraft/aircraft.hpp"
#include "manta/mesh/readers.hpp"
#include "manta/meshgen/meshgen.hpp"
#include "ranger_text.hpp"

namespace manta::test::meshgen_support {

namespace fs = std::filesystem;

inline fs::path scratch(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("manta-meshgen-" + std::to_string(getpid()));
    fs::create_directories(dir);
    return dir / name;
}

inline const aircraft::AircraftDefinition& ranger() {
    static const auto a = aircraft::load_aircraft(ranger_file);
    return a;
}

struct Made {
    meshgen::MeshResult result;
    mesh::Mesh mesh{"none"};
};

inline Made make(meshgen::Model model, const std::string& file, double factor = 2.5) {
    meshgen::MeshOptions o;
    o.model = model;
    o.size_factor = factor;
    Made m;
    m.result = meshgen::generate_mesh(ranger(), o, scratch(file));
    m.mesh = mesh::read_mesh(m.result.mesh_file);
    return m;
}

inline std::set<std::string> names(const std::vector<std::string>& v) {
    return {v.begin(), v.end()};
}

/// Nodes of a marker in a mesh read back.
inline std::vector<Eigen::Vector3d> marker_nodes(const mesh::Mesh& m, const std::string& marker) {
    const int k = m.find_marker(marker);
    std::set<mesh::Index> ids;
    for (mesh::Index f = 0; f < m.n_faces(); ++f)
        if (m.face_marker(f) == k)
            for (auto v : m.face(f)) ids.insert(v);
    std::vector<Eigen::Vector3d> out;
    for (auto v : ids) out.push_back(m.node(v));
    return out;
}

inline void expect_sound(const meshgen::MeshResult& r) {
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

}  // namespace manta::test::meshgen_support
