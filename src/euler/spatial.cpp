/// @file spatial.cpp
/// The edge-based residual (spatial.hpp): four sweeps per second-order residual, each over flat
/// arrays: primitive states (nodes), gradient sums and neighbourhood extrema (edges), the
/// limiter (edges), one halo exchange of gradients and limiters, then the fluxes (edges) and
/// the boundary fluxes (boundary nodes). JST: one node sweep (Laplacians, sensor, spectral
/// radii; edges), one halo exchange, then the central fluxes with their dissipation (edges).

#include "manta/euler/spatial.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

#include "manta/core/error.hpp"

namespace manta::euler {

using mesh::Index;

namespace {

/// Values per node in the gradient-and-limiter array: the 5x3 gradient then the 5 limiters.
constexpr int n_gp = 20;
constexpr int phi_offset = 15;

/// Venkatakrishnan's limiter function for an increment `d2` (= grad . dx / 2) toward a face
/// and the neighbourhood's extreme difference `d1` (max - W_i if d2 > 0, min - W_i if d2 < 0):
/// phi = [(d1^2 + eps2) + 2 d1 d2] / [d1^2 + 2 d2^2 + d1 d2 + eps2] (Venkatakrishnan 1995,
/// J. Comput. Phys. 118: his limiter function divided by d2).
inline double venkatakrishnan(double d1, double d2, double eps2) noexcept {
    const double d1s = d1 * d1 + eps2;
    return (d1s + 2.0 * d1 * d2) / (d1s + d2 * (2.0 * d2 + d1));
}

inline void load3(const double* p, double& a, double& b, double& c) noexcept {
    a = p[0];
    b = p[1];
    c = p[2];
}

/// Newell's area vector of the (possibly non-planar) boundary face `f`.
Vec3 face_area(const mesh::Mesh& m, Index f) {
    const auto nodes = m.face(f);
    Vec3 a = Vec3::Zero();
    for (std::size_t k = 0; k < nodes.size(); ++k)
        a += m.node(nodes[k]).cross(m.node(nodes[(k + 1) % nodes.size()]));
    return Vec3(0.5 * a);
}

}  // namespace

void SpatialOptions::validate() const {
    if (order != 1 && order != 2)
        throw ConfigError(fmt::format(
            "numerics.order = {}; expected 1 (first order) or 2 (MUSCL reconstruction)", order));
    if (!(venkatakrishnan_k > 0.0) || !std::isfinite(venkatakrishnan_k))
        throw ConfigError(fmt::format(
            "numerics.venkatakrishnan_k = {}; expected a finite number > 0 (usual range 0.3 to 10)",
            venkatakrishnan_k));
    if (!(sharp_edge_deg > 0.0 && sharp_edge_deg < 180.0))
        throw ConfigError(fmt::format(
            "numerics.sharp_edge_deg = {}; expected an angle in (0, 180) degrees", sharp_edge_deg));
    if (!(flux.entropy_fix >= 0.0 && flux.entropy_fix <= 1.0))
        throw ConfigError(fmt::format(
            "numerics.entropy_fix = {}; expected a fraction of the spectral radius in [0, 1]",
            flux.entropy_fix));
    if (!(flux.jst_k2 >= 0.0 && flux.jst_k2 <= 2.0))
        throw ConfigError(fmt::format(
            "numerics.jst_k2 = {}; expected a number in [0, 2] (SU2's default 0.5)", flux.jst_k2));
    if (!(flux.jst_k4 >= 0.0 && flux.jst_k4 <= 0.5))
        throw ConfigError(
            fmt::format("numerics.jst_k4 = {}; expected a number in [0, 0.5] (SU2's default 0.02)",
                        flux.jst_k4));
}

SpatialOperator::SpatialOperator(const Domain& d, std::vector<BoundaryKind> kinds,
                                 const Vec5& W_inf, double gamma, const SpatialOptions& o)
    : domain_(d), kinds_(std::move(kinds)), W_inf_(W_inf), gamma_(gamma), options_(o) {
    options_.validate();
    if (d.mesh == nullptr || d.dual == nullptr || d.halo == nullptr)
        throw InputError(
            "euler spatial operator: the domain needs a mesh, its dual metrics and a halo");
    const mesh::Mesh& m = *d.mesh;
    const mesh::DualMetrics& dual = *d.dual;
    n_local_ = m.n_nodes();
    if (static_cast<Index>(dual.dual_volumes.size()) != n_local_ ||
        static_cast<int>(dual.boundary.size()) != m.n_markers())
        throw InputError(
            fmt::format("{}: the dual metrics ({} nodes, {} markers) do not belong to the mesh "
                        "({} nodes, {} markers)",
                        m.source(), dual.dual_volumes.size(), dual.boundary.size(), m.n_nodes(),
                        m.n_markers()));
    if (d.n_owned < 0 || d.n_owned > n_local_)
        throw InputError(fmt::format("{}: {} owned nodes; expected 0 to {} (the local nodes)",
                                     m.source(), d.n_owned, n_local_));
    if (static_cast<int>(kinds_.size()) != m.n_markers())
        throw InputError(
            fmt::format("{}: {} boundary kinds given for {} markers; expected one per marker",
                        m.source(), kinds_.size(), m.n_markers()));
    if (!(gamma > 1.0) || !std::isfinite(gamma))
        throw InputError(fmt::format("euler gamma = {}; expected a finite number > 1", gamma));
    if (!(W_inf[0] > 0.0) || !(W_inf[4] > 0.0) || !W_inf.allFinite())
        throw InputError(
            fmt::format("euler free stream (rho {}, p {}); expected finite values, rho > 0, p > 0",
                        W_inf[0], W_inf[4]));

    // Edges are sorted by their first node and i < j: the edges with an owned node come first.
    const auto first_ghost_edge =
        std::partition_point(dual.edges.begin(), dual.edges.end(),
                             [n = d.n_owned](const std::array<Index, 2>& e) { return e[0] < n; });
    n_edges_active_ = static_cast<Index>(first_ghost_edge - dual.edges.begin());

    const auto nl = static_cast<std::size_t>(n_local_);
    const auto no = static_cast<std::size_t>(d.n_owned);
    W_.assign(5 * nl, 0.0);
    const bool jst = options_.flux.scheme == FluxScheme::jst;
    if (jst) init_jst();
    if (options_.resolved_wall() == WallTangency::mixed) init_sharp_edges();
    if (options_.strong_walls()) init_wall_tangency();
    if (options_.order == 2 && !jst) {
        gp_.assign(n_gp * nl, 0.0);
        for (std::size_t n = 0; n < nl; ++n)
            std::fill_n(gp_.begin() + static_cast<std::ptrdiff_t>(n_gp * n + phi_offset), 5, 1.0);
        if (options_.limiter) minmax_.assign(10 * no, 0.0);
        // Unit normals of the owned nodes on symmetry planes (and walls with strong tangency),
        // for the mirrored gradients.
        for (std::size_t mk = 0; mk < dual.boundary.size(); ++mk) {
            // Walls too with strong tangency, for the density and pressure gradients only
            // (spatial.hpp).
            if (kinds_[mk] != BoundaryKind::symmetry &&
                !(kinds_[mk] == BoundaryKind::wall && options_.strong_walls()))
                continue;
            const mesh::BoundaryVertices& bv = dual.boundary[mk];
            for (std::size_t k = 0; k < bv.nodes.size() && bv.nodes[k] < d.n_owned; ++k) {
                const Vec3 n = bv.normals.col(static_cast<Index>(k));
                const double a = n.norm();
                if (!(a > 0.0)) continue;
                if (kinds_[mk] == BoundaryKind::wall && is_sharp(bv.nodes[k])) continue;
                symmetry_nodes_.push_back(bv.nodes[k]);
                symmetry_is_wall_.push_back(kinds_[mk] == BoundaryKind::wall ? 1 : 0);
                symmetry_sources_.push_back({static_cast<Index>(mk), static_cast<Index>(k)});
                for (int c = 0; c < 3; ++c) symmetry_normals_.push_back(n[c] / a);
            }
        }
    }
    if (options_.order == 2 && !jst && options_.gradient == GradientMethod::least_squares) {
        lsq_.assign(6 * no, 0.0);
        compute_least_squares();
    }
}

void SpatialOperator::compute_least_squares() {
    // Normal matrices M_i = sum_j w dx dx^T, w = 1 / |dx|^2, over the edges of owned nodes,
    // summed in lsq_ and inverted there.
    const mesh::DualMetrics& dual = *domain_.dual;
    const Index no = domain_.n_owned;
    std::fill(lsq_.begin(), lsq_.end(), 0.0);
    double* M = lsq_.data();
    const double* x = domain_.mesh->coordinates().data();
    const auto add = [M](Index n, double dx, double dy, double dz, double w) {
        double* a = M + 6 * static_cast<std::size_t>(n);
        a[0] += w * dx * dx;
        a[1] += w * dx * dy;
        a[2] += w * dx * dz;
        a[3] += w * dy * dy;
        a[4] += w * dy * dz;
        a[5] += w * dz * dz;
    };
    for (Index e = 0; e < n_edges_active_; ++e) {
        const auto [i, j] = dual.edges[e];
        const double dx = x[3 * j] - x[3 * i], dy = x[3 * j + 1] - x[3 * i + 1],
                     dz = x[3 * j + 2] - x[3 * i + 2];
        const double w = 1.0 / (dx * dx + dy * dy + dz * dz);
        add(i, dx, dy, dz, w);
        if (j < no) add(j, dx, dy, dz, w);
    }
    for (std::size_t n = 0; n < static_cast<std::size_t>(no); ++n) {
        double* a = M + 6 * n;
        Eigen::Matrix3d A;
        A << a[0], a[1], a[2], a[1], a[3], a[4], a[2], a[4], a[5];
        // The weighted directions are unit vectors: trace(A) = number of neighbours. A node
        // whose neighbours span less than three dimensions (never in a valid 3-D mesh) gets
        // the pseudo-inverse, i.e. the gradient in the directions it can see.
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(A);
        const Eigen::Vector3d l = es.eigenvalues();
        const double tol = 1e-10 * std::max(l.maxCoeff(), 1e-300);
        Eigen::Vector3d inv_l;
        for (int k = 0; k < 3; ++k) inv_l[k] = l[k] > tol ? 1.0 / l[k] : 0.0;
        const Eigen::Matrix3d Ai =
            es.eigenvectors() * inv_l.asDiagonal() * es.eigenvectors().transpose();
        a[0] = Ai(0, 0);
        a[1] = Ai(0, 1);
        a[2] = Ai(0, 2);
        a[3] = Ai(1, 1);
        a[4] = Ai(1, 2);
        a[5] = Ai(2, 2);
    }
}

void SpatialOperator::refresh_symmetry_normals() {
    const mesh::DualMetrics& dual = *domain_.dual;
    for (std::size_t s = 0; s < symmetry_sources_.size(); ++s) {
        const auto [mk, k] = symmetry_sources_[s];
        const Vec3 n = dual.boundary[static_cast<std::size_t>(mk)].normals.col(k);
        const double a = n.norm();
        for (int c = 0; c < 3; ++c) symmetry_normals_[3 * s + c] = a > 0.0 ? n[c] / a : 0.0;
    }
}

void SpatialOperator::update_geometry() {
    const mesh::Mesh& m = *domain_.mesh;
    const mesh::DualMetrics& dual = *domain_.dual;
    if (static_cast<Index>(dual.dual_volumes.size()) != n_local_ ||
        static_cast<int>(dual.boundary.size()) != m.n_markers() || m.n_nodes() != n_local_)
        throw InputError(fmt::format(
            "{}: update_geometry: the dual metrics ({} nodes, {} markers) no longer belong to the "
            "mesh ({} nodes, {} markers); expected the operator's mesh and metrics, updated in "
            "place",
            m.source(), dual.dual_volumes.size(), dual.boundary.size(), m.n_nodes(),
            m.n_markers()));
    if (!lsq_.empty()) compute_least_squares();
    refresh_symmetry_normals();
    if (!sharp_sides_.empty()) refresh_sharp_sides();
    if (options_.strong_walls()) refresh_wall_tangency();
}

void SpatialOperator::set_grid_fluxes(const mesh::DualFaceValues* g,
                                      const Eigen::Matrix3Xd* node_velocities) {
    const mesh::DualMetrics& dual = *domain_.dual;
    if (g != nullptr && !g->fits(dual))
        throw InputError(fmt::format(
            "{}: grid fluxes for {} edges and {} markers; expected one per edge ({}) and one per "
            "boundary vertex of each of the {} markers (mesh::DualFaceValues::resize_for)",
            domain_.mesh->source(), g->edges.size(), g->boundary.size(), dual.n_edges(),
            dual.boundary.size()));
    if (node_velocities != nullptr && node_velocities->cols() != n_local_)
        throw InputError(
            fmt::format("{}: {} node grid velocities; expected one per local node ({})",
                        domain_.mesh->source(), node_velocities->cols(), n_local_));
    grid_ = g;
    grid_velocity_ = g != nullptr ? node_velocities : nullptr;
    if (options_.strong_walls()) refresh_wall_tangency();
}

std::size_t SpatialOperator::memory_bytes() const noexcept {
    return (W_.capacity() + gp_.capacity() + minmax_.capacity() + lsq_.capacity() +
            symmetry_normals_.capacity() + jst_.capacity() + jst_neighbours_.capacity() +
            jst_work_.capacity()) *
               sizeof(double) +
           symmetry_nodes_.capacity() * sizeof(Index) + kinds_.capacity() * sizeof(BoundaryKind) +
           jst_boundary_.capacity() + sharp_.capacity() +
           sharp_sides_.capacity() * sizeof(SharpNode) +
           sharp_faces_.capacity() * sizeof(sharp_faces_[0]) +
           symmetry_sources_.capacity() * sizeof(symmetry_sources_[0]) +
           tangency_.capacity() * sizeof(TangencyNode) +
           tangency_sources_.capacity() * sizeof(tangency_sources_[0]);
}

BlockMatrix SpatialOperator::make_jacobian_matrix() const {
    return {domain_.n_owned, n_local_, domain_.dual->edges};
}

Eigen::Matrix<double, 5, 3> SpatialOperator::gradient(Index n) const {
    Eigen::Matrix<double, 5, 3> g = Eigen::Matrix<double, 5, 3>::Zero();
    if (gp_.empty()) return g;
    const double* p = gp_.data() + n_gp * static_cast<std::size_t>(n);
    for (int k = 0; k < 5; ++k)
        for (int c = 0; c < 3; ++c) g(k, c) = p[3 * k + c];
    return g;
}

Vec5 SpatialOperator::limiter(Index n) const {
    if (gp_.empty()) return Vec5::Ones();
    return Eigen::Map<const Vec5>(gp_.data() + n_gp * static_cast<std::size_t>(n) + phi_offset);
}

void SpatialOperator::set_limiter(Index n, const Vec5& phi) {
    if (gp_.empty() || !options_.limiter) return;
    Eigen::Map<Vec5>(gp_.data() + n_gp * static_cast<std::size_t>(n) + phi_offset) = phi;
}

void SpatialOperator::compute_primitive(const NodeStates& U) {
    MANTA_REQUIRE(U.cols() == n_local_, "euler residual: U needs one column per local node");
    const double g1 = gamma_ - 1.0;
    const double* u = U.data();
    double* w = W_.data();
    for (Index n = 0; n < n_local_; ++n, u += 5, w += 5) {
        const double inv = 1.0 / u[0];
        const double vx = u[1] * inv, vy = u[2] * inv, vz = u[3] * inv;
        w[0] = u[0];
        w[1] = vx;
        w[2] = vy;
        w[3] = vz;
        w[4] = g1 * (u[4] - 0.5 * u[0] * (vx * vx + vy * vy + vz * vz));
    }
}

void SpatialOperator::compute_gradients() {
    const mesh::DualMetrics& dual = *domain_.dual;
    const Index no = domain_.n_owned;
    const double* x = domain_.mesh->coordinates().data();
    const double* W = W_.data();
    const double* sn = dual.edge_normals.data();
    const auto* edges = dual.edges.data();
    const bool lsq = options_.gradient == GradientMethod::least_squares;
    const bool extrema = options_.limiter && !frozen_;
    double* gp = gp_.data();
    double* mm = minmax_.data();

    for (Index n = 0; n < no; ++n) {
        std::fill_n(gp + n_gp * static_cast<std::size_t>(n), 15, 0.0);
        if (extrema) {
            std::copy_n(W + 5 * static_cast<std::size_t>(n), 5, mm + 10 * n);
            std::copy_n(W + 5 * static_cast<std::size_t>(n), 5, mm + 10 * n + 5);
        }
    }

    // Sums over the edges: least squares sum_j w dx (W_j - W_i) (the same for both nodes:
    // dx and dW both change sign); Green-Gauss sum_j (W_j - W_i) n_ij / 2 (n_ji = -n_ij).
    for (Index e = 0; e < n_edges_active_; ++e) {
        const Index i = edges[e][0], j = edges[e][1];
        double ax, ay, az;  // the weighted direction of the differences
        if (lsq) {
            const double dx = x[3 * j] - x[3 * i], dy = x[3 * j + 1] - x[3 * i + 1],
                         dz = x[3 * j + 2] - x[3 * i + 2];
            const double w = 1.0 / (dx * dx + dy * dy + dz * dz);
            ax = w * dx;
            ay = w * dy;
            az = w * dz;
        } else {
            load3(sn + 3 * static_cast<std::size_t>(e), ax, ay, az);
            ax *= 0.5;
            ay *= 0.5;
            az *= 0.5;
        }
        const double* Wi = W + 5 * static_cast<std::size_t>(i);
        const double* Wj = W + 5 * static_cast<std::size_t>(j);
        double* gi = gp + n_gp * static_cast<std::size_t>(i);
        double* gj = gp + n_gp * static_cast<std::size_t>(j);
        const bool j_owned = j < no;
        for (int k = 0; k < 5; ++k) {
            const double dW = Wj[k] - Wi[k];
            gi[3 * k] += ax * dW;
            gi[3 * k + 1] += ay * dW;
            gi[3 * k + 2] += az * dW;
        }
        if (j_owned) {
            for (int k = 0; k < 5; ++k) {
                const double dW = Wj[k] - Wi[k];
                gj[3 * k] += ax * dW;
                gj[3 * k + 1] += ay * dW;
                gj[3 * k + 2] += az * dW;
            }
        }
        if (extrema) {
            double* mi = mm + 10 * static_cast<std::size_t>(i);
            for (int k = 0; k < 5; ++k) {
                mi[k] = std::min(mi[k], Wj[k]);
                mi[5 + k] = std::max(mi[5 + k], Wj[k]);
            }
            if (j_owned) {
                double* mj = mm + 10 * static_cast<std::size_t>(j);
                for (int k = 0; k < 5; ++k) {
                    mj[k] = std::min(mj[k], Wi[k]);
                    mj[5 + k] = std::max(mj[5 + k], Wi[k]);
                }
            }
        }
    }

    // Node step: least squares multiplies by the inverse normal matrix, Green-Gauss divides by
    // the dual volume.
    for (Index n = 0; n < no; ++n) {
        double* g = gp + n_gp * static_cast<std::size_t>(n);
        if (lsq) {
            const double* a = lsq_.data() + 6 * static_cast<std::size_t>(n);
            for (int k = 0; k < 5; ++k) {
                const double bx = g[3 * k], by = g[3 * k + 1], bz = g[3 * k + 2];
                g[3 * k] = a[0] * bx + a[1] * by + a[2] * bz;
                g[3 * k + 1] = a[1] * bx + a[3] * by + a[4] * bz;
                g[3 * k + 2] = a[2] * bx + a[4] * by + a[5] * bz;
            }
        } else {
            const double s = 1.0 / dual.dual_volumes[n];
            for (int k = 0; k < 15; ++k) g[k] *= s;
        }
    }
}

void SpatialOperator::mirror_symmetry_gradients() {
    for (std::size_t s = 0; s < symmetry_nodes_.size(); ++s) {
        const Eigen::Map<const Vec3> n(symmetry_normals_.data() + 3 * s);
        double* g = gp_.data() + n_gp * static_cast<std::size_t>(symmetry_nodes_[s]);
        // Scalars rho and p: (g + S g) / 2 = g - (g . n) n.
        for (int k : {0, 4}) {
            Eigen::Map<Vec3> gk(g + 3 * k);
            gk -= gk.dot(n) * n;
        }
        if (symmetry_is_wall_[s] != 0) continue;  // a wall: the scalars only
        // Velocity (rows u, v, w): (G + S G S) / 2 = G - (P G + G P) + 2 P G P, P = n n^T.
        Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> G(g + 3);
        const Vec3 Gn = G * n;                            // G P = Gn n^T
        const Eigen::RowVector3d nG = n.transpose() * G;  // P G = n nG
        const double nGn = nG.dot(n);
        G -= n * nG + Gn * n.transpose();
        G += 2.0 * nGn * n * n.transpose();
    }
}

void SpatialOperator::compute_limiter() {
    const mesh::DualMetrics& dual = *domain_.dual;
    const Index no = domain_.n_owned;
    const double* x = domain_.mesh->coordinates().data();
    const double* W = W_.data();
    const auto* edges = dual.edges.data();
    double* gp = gp_.data();
    const double* mm = minmax_.data();
    const double k3 =
        options_.venkatakrishnan_k * options_.venkatakrishnan_k * options_.venkatakrishnan_k;

    for (Index n = 0; n < no; ++n) std::fill_n(gp + n_gp * n + phi_offset, 5, 1.0);

    // One side of an edge: the increment toward the midpoint is s * grad . dx / 2.
    const auto side = [&](Index n, double dx, double dy, double dz) {
        double* g = gp + n_gp * static_cast<std::size_t>(n);
        const double* Wn = W + 5 * static_cast<std::size_t>(n);
        const double* m = mm + 10 * static_cast<std::size_t>(n);
        // eps^2 = (K h)^3 with h^3 = V (Venkatakrishnan 1995).
        const double eps2 = k3 * dual.dual_volumes[n];
        for (int k = 0; k < 5; ++k) {
            const double d2 = 0.5 * (g[3 * k] * dx + g[3 * k + 1] * dy + g[3 * k + 2] * dz);
            double phi = 1.0;
            if (d2 > 0.0)
                phi = venkatakrishnan(m[5 + k] - Wn[k], d2, eps2);
            else if (d2 < 0.0)
                phi = venkatakrishnan(m[k] - Wn[k], d2, eps2);
            g[phi_offset + k] = std::min(g[phi_offset + k], phi);
        }
    };
    for (Index e = 0; e < n_edges_active_; ++e) {
        const Index i = edges[e][0], j = edges[e][1];
        const double dx = x[3 * j] - x[3 * i], dy = x[3 * j + 1] - x[3 * i + 1],
                     dz = x[3 * j + 2] - x[3 * i + 2];
        side(i, dx, dy, dz);
        if (j < no) side(j, -dx, -dy, -dz);
    }
}

void SpatialOperator::add_boundary_fluxes(double* r) const {
    const mesh::DualMetrics& dual = *domain_.dual;
    const Index no = domain_.n_owned;
    const double* W = W_.data();
    for (std::size_t mk = 0; mk < dual.boundary.size(); ++mk) {
        const mesh::BoundaryVertices& bv = dual.boundary[mk];
        const BoundaryKind kind = kinds_[mk];
        const double* bn = bv.normals.data();
        const double* gb = grid_ != nullptr ? grid_->boundary[mk].data() : nullptr;
        // Nodes ascending: the owned ones come first.
        for (std::size_t k = 0; k < bv.nodes.size() && bv.nodes[k] < no; ++k) {
            const Index n = bv.nodes[k];
            const Vec5 Wn = Eigen::Map<const Vec5>(W + 5 * static_cast<std::size_t>(n));
            const Vec3 nv(bn[3 * k], bn[3 * k + 1], bn[3 * k + 2]);
            const double g = gb != nullptr ? gb[k] : 0.0;
            const Vec5 F = kind == BoundaryKind::farfield ? farfield_flux(Wn, W_inf_, nv, g, gamma_)
                                                          : wall_flux(Wn, nv, g, gamma_);
            Eigen::Map<Vec5>(r + 5 * static_cast<std::size_t>(n)) += F;
        }
    }
}

void SpatialOperator::init_sharp_edges() {
    const mesh::Mesh& m = *domain_.mesh;
    const Index no = domain_.n_owned;
    const auto face_area = [&m](Index f) { return euler::face_area(m, f); };
    // Node wall normals: sum of the adjacent wall faces' area vectors.
    std::vector<Vec3> nn(static_cast<std::size_t>(no), Vec3::Zero());
    for (Index f = 0; f < m.n_faces(); ++f) {
        if (kinds_[static_cast<std::size_t>(m.face_marker(f))] != BoundaryKind::wall) continue;
        const Vec3 a = face_area(f);
        for (Index n : m.face(f))
            if (n < no) nn[static_cast<std::size_t>(n)] += a;
    }
    // A node is sharp when a face's unit normal makes more than sharp_edge_deg with the node
    // normal; `ref` keeps the unit normal of its most deviating face.
    const double c = std::cos(options_.sharp_edge_deg * M_PI / 180.0);
    sharp_.assign(static_cast<std::size_t>(no), 0);
    std::vector<double> worst(static_cast<std::size_t>(no), 2.0);
    std::vector<Vec3> ref(static_cast<std::size_t>(no), Vec3::Zero());
    for (Index f = 0; f < m.n_faces(); ++f) {
        if (kinds_[static_cast<std::size_t>(m.face_marker(f))] != BoundaryKind::wall) continue;
        const Vec3 a = face_area(f);
        const double an = a.norm();
        if (!(an > 0.0)) continue;
        for (Index n : m.face(f)) {
            if (n >= no) continue;
            const auto i = static_cast<std::size_t>(n);
            const double Nn = nn[i].norm();
            const double cf = Nn > 0.0 ? a.dot(nn[i]) / (an * Nn) : -1.0;
            if (cf < worst[i]) {
                worst[i] = cf;
                ref[i] = a / an;
            }
        }
    }
    for (Index n = 0; n < no; ++n) {
        const auto i = static_cast<std::size_t>(n);
        if (worst[i] < c) sharp_[i] = 1;
    }
    // The two sides of each sharp node: its wall faces split by the sign of their normal's
    // component along `ref` (kept as the faces' sides for `update_geometry`), each side's normal
    // the sum of its faces' area vectors.
    sharp_sides_.clear();
    std::vector<Index> index(static_cast<std::size_t>(no), -1);
    for (Index n = 0; n < no; ++n)
        if (sharp_[static_cast<std::size_t>(n)] != 0) {
            index[static_cast<std::size_t>(n)] = static_cast<Index>(sharp_sides_.size());
            sharp_sides_.push_back({n, {Vec3::Zero(), Vec3::Zero()}});
        }
    sharp_faces_.clear();
    for (Index f = 0; f < m.n_faces(); ++f) {
        if (kinds_[static_cast<std::size_t>(m.face_marker(f))] != BoundaryKind::wall) continue;
        const Vec3 a = face_area(f);
        for (Index n : m.face(f)) {
            if (n >= no || sharp_[static_cast<std::size_t>(n)] == 0) continue;
            sharp_faces_.push_back({index[static_cast<std::size_t>(n)], f,
                                    a.dot(ref[static_cast<std::size_t>(n)]) > 0.0 ? 0 : 1});
        }
    }
    refresh_sharp_sides();
}

void SpatialOperator::refresh_sharp_sides() {
    const mesh::Mesh& m = *domain_.mesh;
    for (SharpNode& sn : sharp_sides_) sn.sides = {Vec3::Zero(), Vec3::Zero()};
    for (const auto& [s, f, side] : sharp_faces_)
        sharp_sides_[static_cast<std::size_t>(s)].sides[static_cast<std::size_t>(side)] +=
            face_area(m, f);
}

std::int64_t SpatialOperator::sharp_edge_nodes() const noexcept {
    return static_cast<std::int64_t>(std::count(sharp_.begin(), sharp_.end(), char{1}));
}

void SpatialOperator::init_wall_tangency() {
    const mesh::DualMetrics& dual = *domain_.dual;
    const Index no = domain_.n_owned;
    // Each owned node's wall and symmetry normals, in marker order (as (marker, k) references);
    // sharp-edge nodes of `mixed` tangency: first the difference b of the edge's two sides' unit
    // normals instead of the node's wall normal, then the symmetry normals.
    std::vector<int> sharp_index(static_cast<std::size_t>(no), -1);
    for (std::size_t s = 0; s < sharp_sides_.size(); ++s)
        sharp_index[static_cast<std::size_t>(sharp_sides_[s].node)] = static_cast<int>(s);
    std::vector<std::vector<std::array<Index, 2>>> sources(static_cast<std::size_t>(no));
    for (std::size_t mk = 0; mk < dual.boundary.size(); ++mk) {
        if (kinds_[mk] == BoundaryKind::farfield) continue;
        const mesh::BoundaryVertices& bv = dual.boundary[mk];
        for (std::size_t k = 0; k < bv.nodes.size() && bv.nodes[k] < no; ++k) {
            if (kinds_[mk] == BoundaryKind::wall && is_sharp(bv.nodes[k])) continue;
            const Vec3 n = bv.normals.col(static_cast<Index>(k));
            if (n.norm() > 0.0)
                sources[static_cast<std::size_t>(bv.nodes[k])].push_back(
                    {static_cast<Index>(mk), static_cast<Index>(k)});
        }
    }
    tangency_.clear();
    tangency_sources_.clear();
    for (Index i = 0; i < no; ++i) {
        const auto& src = sources[static_cast<std::size_t>(i)];
        int sharp = sharp_index[static_cast<std::size_t>(i)];
        if (sharp >= 0) {
            const SharpNode& sn = sharp_sides_[static_cast<std::size_t>(sharp)];
            if (!(sn.sides[0].norm() > 0.0) || !(sn.sides[1].norm() > 0.0) ||
                !((sn.sides[0].normalized() - sn.sides[1].normalized()).norm() > 0.0))
                sharp = -1;
        }
        if (src.empty() && sharp < 0) continue;
        TangencyNode t{i,
                       0,
                       {},
                       {},
                       sharp,
                       static_cast<std::int32_t>(tangency_sources_.size()),
                       static_cast<std::int32_t>(src.size())};
        tangency_sources_.insert(tangency_sources_.end(), src.begin(), src.end());
        tangency_.push_back(t);
    }
    refresh_wall_tangency();
}

void SpatialOperator::refresh_wall_tangency() {
    const mesh::DualMetrics& dual = *domain_.dual;
    // Gram-Schmidt over the node's directions (the sharp-edge bisector first); a normal within
    // about 3 degrees of the span of the earlier ones adds no condition (two markers meeting at a
    // shallow angle). Each direction carries its target, the grid velocity along it: from the
    // node velocity when given, else the marker face's normal speed g / |n| (orthonormalised with
    // the direction), and 0 for the sharp-edge bisector.
    for (TangencyNode& t : tangency_) {
        t.count = 0;
        t.b = {0.0, 0.0, 0.0};
        const auto add = [&t](const Vec3& n, double speed) {
            const double a = n.norm();
            if (!(a > 0.0)) return;
            Vec3 v = n.normalized();
            double s = speed;
            for (int k = 0; k < t.count; ++k) {
                const auto ks = static_cast<std::size_t>(k);
                const double c = t.e[ks].dot(v);
                v -= c * t.e[ks];
                s -= c * t.b[ks];
            }
            const double vn = v.norm();
            if (vn > 0.05 && t.count < 3) {
                t.b[static_cast<std::size_t>(t.count)] = s / vn;
                t.e[static_cast<std::size_t>(t.count++)] = v.normalized();
            }
        };
        if (t.sharp >= 0) {
            const SharpNode& sn = sharp_sides_[static_cast<std::size_t>(t.sharp)];
            add(sn.sides[0].normalized() - sn.sides[1].normalized(), 0.0);
        }
        for (std::int32_t q = t.first; q < t.first + t.n; ++q) {
            const auto [mk, k] = tangency_sources_[static_cast<std::size_t>(q)];
            const Vec3 n = dual.boundary[static_cast<std::size_t>(mk)].normals.col(k);
            double speed = 0.0;
            if (grid_ != nullptr && grid_velocity_ == nullptr) {
                const double a = n.norm();
                if (a > 0.0)
                    speed =
                        grid_->boundary[static_cast<std::size_t>(mk)][static_cast<std::size_t>(k)] /
                        a;
            }
            add(n, speed);
        }
        if (grid_velocity_ != nullptr) {
            const Vec3 v = grid_velocity_->col(t.node);
            for (int k = 0; k < t.count; ++k)
                t.b[static_cast<std::size_t>(k)] = v.dot(t.e[static_cast<std::size_t>(k)]);
        }
    }
}

void SpatialOperator::apply_wall_tangency(const NodeStates& U, const std::vector<double>& lambda,
                                          NodeStates& R) const {
    for (const TangencyNode& t : tangency_) {
        const double lam = lambda[static_cast<std::size_t>(t.node)];
        const Vec3 m = U.col(t.node).segment<3>(1);
        const double rho = U(0, t.node);
        Vec3 r = R.col(t.node).segment<3>(1);
        Vec3 c = Vec3::Zero();
        for (int k = 0; k < t.count; ++k) {
            const Vec3& e = t.e[static_cast<std::size_t>(k)];
            r -= e.dot(r) * e;
            // rho (u - v_grid) . e = 0 (the target b is 0 on a fixed mesh: bit for bit).
            c += lam * (e.dot(m) - rho * t.b[static_cast<std::size_t>(k)]) * e;
        }
        R.col(t.node).segment<3>(1) = r + c;
    }
}

void SpatialOperator::apply_wall_tangency(const std::vector<double>& lambda, double cfl,
                                          BlockMatrix& J) const {
    for (const TangencyNode& t : tangency_) {
        Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
        for (int k = 0; k < t.count; ++k)
            N += t.e[static_cast<std::size_t>(k)] * t.e[static_cast<std::size_t>(k)].transpose();
        Mat5 T = Mat5::Identity();
        T.block<3, 3>(1, 1) -= N;
        J.transform_row(t.node, T);
        Mat5 A = Mat5::Zero();
        const double lam = lambda[static_cast<std::size_t>(t.node)];
        A.block<3, 3>(1, 1) = (1.0 + 1.0 / cfl) * lam * N;
        // d(-lambda rho b_k e_k)/d rho of a moving wall.
        if (grid_ != nullptr)
            for (int k = 0; k < t.count; ++k)
                A.block<3, 1>(1, 0) -=
                    (lam * t.b[static_cast<std::size_t>(k)]) * t.e[static_cast<std::size_t>(k)];
        J.add_diagonal(t.node, A);
    }
}

void SpatialOperator::residual(const NodeStates& U, NodeStates& R) {
    compute_primitive(U);
    if (options_.flux.scheme == FluxScheme::jst) {
        residual_jst(R);
        return;
    }
    const bool second = options_.order == 2;
    if (second) {
        compute_gradients();
        mirror_symmetry_gradients();
        if (options_.limiter && !frozen_) compute_limiter();
        domain_.halo->exchange(gp_, n_gp);
    }

    if (R.cols() != n_local_) R.resize(5, n_local_);
    R.setZero();
    const mesh::DualMetrics& dual = *domain_.dual;
    const double* x = domain_.mesh->coordinates().data();
    const double* W = W_.data();
    const double* gp = gp_.data();
    const double* sn = dual.edge_normals.data();
    const double* ge = grid_ != nullptr ? grid_->edges.data() : nullptr;
    const auto* edges = dual.edges.data();
    double* r = R.data();
    std::int64_t fallbacks = 0;

    for (Index e = 0; e < n_edges_active_; ++e) {
        const Index i = edges[e][0], j = edges[e][1];
        const Vec3 nv(sn[3 * e], sn[3 * e + 1], sn[3 * e + 2]);
        const double g = ge != nullptr ? ge[e] : 0.0;
        Vec5 WL = Eigen::Map<const Vec5>(W + 5 * static_cast<std::size_t>(i));
        Vec5 WR = Eigen::Map<const Vec5>(W + 5 * static_cast<std::size_t>(j));
        Vec5 F;
        if (second) {
            const double dx = 0.5 * (x[3 * j] - x[3 * i]), dy = 0.5 * (x[3 * j + 1] - x[3 * i + 1]),
                         dz = 0.5 * (x[3 * j + 2] - x[3 * i + 2]);
            const double* gi = gp + n_gp * static_cast<std::size_t>(i);
            const double* gj = gp + n_gp * static_cast<std::size_t>(j);
            Vec5 L, Rr;
            for (int k = 0; k < 5; ++k) {
                L[k] = WL[k] + gi[phi_offset + k] *
                                   (gi[3 * k] * dx + gi[3 * k + 1] * dy + gi[3 * k + 2] * dz);
                Rr[k] = WR[k] - gj[phi_offset + k] *
                                    (gj[3 * k] * dx + gj[3 * k + 1] * dy + gj[3 * k + 2] * dz);
            }
            if (L[0] > 0.0 && L[4] > 0.0 && Rr[0] > 0.0 && Rr[4] > 0.0) {
                F = numerical_flux(L, Rr, nv, g, gamma_, options_.flux);
            } else {
                ++fallbacks;
                F = numerical_flux(WL, WR, nv, g, gamma_, options_.flux);
            }
        } else {
            F = numerical_flux(WL, WR, nv, g, gamma_, options_.flux);
        }
        Eigen::Map<Vec5>(r + 5 * static_cast<std::size_t>(i)) += F;
        Eigen::Map<Vec5>(r + 5 * static_cast<std::size_t>(j)) -= F;
    }
    n_fallbacks_ = fallbacks;

    add_boundary_fluxes(r);
    if (domain_.n_owned < n_local_) R.rightCols(n_local_ - domain_.n_owned).setZero();
}

void SpatialOperator::spectral_radii(const NodeStates& U, std::vector<double>& lambda) const {
    MANTA_REQUIRE(U.cols() == n_local_, "euler spectral radii: U needs one column per local node");
    const mesh::DualMetrics& dual = *domain_.dual;
    const Index no = domain_.n_owned;
    lambda.assign(static_cast<std::size_t>(no), 0.0);
    const double* sn = dual.edge_normals.data();
    const double* ge = grid_ != nullptr ? grid_->edges.data() : nullptr;
    for (Index e = 0; e < n_edges_active_; ++e) {
        const Index i = dual.edges[e][0], j = dual.edges[e][1];
        const Vec3 nv(sn[3 * e], sn[3 * e + 1], sn[3 * e + 2]);
        const double g = ge != nullptr ? ge[e] : 0.0;
        const double s = 0.5 * (spectral_radius(primitive(U.col(i), gamma_), nv, g, gamma_) +
                                spectral_radius(primitive(U.col(j), gamma_), nv, g, gamma_));
        lambda[i] += s;
        if (j < no) lambda[j] += s;
    }
    for (std::size_t mk = 0; mk < dual.boundary.size(); ++mk) {
        const mesh::BoundaryVertices& bv = dual.boundary[mk];
        const double* gb = grid_ != nullptr ? grid_->boundary[mk].data() : nullptr;
        for (std::size_t k = 0; k < bv.nodes.size() && bv.nodes[k] < no; ++k) {
            const Index n = bv.nodes[k];
            lambda[n] +=
                spectral_radius(primitive(U.col(n), gamma_), bv.normals.col(static_cast<Index>(k)),
                                gb != nullptr ? gb[k] : 0.0, gamma_);
        }
    }
}

void SpatialOperator::jacobian(const NodeStates& U, BlockMatrix& J) const {
    MANTA_REQUIRE(U.cols() == n_local_, "euler jacobian: U needs one column per local node");
    const mesh::DualMetrics& dual = *domain_.dual;
    const Index no = domain_.n_owned;
    MANTA_REQUIRE(J.n_rows() == no && J.n_cols() == n_local_,
                  "euler jacobian: J needs the pattern of make_jacobian_matrix");
    J.set_zero();
    if (options_.flux.scheme == FluxScheme::jst) {
        jacobian_jst(U, J);
        add_boundary_jacobians(U, J);
        return;
    }
    const double* sn = dual.edge_normals.data();
    const double* ge = grid_ != nullptr ? grid_->edges.data() : nullptr;
    Mat5 A, B;
    for (Index e = 0; e < n_edges_active_; ++e) {
        const Index i = dual.edges[e][0], j = dual.edges[e][1];
        const Vec3 nv(sn[3 * e], sn[3 * e + 1], sn[3 * e + 2]);
        const double g = ge != nullptr ? ge[e] : 0.0;
        flux_jacobians(primitive(U.col(i), gamma_), primitive(U.col(j), gamma_), nv, g, gamma_,
                       options_.flux, A, B);
        // R_i += F(U_i, U_j), R_j -= F(U_i, U_j).
        J.add_diagonal(i, A);
        J.add(J.edge_ij(e), B);
        J.add(J.edge_ji(e), -A);
        if (j < no) J.add_diagonal(j, -B);
    }
    add_boundary_jacobians(U, J);
}

void SpatialOperator::add_boundary_jacobians(const NodeStates& U, BlockMatrix& J) const {
    const mesh::DualMetrics& dual = *domain_.dual;
    const Index no = domain_.n_owned;
    Mat5 A;
    for (std::size_t mk = 0; mk < dual.boundary.size(); ++mk) {
        const mesh::BoundaryVertices& bv = dual.boundary[mk];
        const double* gb = grid_ != nullptr ? grid_->boundary[mk].data() : nullptr;
        for (std::size_t k = 0; k < bv.nodes.size() && bv.nodes[k] < no; ++k) {
            const Index n = bv.nodes[k];
            const Vec5 Wn = primitive(U.col(n), gamma_);
            const Vec3 nv = bv.normals.col(static_cast<Index>(k));
            const double g = gb != nullptr ? gb[k] : 0.0;
            if (kinds_[mk] == BoundaryKind::farfield) {
                (void)farfield_flux(Wn, W_inf_, nv, g, gamma_, &A);
                J.add_diagonal(n, A);
            } else {
                J.add_diagonal(n, wall_flux_jacobian(Wn, nv, g, gamma_));
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// JST (spatial.hpp): jst_ holds per local node L (5), nu, lambda, NL.

namespace {

constexpr int n_jst = 8;

/// V = (rho, rho u, rho v, rho w, rho H) of a primitive state; gg = gamma / (gamma - 1).
inline Vec5 jst_variables(const double* W, double gg) noexcept {
    Vec5 V;
    V[0] = W[0];
    V[1] = W[0] * W[1];
    V[2] = W[0] * W[2];
    V[3] = W[0] * W[3];
    V[4] = gg * W[4] + 0.5 * W[0] * (W[1] * W[1] + W[2] * W[2] + W[3] * W[3]);
    return V;
}

/// Spectral radius |u.n - g| + c |n| of a primitive state given as a pointer.
inline double radius(const double* W, const Vec3& n, double g, double gamma) noexcept {
    return std::abs(W[1] * n.x() + W[2] * n.y() + W[3] * n.z() - g) +
           std::sqrt(gamma * W[4] / W[0]) * n.norm();
}

/// dV/dU: the identity with the last row d(rho H)/dU = ((g-1) q^2/2, -(g-1) u, gamma).
inline Mat5 jst_transform(const Vec5& W, double gamma) noexcept {
    const double g1 = gamma - 1.0;
    Mat5 T = Mat5::Identity();
    T(4, 0) = 0.5 * g1 * (W[1] * W[1] + W[2] * W[2] + W[3] * W[3]);
    T(4, 1) = -g1 * W[1];
    T(4, 2) = -g1 * W[2];
    T(4, 3) = -g1 * W[3];
    T(4, 4) = gamma;
    return T;
}

/// The JST edge coefficients: e2, e4 and S l_ij (the stretching factor times the edge's
/// spectral radius). `ni`, `nj`: the nodes' (all) neighbour counts; `ti`, `tj`: their node
/// terms (jst_ entries); `li`, `lj`: the two nodes' spectral radii on the edge face.
struct JstCoefficients {
    double s2, e2, e4, s_lambda;
};
inline JstCoefficients jst_coefficients(double ni, double nj, const double* ti, const double* tj,
                                        double li, double lj, double k2, double k4) noexcept {
    const double s2 = 3.0 * (ni + nj) / (ni * nj);
    const double e2 = k2 * 0.5 * (ti[5] + tj[5]) * s2;
    const double e4 = std::max(0.0, k4 - e2) * 0.25 * s2 * s2;
    const double lij = 0.5 * (li + lj);
    double s_lambda = 0.0;
    if (lij > 0.0) {
        const double pi = std::pow(ti[6] / (4.0 * lij), 0.3);
        const double pj = std::pow(tj[6] / (4.0 * lij), 0.3);
        // Before any residual (lambda = 0) the stretching factor is taken as 1.
        const double S = pi + pj > 0.0 ? 4.0 * pi * pj / (pi + pj) : 1.0;
        s_lambda = S * lij;
    }
    return {s2, e2, e4, s_lambda};
}

}  // namespace

void SpatialOperator::init_jst() {
    const mesh::DualMetrics& dual = *domain_.dual;
    const Index no = domain_.n_owned;
    const auto nl = static_cast<std::size_t>(n_local_);
    jst_.assign(n_jst * nl, 0.0);
    jst_work_.assign(static_cast<std::size_t>(no), 0.0);
    // Boundary flags and neighbour counts of the owned nodes (their edges are all local), then
    // the ghosts' from their owners.
    std::vector<double> flags(2 * nl, 0.0);
    for (const mesh::BoundaryVertices& bv : dual.boundary)
        for (const Index n : bv.nodes)
            if (n < no) flags[2 * static_cast<std::size_t>(n)] = 1.0;
    for (Index e = 0; e < n_edges_active_; ++e) {
        const Index i = dual.edges[e][0], j = dual.edges[e][1];
        flags[2 * static_cast<std::size_t>(i) + 1] += 1.0;
        if (j < no) flags[2 * static_cast<std::size_t>(j) + 1] += 1.0;
    }
    domain_.halo->exchange(flags, 2);
    jst_boundary_.assign(nl, 0);
    jst_neighbours_.assign(nl, 0.0);
    for (std::size_t n = 0; n < nl; ++n) {
        jst_boundary_[n] = flags[2 * n] > 0.5 ? 1 : 0;
        jst_neighbours_[n] = std::max(flags[2 * n + 1], 1.0);
    }
}

void SpatialOperator::compute_jst_node_terms() {
    const mesh::DualMetrics& dual = *domain_.dual;
    const Index no = domain_.n_owned;
    const double gg = gamma_ / (gamma_ - 1.0);
    const double* W = W_.data();
    const double* sn = dual.edge_normals.data();
    const double* ge = grid_ != nullptr ? grid_->edges.data() : nullptr;
    double* t = jst_.data();
    double* den = jst_work_.data();
    std::fill_n(t, n_jst * static_cast<std::size_t>(no), 0.0);
    std::fill(jst_work_.begin(), jst_work_.end(), 0.0);
    for (Index e = 0; e < n_edges_active_; ++e) {
        const Index i = dual.edges[e][0], j = dual.edges[e][1];
        const double* Wi = W + 5 * static_cast<std::size_t>(i);
        const double* Wj = W + 5 * static_cast<std::size_t>(j);
        const Vec3 nv(sn[3 * e], sn[3 * e + 1], sn[3 * e + 2]);
        const double g = ge != nullptr ? ge[e] : 0.0;
        const double s = 0.5 * (radius(Wi, nv, g, gamma_) + radius(Wj, nv, g, gamma_));
        const bool bi = jst_boundary_[static_cast<std::size_t>(i)] != 0;
        const bool bj = jst_boundary_[static_cast<std::size_t>(j)] != 0;
        const Vec5 dV = jst_variables(Wj, gg) - jst_variables(Wi, gg);
        const double dp = Wj[4] - Wi[4], sp = Wj[4] + Wi[4];
        double* ti = t + n_jst * static_cast<std::size_t>(i);
        ti[6] += s;
        // A boundary node's Laplacian and sensor see only its boundary neighbours.
        if (!bi || bj) {
            for (int k = 0; k < 5; ++k) ti[k] += dV[k];
            ti[5] += dp;
            ti[7] += 1.0;
            den[i] += sp;
        }
        if (j < no) {
            double* tj = t + n_jst * static_cast<std::size_t>(j);
            tj[6] += s;
            if (!bj || bi) {
                for (int k = 0; k < 5; ++k) tj[k] -= dV[k];
                tj[5] -= dp;
                tj[7] += 1.0;
                den[j] += sp;
            }
        }
    }
    for (std::size_t mk = 0; mk < dual.boundary.size(); ++mk) {
        const mesh::BoundaryVertices& bv = dual.boundary[mk];
        const double* bn = bv.normals.data();
        const double* gb = grid_ != nullptr ? grid_->boundary[mk].data() : nullptr;
        for (std::size_t k = 0; k < bv.nodes.size() && bv.nodes[k] < no; ++k) {
            const Index n = bv.nodes[k];
            const Vec3 nv(bn[3 * k], bn[3 * k + 1], bn[3 * k + 2]);
            t[n_jst * static_cast<std::size_t>(n) + 6] += radius(
                W + 5 * static_cast<std::size_t>(n), nv, gb != nullptr ? gb[k] : 0.0, gamma_);
        }
    }
    for (Index n = 0; n < no; ++n) {
        double* tn = t + n_jst * static_cast<std::size_t>(n);
        tn[5] = den[n] > 0.0 ? std::abs(tn[5]) / den[n] : 0.0;
    }
    domain_.halo->exchange(jst_, n_jst);
}

void SpatialOperator::residual_jst(NodeStates& R) {
    compute_jst_node_terms();
    if (R.cols() != n_local_) R.resize(5, n_local_);
    R.setZero();
    const mesh::DualMetrics& dual = *domain_.dual;
    const double gg = gamma_ / (gamma_ - 1.0);
    const double k2 = options_.flux.jst_k2, k4 = options_.flux.jst_k4;
    const double* W = W_.data();
    const double* t = jst_.data();
    const double* sn = dual.edge_normals.data();
    const double* ge = grid_ != nullptr ? grid_->edges.data() : nullptr;
    double* r = R.data();
    for (Index e = 0; e < n_edges_active_; ++e) {
        const Index i = dual.edges[e][0], j = dual.edges[e][1];
        const Vec3 nv(sn[3 * e], sn[3 * e + 1], sn[3 * e + 2]);
        const double g = ge != nullptr ? ge[e] : 0.0;
        const double* Wi = W + 5 * static_cast<std::size_t>(i);
        const double* Wj = W + 5 * static_cast<std::size_t>(j);
        const Vec5 Vi = jst_variables(Wi, gg), Vj = jst_variables(Wj, gg);
        // Central flux of the mean density, velocity, pressure and total enthalpy (as SU2),
        // through the moving face: (rho (V - g), rho u (V - g) + p n, rho H (V - g) + p g).
        const double rho = 0.5 * (Wi[0] + Wj[0]);
        const Vec3 u(0.5 * (Wi[1] + Wj[1]), 0.5 * (Wi[2] + Wj[2]), 0.5 * (Wi[3] + Wj[3]));
        const double H = 0.5 * (Vi[4] / Wi[0] + Vj[4] / Wj[0]);
        const double p = 0.5 * (Wi[4] + Wj[4]);
        const double mass = rho * (u.dot(nv) - g);
        Vec5 F;
        F[0] = mass;
        F.segment<3>(1) = mass * u + p * nv;
        F[4] = mass * H + p * g;
        const double* ti = t + n_jst * static_cast<std::size_t>(i);
        const double* tj = t + n_jst * static_cast<std::size_t>(j);
        const JstCoefficients c =
            jst_coefficients(jst_neighbours_[static_cast<std::size_t>(i)],
                             jst_neighbours_[static_cast<std::size_t>(j)], ti, tj,
                             radius(Wi, nv, g, gamma_), radius(Wj, nv, g, gamma_), k2, k4);
        for (int k = 0; k < 5; ++k)
            F[k] += (c.e2 * (Vi[k] - Vj[k]) - c.e4 * (ti[k] - tj[k])) * c.s_lambda;
        Eigen::Map<Vec5>(r + 5 * static_cast<std::size_t>(i)) += F;
        Eigen::Map<Vec5>(r + 5 * static_cast<std::size_t>(j)) -= F;
    }
    n_fallbacks_ = 0;
    add_boundary_fluxes(r);
    if (domain_.n_owned < n_local_) R.rightCols(n_local_ - domain_.n_owned).setZero();
}

void SpatialOperator::jacobian_jst(const NodeStates& U, BlockMatrix& J) const {
    const mesh::DualMetrics& dual = *domain_.dual;
    const Index no = domain_.n_owned;
    const double k2 = options_.flux.jst_k2, k4 = options_.flux.jst_k4;
    const double* t = jst_.data();
    const double* sn = dual.edge_normals.data();
    const double* ge = grid_ != nullptr ? grid_->edges.data() : nullptr;
    for (Index e = 0; e < n_edges_active_; ++e) {
        const Index i = dual.edges[e][0], j = dual.edges[e][1];
        const Vec3 nv(sn[3 * e], sn[3 * e + 1], sn[3 * e + 2]);
        const double g = ge != nullptr ? ge[e] : 0.0;
        const Vec5 Wi = primitive(U.col(i), gamma_), Wj = primitive(U.col(j), gamma_);
        const double* ti = t + n_jst * static_cast<std::size_t>(i);
        const double* tj = t + n_jst * static_cast<std::size_t>(j);
        const JstCoefficients c = jst_coefficients(jst_neighbours_[static_cast<std::size_t>(i)],
                                                   jst_neighbours_[static_cast<std::size_t>(j)], ti,
                                                   tj, radius(Wi.data(), nv, g, gamma_),
                                                   radius(Wj.data(), nv, g, gamma_), k2, k4);
        // d(-(L_i - L_j))/dU_i = NL_i + [U_i enters L_j]; likewise for j.
        const bool bi = jst_boundary_[static_cast<std::size_t>(i)] != 0;
        const bool bj = jst_boundary_[static_cast<std::size_t>(j)] != 0;
        const double ai = ti[7] + ((!bj || bi) ? 1.0 : 0.0);
        const double aj = tj[7] + ((!bi || bj) ? 1.0 : 0.0);
        // Lower bound of the dissipation coefficient: k2 s2 / 4 (spatial.hpp).
        const double e_min = 0.25 * k2 * c.s2;
        const Mat5 A = 0.5 * physical_flux_jacobian(Wi, nv, g, gamma_) +
                       (std::max(e_min, c.e2 + c.e4 * ai) * c.s_lambda) * jst_transform(Wi, gamma_);
        const Mat5 B = 0.5 * physical_flux_jacobian(Wj, nv, g, gamma_) -
                       (std::max(e_min, c.e2 + c.e4 * aj) * c.s_lambda) * jst_transform(Wj, gamma_);
        // R_i += F(U_i, U_j), R_j -= F(U_i, U_j).
        J.add_diagonal(i, A);
        J.add(J.edge_ij(e), B);
        J.add(J.edge_ji(e), -A);
        if (j < no) J.add_diagonal(j, -B);
    }
}

}  // namespace manta::euler
