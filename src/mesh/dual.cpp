/// @file dual.cpp
/// Median-dual metrics (dual.hpp): one sweep over the cells' faces builds the edge normals and
/// the dual volumes from the same triangles, a second over the boundary faces the boundary
/// normals.

#include "manta/mesh/dual.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "manta/core/error.hpp"

namespace manta::mesh {

namespace {

std::uint64_t edge_key(Index a, Index b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}

/// Signed volume of the cone from `apex` over the triangle (a, b, c) (positive when the
/// triangle's right-hand normal points away from the apex).
double cone(const Eigen::Vector3d& apex, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
            const Eigen::Vector3d& c) {
    return (b - a).cross(c - a).dot(a - apex) / 6.0;
}

}  // namespace

std::size_t DualMetrics::memory_bytes() const noexcept {
    std::size_t b = edges.capacity() * sizeof(edges[0]) +
                    static_cast<std::size_t>(edge_normals.size()) * sizeof(double) +
                    dual_volumes.capacity() * sizeof(double) +
                    node_edge_offsets.capacity() * sizeof(std::int64_t) +
                    node_edges.capacity() * sizeof(Index);
    for (const auto& bv : boundary)
        b += bv.nodes.capacity() * sizeof(Index) +
             static_cast<std::size_t>(bv.normals.size()) * sizeof(double);
    return b;
}

DualMetrics compute_dual_metrics(const Mesh& mesh) {
    if (!mesh.is_finalized())
        throw InputError(
            fmt::format("{}: dual metrics need a finalized mesh (Mesh::finalize)", mesh.source()));
    DualMetrics d;
    const Index nn = mesh.n_nodes();

    // Edge list: every cell edge is an edge of one of its faces.
    std::vector<std::uint64_t> keys;
    keys.reserve(static_cast<std::size_t>(mesh.n_cells()) * 12);
    for (Index c = 0; c < mesh.n_cells(); ++c) {
        const auto nodes = mesh.cell(c);
        for (const auto& f : cell_faces(mesh.cell_type(c))) {
            const int nf = f[3] < 0 ? 3 : 4;
            for (int k = 0; k < nf; ++k)
                keys.push_back(edge_key(nodes[f[k]], nodes[f[(k + 1) % nf]]));
        }
    }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    keys.shrink_to_fit();
    const auto ne = static_cast<Index>(keys.size());
    d.edges.resize(ne);
    for (Index e = 0; e < ne; ++e)
        d.edges[e] = {static_cast<Index>(keys[e] >> 32), static_cast<Index>(keys[e] & 0xffffffffu)};
    const auto find_edge = [&keys](Index a, Index b) {
        return static_cast<Index>(std::lower_bound(keys.begin(), keys.end(), edge_key(a, b)) -
                                  keys.begin());
    };

    // Node-to-edge CSR.
    d.node_edge_offsets.assign(static_cast<std::size_t>(nn) + 1, 0);
    for (const auto& e : d.edges) {
        ++d.node_edge_offsets[e[0] + 1];
        ++d.node_edge_offsets[e[1] + 1];
    }
    for (Index n = 0; n < nn; ++n) d.node_edge_offsets[n + 1] += d.node_edge_offsets[n];
    d.node_edges.resize(static_cast<std::size_t>(d.node_edge_offsets[nn]));
    {
        std::vector<std::int64_t> fill(d.node_edge_offsets.begin(), d.node_edge_offsets.end() - 1);
        for (Index e = 0; e < ne; ++e) {
            d.node_edges[fill[d.edges[e][0]]++] = e;
            d.node_edges[fill[d.edges[e][1]]++] = e;
        }
    }

    // Interior dual faces and volumes: for the face edge p->q of an outward cell face f, the
    // triangle (m_pq, c_f, c_cell) separates p from q; its area vector oriented p->q is
    // (c_cell - m) x (c_f - m) / 2. The cones from c_cell over (p, m, c_f) and (q, c_f, m) are
    // the parts of p's and q's dual cells next to that face.
    d.edge_normals = Eigen::Matrix3Xd::Zero(3, ne);
    d.dual_volumes.assign(nn, 0.0);
    for (Index c = 0; c < mesh.n_cells(); ++c) {
        const auto nodes = mesh.cell(c);
        Eigen::Vector3d cc = Eigen::Vector3d::Zero();
        for (Index n : nodes) cc += mesh.node(n);
        cc /= static_cast<double>(nodes.size());
        for (const auto& f : cell_faces(mesh.cell_type(c))) {
            const int nf = f[3] < 0 ? 3 : 4;
            Eigen::Vector3d cf = Eigen::Vector3d::Zero();
            for (int k = 0; k < nf; ++k) cf += mesh.node(nodes[f[k]]);
            cf /= nf;
            for (int k = 0; k < nf; ++k) {
                const Index p = nodes[f[k]];
                const Index q = nodes[f[(k + 1) % nf]];
                const Eigen::Vector3d xp = mesh.node(p);
                const Eigen::Vector3d xq = mesh.node(q);
                const Eigen::Vector3d m = 0.5 * (xp + xq);
                const Eigen::Vector3d s = 0.5 * (cc - m).cross(cf - m);
                const Index e = find_edge(p, q);
                if (p < q)
                    d.edge_normals.col(e) += s;
                else
                    d.edge_normals.col(e) -= s;
                d.dual_volumes[p] += cone(cc, xp, m, cf);
                d.dual_volumes[q] += cone(cc, xq, cf, m);
            }
        }
    }

    // Boundary normals per marker: the parts (p, m_pq, c_f) and (q, c_f, m_pq) of each
    // outward boundary face.
    d.boundary.resize(mesh.n_markers());
    for (int mk = 0; mk < mesh.n_markers(); ++mk) d.boundary[mk].marker = mk;
    for (Index f = 0; f < mesh.n_faces(); ++f) {
        auto& nodes = d.boundary[mesh.face_marker(f)].nodes;
        for (Index n : mesh.face(f)) nodes.push_back(n);
    }
    for (auto& bv : d.boundary) {
        std::sort(bv.nodes.begin(), bv.nodes.end());
        bv.nodes.erase(std::unique(bv.nodes.begin(), bv.nodes.end()), bv.nodes.end());
        bv.normals = Eigen::Matrix3Xd::Zero(3, static_cast<Index>(bv.nodes.size()));
    }
    for (Index f = 0; f < mesh.n_faces(); ++f) {
        auto& bv = d.boundary[mesh.face_marker(f)];
        const auto local = [&bv](Index n) {
            return static_cast<Index>(std::lower_bound(bv.nodes.begin(), bv.nodes.end(), n) -
                                      bv.nodes.begin());
        };
        const auto nodes = mesh.face(f);
        const int nf = static_cast<int>(nodes.size());
        Eigen::Vector3d cf = Eigen::Vector3d::Zero();
        for (Index n : nodes) cf += mesh.node(n);
        cf /= nf;
        for (int k = 0; k < nf; ++k) {
            const Index p = nodes[k];
            const Index q = nodes[(k + 1) % nf];
            const Eigen::Vector3d xp = mesh.node(p);
            const Eigen::Vector3d xq = mesh.node(q);
            const Eigen::Vector3d m = 0.5 * (xp + xq);
            bv.normals.col(local(p)) += 0.5 * (m - xp).cross(cf - xp);
            bv.normals.col(local(q)) += 0.5 * (cf - xq).cross(m - xq);
        }
    }
    return d;
}

double max_closure_defect(const Mesh& mesh, const DualMetrics& dual) {
    const Index nn = mesh.n_nodes();
    Eigen::Matrix3Xd sum = Eigen::Matrix3Xd::Zero(3, nn);
    std::vector<double> scale(nn, 0.0);
    for (Index e = 0; e < dual.n_edges(); ++e) {
        const auto [i, j] = dual.edges[e];
        sum.col(i) += dual.edge_normals.col(e);
        sum.col(j) -= dual.edge_normals.col(e);
        const double a = dual.edge_normals.col(e).norm();
        scale[i] = std::max(scale[i], a);
        scale[j] = std::max(scale[j], a);
    }
    for (const auto& bv : dual.boundary)
        for (std::size_t k = 0; k < bv.nodes.size(); ++k) {
            const Index n = bv.nodes[k];
            sum.col(n) += bv.normals.col(static_cast<Index>(k));
            scale[n] = std::max(scale[n], bv.normals.col(static_cast<Index>(k)).norm());
        }
    double worst = 0.0;
    for (Index n = 0; n < nn; ++n)
        if (scale[n] > 0.0) worst = std::max(worst, sum.col(n).norm() / scale[n]);
    return worst;
}

}  // namespace manta::mesh
