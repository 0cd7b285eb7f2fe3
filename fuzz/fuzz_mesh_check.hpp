#pragma once
/// @file fuzz_mesh_check.hpp
/// The invariants of a mesh returned by a mesh reader (mesh/mesh.hpp, `Mesh::finalize`), checked
/// by fuzz_su2, fuzz_gmsh and fuzz_cgns (docs/fuzzing.md): finalized, finite coordinates, node
/// numbers in range, positive finite cell volumes, faces on existing markers.

#include <cmath>

#include "fuzz_check.hpp"
#include "manta/mesh/mesh.hpp"

namespace manta::fuzz {

inline void check_mesh(const manta::mesh::Mesh& m) {
    check(m.is_finalized(), "mesh: finalized");
    check(m.n_nodes() > 0 && m.n_cells() > 0, "mesh: nodes and cells");
    check(all_finite(m.coordinates()), "mesh: coordinates finite");
    const auto in_range = [&](auto nodes) {
        for (const auto n : nodes)
            if (n < 0 || n >= m.n_nodes()) return false;
        return true;
    };
    for (manta::mesh::Index c = 0; c < m.n_cells(); ++c) {
        check(static_cast<int>(m.cell(c).size()) == manta::mesh::node_count(m.cell_type(c)),
              "mesh: cell node count of its type");
        check(in_range(m.cell(c)), "mesh: cell node numbers in range");
        const double v = m.cell_volume(c);
        check(std::isfinite(v) && v > 0.0, "mesh: cell volume finite, > 0");
    }
    for (manta::mesh::Index f = 0; f < m.n_faces(); ++f) {
        check(static_cast<int>(m.face(f).size()) == manta::mesh::node_count(m.face_type(f)),
              "mesh: face node count of its type");
        check(in_range(m.face(f)), "mesh: face node numbers in range");
        check(m.face_marker(f) >= 0 && m.face_marker(f) < m.n_markers(),
              "mesh: face marker exists");
    }
}

}  // namespace manta::fuzz
