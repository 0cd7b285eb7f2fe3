/// @file write_su2.cpp
/// `write_su2` of test_meshes.hpp (a file of its own: a test linking the meshmotion tests' support
/// library as well takes only this object, not test_meshes.cpp's sanitizer settings, which both
/// libraries define).

#include <fmt/format.h>

#include <filesystem>
#include <fstream>

#include "manta/core/error.hpp"
#include "test_meshes.hpp"

namespace manta::test {

void write_su2(const mesh::Mesh& m, const std::filesystem::path& file) {
    std::ofstream o(file);
    o.precision(17);
    o << "NDIME= 3\nNELEM= " << m.n_cells() << "\n";
    for (mesh::Index c = 0; c < m.n_cells(); ++c) {
        o << static_cast<int>(m.cell_type(c));
        for (const mesh::Index n : m.cell(c)) o << ' ' << n;
        o << ' ' << c << "\n";
    }
    o << "NPOIN= " << m.n_nodes() << "\n";
    for (mesh::Index i = 0; i < m.n_nodes(); ++i) {
        const Eigen::Vector3d x = m.node(i);
        o << x.x() << ' ' << x.y() << ' ' << x.z() << ' ' << i << "\n";
    }
    o << "NMARK= " << m.n_markers() << "\n";
    for (int k = 0; k < m.n_markers(); ++k) {
        int count = 0;
        for (mesh::Index f = 0; f < m.n_faces(); ++f) count += m.face_marker(f) == k ? 1 : 0;
        o << "MARKER_TAG= " << m.markers()[static_cast<std::size_t>(k)]
          << "\nMARKER_ELEMS= " << count << "\n";
        for (mesh::Index f = 0; f < m.n_faces(); ++f) {
            if (m.face_marker(f) != k) continue;
            o << static_cast<int>(m.face_type(f));
            for (const mesh::Index n : m.face(f)) o << ' ' << n;
            o << "\n";
        }
    }
    if (!o) throw IoError(fmt::format("{}: cannot write the SU2 file", file.string()));
}

}  // namespace manta::test
