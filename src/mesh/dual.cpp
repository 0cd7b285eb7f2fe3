/// @file dual.cpp
/// Median-dual metrics (dual.hpp): one sweep over the cells' faces builds the edge normals and
/// the dual volumes from the same triangles, a second over the boundary faces the boundary
/// normals.

#include "manta/mesh/dual.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

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

/// Number of edge (a, b) in the sorted edge list (a, b in any order; the edge must exist).
Index find_edge(const DualMetrics& d, Index a, Index b) {
    if (a > b) std::swap(a, b);
    const std::array<Index, 2> key{a, b};
    return static_cast<Index>(std::lower_bound(d.edges.begin(), d.edges.end(), key) -
                              d.edges.begin());
}

/// Local number of node n in a boundary's sorted node list.
Index local_index(const BoundaryVertices& bv, Index n) {
    return static_cast<Index>(std::lower_bound(bv.nodes.begin(), bv.nodes.end(), n) -
                              bv.nodes.begin());
}

/// The geometric part of the metrics from the mesh's coordinates, into arrays already sized.
///
/// Interior dual faces and volumes: for the face edge p->q of an outward cell face f, the
/// triangle (m_pq, c_f, c_cell) separates p from q; its area vector oriented p->q is
/// (c_cell - m) x (c_f - m) / 2. The cones from c_cell over (p, m, c_f) and (q, c_f, m) are the
/// parts of p's and q's dual cells next to that face. Boundary normals per marker: the parts
/// (p, m_pq, c_f) and (q, c_f, m_pq) of each outward boundary face.
void fill_geometry(const Mesh& mesh, DualMetrics& d) {
    d.edge_normals.setZero();
    std::fill(d.dual_volumes.begin(), d.dual_volumes.end(), 0.0);
    const Index* slot = d.cell_face_edges.data();
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
                const Index e = *slot++;
                if (p < q)
                    d.edge_normals.col(e) += s;
                else
                    d.edge_normals.col(e) -= s;
                d.dual_volumes[p] += cone(cc, xp, m, cf);
                d.dual_volumes[q] += cone(cc, xq, cf, m);
            }
        }
    }
    for (auto& bv : d.boundary) bv.normals.setZero();
    const Index* bslot = d.boundary_face_slots.data();
    for (Index f = 0; f < mesh.n_faces(); ++f) {
        auto& bv = d.boundary[mesh.face_marker(f)];
        const Index* face_slots = bslot;
        bslot += mesh.face(f).size();
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
            bv.normals.col(face_slots[k]) += 0.5 * (m - xp).cross(cf - xp);
            bv.normals.col(face_slots[(k + 1) % nf]) += 0.5 * (cf - xq).cross(m - xq);
        }
    }
}

/// Whether `d` has the sizes of metrics of `mesh` (a cheap check, not a proof).
bool belongs_to(const Mesh& mesh, const DualMetrics& d) {
    if (static_cast<Index>(d.dual_volumes.size()) != mesh.n_nodes() ||
        d.edge_normals.cols() != d.n_edges() ||
        static_cast<int>(d.boundary.size()) != mesh.n_markers() ||
        d.node_edge_offsets.size() != static_cast<std::size_t>(mesh.n_nodes()) + 1)
        return false;
    for (const auto& bv : d.boundary)
        if (bv.normals.cols() != static_cast<Index>(bv.nodes.size())) return false;
    std::size_t n_face_edges = 0, n_face_nodes = 0;
    for (Index c = 0; c < mesh.n_cells(); ++c)
        for (const auto& f : cell_faces(mesh.cell_type(c))) n_face_edges += f[3] < 0 ? 3 : 4;
    for (Index f = 0; f < mesh.n_faces(); ++f) n_face_nodes += mesh.face(f).size();
    return d.cell_face_edges.size() == n_face_edges && d.boundary_face_slots.size() == n_face_nodes;
}

/// Position of node n in a flat coordinate array.
inline Eigen::Vector3d at(std::span<const double> x, Index n) {
    const auto k = 3 * static_cast<std::size_t>(n);
    return {x[k], x[k + 1], x[k + 2]};
}

/// Area vector of the triangle (a, b, c), (b - a) x (c - a) / 2, written as the metrics write
/// their triangles: 0.5 (b - a) x (c - a).
inline Eigen::Vector3d area(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c) {
    return 0.5 * (b - a).cross(c - a);
}

