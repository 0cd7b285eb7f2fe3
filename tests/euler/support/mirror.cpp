/// @file mirror.cpp
/// A whole-span mesh from a half model (mirror.hpp).

#include "mirror.hpp"

#include <array>
#include <vector>

#include "manta/core/error.hpp"

namespace manta::test {

mesh::Mesh mirrored_about_y(const mesh::Mesh& half, const std::string& symmetry_marker,
                            const std::map<std::string, std::string>& renamed) {
    mesh::Mesh m(half.source() + " mirrored about y = 0");
    const int sym = half.find_marker(symmetry_marker);
    if (sym < 0) throw InputError(half.source() + ": no marker '" + symmetry_marker + "'");
    std::vector<mesh::Index> image(static_cast<std::size_t>(half.n_nodes()));
    for (mesh::Index n = 0; n < half.n_nodes(); ++n) (void)m.add_node(half.node(n));
    for (mesh::Index n = 0; n < half.n_nodes(); ++n) {
        const Eigen::Vector3d x = half.node(n);
        image[static_cast<std::size_t>(n)] =
            x.y() == 0.0 ? n : m.add_node(Eigen::Vector3d(x.x(), -x.y(), x.z()));
    }
    const auto im = [&](mesh::Index n) { return image[static_cast<std::size_t>(n)]; };
    for (mesh::Index c = 0; c < half.n_cells(); ++c) {
        if (half.cell_type(c) != mesh::CellType::tetra)
            throw InputError(half.source() + ": mirrored_about_y takes tetrahedra only");
        const auto k = half.cell(c);
        (void)m.add_cell(mesh::CellType::tetra, std::array<mesh::Index, 4>{k[0], k[1], k[2], k[3]});
        // The mirror image reverses the orientation: two nodes swapped.
        (void)m.add_cell(mesh::CellType::tetra,
                         std::array<mesh::Index, 4>{im(k[0]), im(k[2]), im(k[1]), im(k[3])});
    }
    for (mesh::Index f = 0; f < half.n_faces(); ++f) {
        const int mk = half.face_marker(f);
        if (mk == sym) continue;
        const std::string& name = half.markers()[static_cast<std::size_t>(mk)];
        const auto r = renamed.find(name);
        const int a = m.add_marker(name);
        const int b = m.add_marker(r == renamed.end() ? name : r->second);
        const auto k = half.face(f);
        std::vector<mesh::Index> nodes(k.begin(), k.end()), mirror;
        for (mesh::Index n : nodes) mirror.push_back(im(n));
        (void)m.add_face(half.face_type(f), nodes, a);
        (void)m.add_face(half.face_type(f), mirror, b);
    }
    m.finalize();
    return m;
}

}  // namespace manta::test
