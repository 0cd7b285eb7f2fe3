/// @file reorder.cpp
/// Reverse Cuthill-McKee renumbering (reorder.hpp).

#include "manta/mesh/reorder.hpp"

#include <algorithm>
#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/cuthill_mckee_ordering.hpp>
#include <cstdlib>
#include <utility>

#include "manta/core/error.hpp"

namespace manta::mesh {

namespace {

/// The node pairs joined by an edge of some cell's faces (each pair once, i < j).
std::vector<std::pair<Index, Index>> cell_edges(const Mesh& mesh) {
    std::vector<std::pair<Index, Index>> e;
    e.reserve(static_cast<std::size_t>(mesh.n_cells()) * 6);
    for (Index c = 0; c < mesh.n_cells(); ++c) {
        const auto nodes = mesh.cell(c);
        for (const auto& f : cell_faces(mesh.cell_type(c))) {
            const int n = f[3] < 0 ? 3 : 4;
            for (int k = 0; k < n; ++k) {
                Index a = nodes[static_cast<std::size_t>(f[k])];
                Index b = nodes[static_cast<std::size_t>(f[(k + 1) % n])];
                if (a > b) std::swap(a, b);
                e.emplace_back(a, b);
            }
        }
    }
    std::sort(e.begin(), e.end());
    e.erase(std::unique(e.begin(), e.end()), e.end());
    return e;
}

}  // namespace

Index bandwidth(const Mesh& mesh) {
    Index b = 0;
    for (const auto& [i, j] : cell_edges(mesh)) b = std::max(b, j - i);
    return b;
}

ReorderedMesh reorder_reverse_cuthill_mckee(const Mesh& mesh) {
    if (!mesh.is_finalized())
        throw InputError(mesh.source() + ": reordering needs a finalized mesh");
    using Graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS>;
    const Index n = mesh.n_nodes();
    Graph g(static_cast<std::size_t>(n));
    for (const auto& [i, j] : cell_edges(mesh))
        boost::add_edge(static_cast<std::size_t>(i), static_cast<std::size_t>(j), g);
    std::vector<std::size_t> order(static_cast<std::size_t>(n));
    // Without a start vertex the library picks a pseudo-peripheral node of each component.
    boost::cuthill_mckee_ordering(g, order.rbegin());

    ReorderedMesh r{Mesh(mesh.source()), {}, {}};
    r.old_from_new.resize(static_cast<std::size_t>(n));
    r.new_from_old.assign(static_cast<std::size_t>(n), -1);
    for (std::size_t k = 0; k < order.size(); ++k) {
        r.old_from_new[k] = static_cast<Index>(order[k]);
        r.new_from_old[order[k]] = static_cast<Index>(k);
    }
    Mesh& m = r.mesh;
    m.reserve(n, mesh.n_cells(), mesh.n_faces());
    for (std::size_t k = 0; k < order.size(); ++k) m.add_node(mesh.node(r.old_from_new[k]));
    for (const std::string& name : mesh.markers()) m.add_marker(name);
    std::vector<Index> buf;
    for (Index c = 0; c < mesh.n_cells(); ++c) {
        buf.clear();
        for (const Index v : mesh.cell(c))
            buf.push_back(r.new_from_old[static_cast<std::size_t>(v)]);
        m.add_cell(mesh.cell_type(c), buf);
    }
    for (Index f = 0; f < mesh.n_faces(); ++f) {
        buf.clear();
        for (const Index v : mesh.face(f))
            buf.push_back(r.new_from_old[static_cast<std::size_t>(v)]);
        m.add_face(mesh.face_type(f), buf, mesh.face_marker(f));
    }
    m.finalize();
    return r;
}

}  // namespace manta::mesh