/// Volume swept by the triangle whose corners move linearly from (a0, b0, c0) to (a1, b1, c1),
/// positive along its area vector (b - a) x (c - a) / 2: the mean corner displacement dotted
/// with Simpson's rule on the area vector (quadratic in time, so exact).
inline double swept(const Eigen::Vector3d& a0, const Eigen::Vector3d& b0, const Eigen::Vector3d& c0,
                    const Eigen::Vector3d& a1, const Eigen::Vector3d& b1,
                    const Eigen::Vector3d& c1) {
    const Eigen::Vector3d nm = area(0.5 * (a0 + a1), 0.5 * (b0 + b1), 0.5 * (c0 + c1));
    const Eigen::Vector3d n = area(a0, b0, c0) + 4.0 * nm + area(a1, b1, c1);
    const Eigen::Vector3d dm = (a1 - a0) + (b1 - b0) + (c1 - c0);
    return dm.dot(n) / 18.0;
}

}  // namespace

std::size_t DualMetrics::memory_bytes() const noexcept {
    std::size_t b = edges.capacity() * sizeof(edges[0]) +
                    static_cast<std::size_t>(edge_normals.size()) * sizeof(double) +
                    dual_volumes.capacity() * sizeof(double) +
                    node_edge_offsets.capacity() * sizeof(std::int64_t) +
                    node_edges.capacity() * sizeof(Index) +
                    (cell_face_edges.capacity() + boundary_face_slots.capacity()) * sizeof(Index);
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

    // Boundary node lists per marker.
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
    // The topology the per-step geometry reuses (fill_geometry's and swept_volumes' order).
    d.cell_face_edges.reserve(static_cast<std::size_t>(mesh.n_cells()) * 12);
    for (Index c = 0; c < mesh.n_cells(); ++c) {
        const auto nodes = mesh.cell(c);
        for (const auto& f : cell_faces(mesh.cell_type(c))) {
            const int nf = f[3] < 0 ? 3 : 4;
            for (int k = 0; k < nf; ++k)
                d.cell_face_edges.push_back(find_edge(d, nodes[f[k]], nodes[f[(k + 1) % nf]]));
        }
    }
    d.cell_face_edges.shrink_to_fit();
    for (Index f = 0; f < mesh.n_faces(); ++f) {
        const auto& bv = d.boundary[mesh.face_marker(f)];
        for (Index n : mesh.face(f)) d.boundary_face_slots.push_back(local_index(bv, n));
    }
    d.edge_normals = Eigen::Matrix3Xd::Zero(3, ne);
    d.dual_volumes.assign(nn, 0.0);
    fill_geometry(mesh, d);
    return d;
}

void update_dual_metrics(const Mesh& mesh, DualMetrics& dual) {
    if (!belongs_to(mesh, dual))
        throw InputError(fmt::format(
            "{}: update_dual_metrics: the metrics ({} nodes, {} markers) do not belong to the mesh "
            "({} nodes, {} markers); expected metrics from compute_dual_metrics of this mesh",
            mesh.source(), dual.dual_volumes.size(), dual.boundary.size(), mesh.n_nodes(),
            mesh.n_markers()));
    fill_geometry(mesh, dual);
}

void DualFaceValues::resize_for(const DualMetrics& dual) {
    edges.assign(static_cast<std::size_t>(dual.n_edges()), 0.0);
    boundary.resize(dual.boundary.size());
    for (std::size_t mk = 0; mk < dual.boundary.size(); ++mk)
        boundary[mk].assign(dual.boundary[mk].nodes.size(), 0.0);
}

bool DualFaceValues::fits(const DualMetrics& dual) const noexcept {
    if (edges.size() != static_cast<std::size_t>(dual.n_edges()) ||
        boundary.size() != dual.boundary.size())
        return false;
    for (std::size_t mk = 0; mk < boundary.size(); ++mk)
        if (boundary[mk].size() != dual.boundary[mk].nodes.size()) return false;
    return true;
}

