/// @file rotating_frame.cpp
/// Grid fluxes and source of a frame rotating with the mesh (rotating_frame.hpp).

#include "manta/euler/rotating_frame.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>

#include "manta/core/frames.hpp"

namespace manta::euler {

namespace {

/// Number of edge (a, b) in the sorted edge list (the edge must exist).
Index find_edge(const mesh::DualMetrics& d, Index a, Index b) {
    if (a > b) std::swap(a, b);
    const std::array<Index, 2> key{a, b};
    return static_cast<Index>(std::lower_bound(d.edges.begin(), d.edges.end(), key) -
                              d.edges.begin());
}

Index local_index(const mesh::BoundaryVertices& bv, Index n) {
    return static_cast<Index>(std::lower_bound(bv.nodes.begin(), bv.nodes.end(), n) -
                              bv.nodes.begin());
}

/// Flux of v_g through the flat triangle (a, b, c) along its area vector (b - a) x (c - a) / 2:
/// v_g at the centroid (exact for a linear field).
double triangle_flux(const RotatingFrame& f, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 centroid = (a + b + c) / 3.0;
    return f.omega.cross(centroid - f.center).dot(0.5 * (b - a).cross(c - a));
}

}  // namespace

void rotation_grid_fluxes(const mesh::Mesh& mesh, const mesh::DualMetrics& dual,
                          const RotatingFrame& frame, mesh::DualFaceValues& g) {
    g.resize_for(dual);
    // The triangles of mesh/dual.cpp: per face edge p->q of each cell face, (m_pq, c_cell, c_f)
    // with area vector (c_cell - m) x (c_f - m) / 2 oriented p->q; per boundary face,
    // (p, m_pq, c_f) for p and (q, c_f, m_pq) for q, outward.
    for (Index c = 0; c < mesh.n_cells(); ++c) {
        const auto nodes = mesh.cell(c);
        Vec3 cc = Vec3::Zero();
        for (Index n : nodes) cc += mesh.node(n);
        cc /= static_cast<double>(nodes.size());
        for (const auto& f : mesh::cell_faces(mesh.cell_type(c))) {
            const int nf = f[3] < 0 ? 3 : 4;
            Vec3 cf = Vec3::Zero();
            for (int k = 0; k < nf; ++k) cf += mesh.node(nodes[f[k]]);
            cf /= nf;
            for (int k = 0; k < nf; ++k) {
                const Index p = nodes[f[k]];
                const Index q = nodes[f[(k + 1) % nf]];
                const Vec3 m = 0.5 * (mesh.node(p) + mesh.node(q));
                const double s = triangle_flux(frame, m, cc, cf);
                const auto e = static_cast<std::size_t>(find_edge(dual, p, q));
                g.edges[e] += p < q ? s : -s;
            }
        }
    }
    for (Index f = 0; f < mesh.n_faces(); ++f) {
        const auto mk = static_cast<std::size_t>(mesh.face_marker(f));
        const mesh::BoundaryVertices& bv = dual.boundary[mk];
        auto& gb = g.boundary[mk];
        const auto nodes = mesh.face(f);
        const auto nf = nodes.size();
        Vec3 cf = Vec3::Zero();
        for (Index n : nodes) cf += mesh.node(n);
        cf /= static_cast<double>(nf);
        for (std::size_t k = 0; k < nf; ++k) {
            const Index p = nodes[k], q = nodes[(k + 1) % nf];
            const Vec3 xp = mesh.node(p), xq = mesh.node(q);
            const Vec3 m = 0.5 * (xp + xq);
            gb[static_cast<std::size_t>(local_index(bv, p))] += triangle_flux(frame, xp, m, cf);
            gb[static_cast<std::size_t>(local_index(bv, q))] += triangle_flux(frame, xq, cf, m);
        }
    }
}

void rotation_node_velocities(const mesh::Mesh& mesh, const RotatingFrame& frame,
                              Eigen::Matrix3Xd& v) {
    v.resize(3, mesh.n_nodes());
    for (Index n = 0; n < mesh.n_nodes(); ++n)
        v.col(n) = frame.omega.cross(mesh.node(n) - frame.center);
}

void rotation_source(const NodeStates& U, const std::vector<double>& volumes,
                     const RotatingFrame& frame, const Vec3& u_inf, Index n_owned, NodeStates& S) {
    S.setZero(5, U.cols());
    const Vec3& w = frame.omega;
    const Vec3 w_x_uinf = w.cross(u_inf);
    const Vec3 uinf_x_w = u_inf.cross(w);
    for (Index i = 0; i < n_owned; ++i) {
        const double V = volumes[static_cast<std::size_t>(i)];
        const Vec3 m = U.col(i).segment<3>(1);
        // Right-hand side per volume: momentum -omega x (m - rho u_inf), energy
        // m . (omega x u_inf) = -(u_inf x omega) . m.
        S.col(i).segment<3>(1) = -V * (w.cross(m) - U(0, i) * w_x_uinf);
        S(4, i) = -V * uinf_x_w.dot(m);
    }
}

bool rotates(const BodyRates& r) noexcept {
    return r[0] != 0.0 || r[1] != 0.0 || r[2] != 0.0;
}

RotatingFrame body_rate_frame(const BodyRates& r, double mach, double span, double chord,
                              const Vec3& center) {
    // Body-axis rates from the non-dimensional ones (free-stream speed = Mach in the solver's
    // units), turned into mesh axes.
    const double V = mach;
    const Vec3 body(r[0] * 2.0 * V / span, r[1] * 2.0 * V / chord, r[2] * 2.0 * V / span);
    RotatingFrame frame;
    frame.omega = core::geometry_from_body(body);
    frame.center = center;
    return frame;
}

std::optional<SymmetryCrossing> symmetry_crossing(const RotatingFrame& frame,
                                                  const std::vector<BoundaryKind>& roles,
                                                  const mesh::DualMetrics& dual) {
    if (!frame.active()) return std::nullopt;
    const Vec3 axis = frame.omega.normalized();
    for (std::size_t mk = 0; mk < roles.size() && mk < dual.boundary.size(); ++mk) {
        if (roles[mk] != BoundaryKind::symmetry) continue;
        const auto& normals = dual.boundary[mk].normals;
        for (Index k = 0; k < normals.cols(); ++k) {
            const double a = normals.col(k).norm();
            if (a > 0.0 && axis.cross(normals.col(k) / a).norm() > 1e-6)
                return SymmetryCrossing{mk, dual.boundary[mk].nodes[static_cast<std::size_t>(k)],
                                        normals.col(k) / a};
        }
    }
    return std::nullopt;
}

std::string symmetry_crossing_message(const std::string& who,
                                      const std::array<std::string, 3>& names, const BodyRates& r,
                                      const std::string& mesh, const std::string& marker,
                                      const Vec3& normal, long long node) {
    return fmt::format(
        "{}: {} {:g}, {} {:g}, {} {:g} turn the mesh {} through its symmetry plane '{}' (normal "
        "({:.3g}, {:.3g}, {:.3g}) at node {}), which mirrors the flow; expected a rotation about "
        "the plane's normal only (q_hat on a half model with the plane y = 0) or a mesh of the "
        "whole aircraft",
        who, names[0], r[0], names[1], r[1], names[2], r[2], mesh, marker, normal.x(), normal.y(),
        normal.z(), node);
}

}  // namespace manta::euler
