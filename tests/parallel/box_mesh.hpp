#pragma once
/// @file box_mesh.hpp
/// Hand-built test meshes of the box [0,1]^3 for the parallel tests, the same on every process
/// (no files, no random numbers): n^3 cubes as hexahedra, as six tetrahedra each (Kuhn's
/// subdivision along the cube diagonal, conforming across cubes), or mixed (columns of
/// hexahedra and columns of two prisms each, conforming on their shared quadrilaterals).
/// Interior nodes are moved by up to `jitter` cube sizes in each direction, so the dual metrics
/// are irregular. Markers: the six sides "x_min" ... "z_max" and "corner", the one face of
/// z_min at the origin.

#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "manta/mesh/mesh.hpp"

namespace manta::parallel::test {

/// How the cubes of the box are split.
enum class BoxCells { hexes, tets, mixed };

/// Signed volume of one cell with the given nodes (m^3).
inline double signed_volume(const mesh::Mesh& m, mesh::CellType t,
                            const std::vector<mesh::Index>& nodes) {
    mesh::Mesh one;
    for (mesh::Index n : nodes) one.add_node(m.node(n));
    std::vector<mesh::Index> local(nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i) local[i] = static_cast<mesh::Index>(i);
    one.add_cell(t, local);
    return one.cell_volume(0);
}

/// Add a cell, mirroring it if its volume is negative (tetra: swap nodes 1, 2; prism: swap the
/// second and third node of both triangles).
inline void add_oriented(mesh::Mesh& m, mesh::CellType t, std::vector<mesh::Index> nodes) {
    if (signed_volume(m, t, nodes) < 0.0) {
        std::swap(nodes[1], nodes[2]);
        if (t == mesh::CellType::prism) std::swap(nodes[4], nodes[5]);
    }
    m.add_cell(t, nodes);
}

/// The box mesh with n cubes per side (see the file comment).
inline mesh::Mesh make_box_mesh(int n, BoxCells kind, double jitter = 0.15) {
    mesh::Mesh m("box");
    const double h = 1.0 / n;
    const auto id = [n](int i, int j, int k) {
        return static_cast<mesh::Index>((k * (n + 1) + j) * (n + 1) + i);
    };
    for (int k = 0; k <= n; ++k)
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                Eigen::Vector3d x(i * h, j * h, k * h);
                const bool interior = i > 0 && i < n && j > 0 && j < n && k > 0 && k < n;
                if (interior)
                    for (int c = 0; c < 3; ++c)
                        x[c] +=
                            jitter * h * std::sin(12.9898 * i + 78.233 * j + 37.719 * k + 1.7 * c);
                m.add_node(x);
            }
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                // Cube corners by bits (x: 1, y: 2, z: 4).
                std::array<mesh::Index, 8> v{};
                for (int b = 0; b < 8; ++b) v[b] = id(i + (b & 1), j + (b >> 1 & 1), k + (b >> 2));
                const bool prisms = kind == BoxCells::mixed && (i + j) % 2 == 1;
                if (kind == BoxCells::hexes || (kind == BoxCells::mixed && !prisms)) {
                    m.add_cell(
                        mesh::CellType::hexa,
                        std::vector<mesh::Index>{v[0], v[1], v[3], v[2], v[4], v[5], v[7], v[6]});
                } else if (prisms) {
                    add_oriented(m, mesh::CellType::prism, {v[0], v[1], v[3], v[4], v[5], v[7]});
                    add_oriented(m, mesh::CellType::prism, {v[0], v[3], v[2], v[4], v[7], v[6]});
                } else {
                    const std::array<std::array<int, 3>, 6> paths{
                        {{1, 2, 4}, {1, 4, 2}, {2, 1, 4}, {2, 4, 1}, {4, 1, 2}, {4, 2, 1}}};
                    for (const auto& p : paths)
                        add_oriented(m, mesh::CellType::tetra,
                                     {v[0], v[p[0]], v[p[0] + p[1]], v[7]});
                }
            }
    // Exposed cell faces (one cell) become boundary faces, on the side their centre lies on.
    std::map<std::array<mesh::Index, 4>, std::pair<int, std::vector<mesh::Index>>> faces;
    for (mesh::Index c = 0; c < m.n_cells(); ++c) {
        const auto nodes = m.cell(c);
        for (const auto& f : mesh::cell_faces(m.cell_type(c))) {
            const int nf = f[3] < 0 ? 3 : 4;
            std::vector<mesh::Index> fn;
            for (int q = 0; q < nf; ++q) fn.push_back(nodes[f[q]]);
            std::array<mesh::Index, 4> key{-1, -1, -1, -1};
            std::copy(fn.begin(), fn.end(), key.begin());
            std::sort(key.begin(), key.end());
            auto& e = faces[key];
            ++e.first;
            e.second = fn;
        }
    }
    const std::array<std::string, 6> side{"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
    for (const auto& s : side) m.add_marker(s);
    const int corner = m.add_marker("corner");
    for (const auto& [key, e] : faces) {
        if (e.first != 1) continue;
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (mesh::Index q : e.second) c += m.node(q);
        c /= static_cast<double>(e.second.size());
        int marker = -1;
        for (int a = 0; a < 3 && marker < 0; ++a) {
            if (std::abs(c[a]) < 1e-12) marker = 2 * a;
            if (std::abs(c[a] - 1.0) < 1e-12) marker = 2 * a + 1;
        }
        if (marker == 4 && c.x() < h && c.y() < h) marker = corner;
        m.add_face(e.second.size() == 3 ? mesh::FaceType::triangle : mesh::FaceType::quad, e.second,
                   marker);
    }
    m.finalize();
    return m;
}

}  // namespace manta::parallel::test