void swept_volumes(const Mesh& mesh, const DualMetrics& dual, std::span<const double> x_a,
                   std::span<const double> x_b, DualFaceValues& out) {
    const auto n3 = 3 * static_cast<std::size_t>(mesh.n_nodes());
    if (x_a.size() != n3 || x_b.size() != n3)
        throw InputError(
            fmt::format("{}: swept_volumes: {} and {} coordinates; expected {} each (3 per node)",
                        mesh.source(), x_a.size(), x_b.size(), n3));
    if (!belongs_to(mesh, dual))
        throw InputError(fmt::format(
            "{}: swept_volumes: the metrics ({} nodes, {} markers) do not belong to the mesh "
            "({} nodes, {} markers)",
            mesh.source(), dual.dual_volumes.size(), dual.boundary.size(), mesh.n_nodes(),
            mesh.n_markers()));
    out.resize_for(dual);
    // Interior: the triangle (m_pq, c_cell, c_f) of each face edge p->q, area vector
    // (c_cell - m) x (c_f - m) / 2 oriented p->q (as in the metrics).
    std::array<Eigen::Vector3d, 8> a, b;
    const Index* slot = dual.cell_face_edges.data();
    for (Index c = 0; c < mesh.n_cells(); ++c) {
        const auto nodes = mesh.cell(c);
        const auto nc = nodes.size();
        Eigen::Vector3d cca = Eigen::Vector3d::Zero(), ccb = Eigen::Vector3d::Zero();
        for (std::size_t k = 0; k < nc; ++k) {
            a[k] = at(x_a, nodes[k]);
            b[k] = at(x_b, nodes[k]);
            cca += a[k];
            ccb += b[k];
        }
        cca /= static_cast<double>(nc);
        ccb /= static_cast<double>(nc);
        for (const auto& f : cell_faces(mesh.cell_type(c))) {
            const int nf = f[3] < 0 ? 3 : 4;
            Eigen::Vector3d cfa = Eigen::Vector3d::Zero(), cfb = Eigen::Vector3d::Zero();
            for (int k = 0; k < nf; ++k) {
                cfa += a[f[k]];
                cfb += b[f[k]];
            }
            cfa /= nf;
            cfb /= nf;
            for (int k = 0; k < nf; ++k) {
                const int lp = f[k], lq = f[(k + 1) % nf];
                const Index p = nodes[lp], q = nodes[lq];
                const Eigen::Vector3d ma = 0.5 * (a[lp] + a[lq]), mb = 0.5 * (b[lp] + b[lq]);
                const double s = swept(ma, cca, cfa, mb, ccb, cfb);
                const auto e = static_cast<std::size_t>(*slot++);
                out.edges[e] += p < q ? s : -s;
            }
        }
    }
    // Boundary: the triangles (p, m_pq, c_f) and (q, c_f, m_pq) of each outward boundary face.
    const Index* bslot = dual.boundary_face_slots.data();
    for (Index f = 0; f < mesh.n_faces(); ++f) {
        const int mk = mesh.face_marker(f);
        auto& sb = out.boundary[static_cast<std::size_t>(mk)];
        const auto nodes = mesh.face(f);
        const auto nf = nodes.size();
        const Index* face_slots = bslot;
        bslot += nf;
        Eigen::Vector3d cfa = Eigen::Vector3d::Zero(), cfb = Eigen::Vector3d::Zero();
        for (std::size_t k = 0; k < nf; ++k) {
            a[k] = at(x_a, nodes[k]);
            b[k] = at(x_b, nodes[k]);
            cfa += a[k];
            cfb += b[k];
        }
        cfa /= static_cast<double>(nf);
        cfb /= static_cast<double>(nf);
        for (std::size_t k = 0; k < nf; ++k) {
            const std::size_t kq = (k + 1) % nf;
            const Eigen::Vector3d ma = 0.5 * (a[k] + a[kq]), mb = 0.5 * (b[k] + b[kq]);
            sb[static_cast<std::size_t>(face_slots[k])] += swept(a[k], ma, cfa, b[k], mb, cfb);
            sb[static_cast<std::size_t>(face_slots[kq])] += swept(a[kq], cfa, ma, b[kq], cfb, mb);
        }
    }
}

double max_swept_volume_defect(const DualMetrics& dual, std::span<const double> v_a,
                               std::span<const double> v_b, const DualFaceValues& swept) {
    const std::size_t nn = dual.dual_volumes.size();
    if (v_a.size() != nn || v_b.size() != nn || !swept.fits(dual))
        throw InputError(fmt::format(
            "max_swept_volume_defect: {} and {} volumes for {} nodes, or swept volumes of "
            "another mesh; expected one volume per node and values from swept_volumes",
            v_a.size(), v_b.size(), nn));
    std::vector<double> sum(nn, 0.0);
    for (Index e = 0; e < dual.n_edges(); ++e) {
        const auto [i, j] = dual.edges[static_cast<std::size_t>(e)];
        sum[static_cast<std::size_t>(i)] += swept.edges[static_cast<std::size_t>(e)];
        sum[static_cast<std::size_t>(j)] -= swept.edges[static_cast<std::size_t>(e)];
    }
    for (std::size_t mk = 0; mk < dual.boundary.size(); ++mk)
        for (std::size_t k = 0; k < dual.boundary[mk].nodes.size(); ++k)
            sum[static_cast<std::size_t>(dual.boundary[mk].nodes[k])] += swept.boundary[mk][k];
    double worst = 0.0, vmax = 0.0;
    for (std::size_t n = 0; n < nn; ++n) {
        worst = std::max(worst, std::abs(v_b[n] - v_a[n] - sum[n]));
        vmax = std::max(vmax, std::abs(v_b[n]));
    }
    return vmax > 0.0 ? worst / vmax : worst;
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
