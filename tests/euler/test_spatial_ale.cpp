/// @file test_spatial_ale.cpp
/// The spatial operator on moving meshes (spatial.hpp, "Moving meshes"): free-stream preservation
/// with the grid fluxes from the exact swept volumes (the discrete geometric conservation law,
/// Mavriplis & Yang, J. Comput. Phys. 213, 557-573, 2006), a zero grid-flux array reproducing the
/// fixed mesh bit for bit, `update_geometry` equal to a fresh operator without allocating, and
/// the Jacobian with grid fluxes against finite differences. Meshes: `irregular_box`
/// (tests/euler/support), random hexahedra, prisms, tetrahedra and pyramids, perturbed nodes.

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <new>
#include <random>
#include <string>

#include "manta/core/error.hpp"
#include "manta/euler/spatial.hpp"
#include "manta/mesh/dual.hpp"
#include "test_meshes.hpp"

// Counting global operator new (std::vector allocations). (GCC sees malloc paired with free
// through inlined new/delete and warns of a mismatch that is none.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
namespace {
std::atomic<long> n_allocations{0};
}  // namespace
void* operator new(std::size_t n) {
    n_allocations.fetch_add(1, std::memory_order_relaxed);
    if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
    throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
    std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
    std::free(p);
}
#pragma GCC diagnostic pop

namespace {

using manta::euler::BlockMatrix;
using manta::euler::BoundaryKind;
using manta::euler::Domain;
using manta::euler::FluxScheme;
using manta::euler::GradientMethod;
using manta::euler::NodeStates;
using manta::euler::SpatialOperator;
using manta::euler::SpatialOptions;
using manta::euler::Vec5;
using manta::euler::WallTangency;
using manta::mesh::DualFaceValues;
using manta::mesh::Index;

constexpr double gamma_air = 1.4;

std::vector<double> coordinates(const manta::mesh::Mesh& m) {
    return {m.coordinates().begin(), m.coordinates().end()};
}

/// Rigid motion over one time step: rotation by `deg` about an oblique axis through the box
/// centre, then a translation.
std::vector<double> rigid(const std::vector<double>& x, double deg) {
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(deg * M_PI / 180.0, Eigen::Vector3d(0.3, 1.0, -0.4).normalized())
            .toRotationMatrix();
    const Eigen::Vector3d o(0.5, 0.5, 0.5), t(0.02, -0.03, 0.015);
    std::vector<double> y(x.size());
    for (std::size_t k = 0; k < x.size(); k += 3) {
        const Eigen::Vector3d p(x[k], x[k + 1], x[k + 2]);
        const Eigen::Vector3d q = o + R * (p - o) + t;
        for (int c = 0; c < 3; ++c) y[k + c] = q[c];
    }
    return y;
}

/// Smooth deformation of amplitude `a` (m).
std::vector<double> deformed(const std::vector<double>& x, double a) {
    std::vector<double> y(x.size());
    for (std::size_t k = 0; k < x.size(); k += 3) {
        const double px = x[k], py = x[k + 1], pz = x[k + 2];
        y[k] = px + a * std::sin(2.1 * py + 0.4) * std::cos(1.3 * pz);
        y[k + 1] = py + a * std::sin(1.7 * pz - 0.3 * px + 1.0);
        y[k + 2] = pz + a * std::cos(2.3 * px + 0.9 * py);
    }
    return y;
}

Vec5 w_inf() {
    return manta::euler::free_stream(0.6, 0.05, 0.02, gamma_air);
}

SpatialOptions roe(int order, GradientMethod g = GradientMethod::least_squares) {
    SpatialOptions o;
    o.order = order;
    o.gradient = g;
    return o;
}
SpatialOptions jst() {
    SpatialOptions o;
    o.flux.scheme = FluxScheme::jst;
    return o;
}

/// Free-stream preservation between two levels (metrics at b, grid fluxes S(a->b) / dt,
/// first-order backward Euler: V_b U - V_a U = -dt R(U)): the largest |R_i + (V_b - V_a)/dt U|
/// relative to the largest edge flux |F(U).n|.
struct Preservation {
    double defect;      ///< with the swept-volume grid fluxes
    double static_gap;  ///< the same without grid fluxes (the mesh treated as fixed)
    double grid_terms;  ///< largest |g U| relative to the same flux scale
};
Preservation preservation(const std::vector<double>& xa, const std::vector<double>& xb,
                          const SpatialOptions& o, std::uint32_t seed) {
    manta::mesh::Mesh m = manta::test::irregular_box(4, 0.15, seed);
    const manta::parallel::SerialHalo halo;
    m.set_coordinates(xa);
    const manta::mesh::DualMetrics da = compute_dual_metrics(m);
    m.set_coordinates(xb);
    manta::mesh::DualMetrics db = da;
    update_dual_metrics(m, db);
    DualFaceValues g;
    swept_volumes(m, db, xa, xb, g);
    const double dt = 0.01;
    for (double& v : g.edges) v /= dt;
    for (auto& b : g.boundary)
        for (double& v : b) v /= dt;
    const Vec5 W = w_inf();
    const Vec5 U = manta::euler::conservative(W, gamma_air);
    NodeStates Us(5, m.n_nodes());
    for (Index n = 0; n < m.n_nodes(); ++n) Us.col(n) = U;
    SpatialOperator op(Domain{&m, &db, m.n_nodes(), &halo},
                       std::vector<BoundaryKind>(m.markers().size(), BoundaryKind::farfield), W,
                       gamma_air, o);
    double scale = 0.0;
    for (Index e = 0; e < db.n_edges(); ++e)
        scale = std::max(scale, manta::euler::physical_flux(W, db.edge_normals.col(e), gamma_air)
                                    .cwiseAbs()
                                    .maxCoeff());
    const auto defect = [&] {
        NodeStates R;
        op.residual(Us, R);
        double worst = 0.0;
        for (Index n = 0; n < m.n_nodes(); ++n)
            worst = std::max(worst, (R.col(n) + (db.dual_volumes[n] - da.dual_volumes[n]) / dt * U)
                                        .cwiseAbs()
                                        .maxCoeff());
        return worst / scale;
    };
    const double gap = defect();
    op.set_grid_fluxes(&g);
    double gu = 0.0;
    for (double v : g.edges) gu = std::max(gu, std::abs(v) * U.cwiseAbs().maxCoeff());
    return {defect(), gap, gu / scale};
}

TEST(SpatialAle, FreeStreamPreservationOnMovingMeshes) {
    for (std::uint32_t seed : {1u, 2u}) {
        const auto x0 = coordinates(manta::test::irregular_box(4, 0.15, seed));
        struct Motion {
            const char* name;
            std::vector<double> a, b;
        };
        const std::vector<Motion> motions{
            {"rigid", x0, rigid(x0, 3.0)},
            {"deforming", deformed(x0, 0.01), deformed(x0, 0.025)},
            {"both", deformed(x0, 0.01), rigid(deformed(x0, 0.02), 2.0)},
        };
        for (const Motion& mo : motions) {
            for (const auto& [name, o] :
                 {std::pair{"Roe order 1", roe(1)}, std::pair{"Roe order 2", roe(2)},
                  std::pair{"Roe order 2 Green-Gauss", roe(2, GradientMethod::green_gauss)},
                  std::pair{"JST", jst()}}) {
                const Preservation p = preservation(mo.a, mo.b, o, seed);
                std::printf(
                    "seed %u, %s, %s: free-stream defect %.2e (without grid fluxes %.2e; largest "
                    "|g U| %.2f)\n",
                    seed, mo.name, name, p.defect, p.static_gap, p.grid_terms);
                EXPECT_LT(p.defect, 1e-13) << mo.name << ", " << name;
                // The grid-flux terms are of the size of the fluxes, so the cancellation is a
                // real one; a deforming mesh treated as fixed loses the uniform flow (a rigidly
                // moving one keeps its dual volumes and needs no grid flux for it).
                EXPECT_GT(p.grid_terms, 0.05) << mo.name << ", " << name;
                if (std::string(mo.name) != "rigid") {
                    EXPECT_GT(p.static_gap, 1e-3) << mo.name << ", " << name;
                }
            }
        }
        // HLLC too.
        SpatialOptions h = roe(2);
        h.flux.scheme = FluxScheme::hllc;
        EXPECT_LT(preservation(motions[2].a, motions[2].b, h, seed).defect, 1e-13);
    }
}

/// A mesh with walls, symmetry planes and far field, a smooth non-uniform state.
struct Walled {
    manta::mesh::Mesh m = manta::test::irregular_box(4, 0.15, 3);
    manta::mesh::DualMetrics d = compute_dual_metrics(m);
    manta::parallel::SerialHalo halo;
    std::vector<BoundaryKind> kinds;
    NodeStates U;
    Walled() {
        const std::map<std::string, BoundaryKind> k{{"ymin", BoundaryKind::wall},
                                                    {"zmin", BoundaryKind::wall},
                                                    {"ymax", BoundaryKind::symmetry}};
        for (const auto& name : m.markers()) {
            const auto it = k.find(name);
            kinds.push_back(it == k.end() ? BoundaryKind::farfield : it->second);
        }
        U.resize(5, m.n_nodes());
        for (Index n = 0; n < m.n_nodes(); ++n) {
            const Eigen::Vector3d x = m.node(n);
            Vec5 W = w_inf();
            W[0] *= 1.0 + 0.05 * std::sin(2.0 * x.x() + x.y());
            W[1] += 0.05 * std::cos(1.7 * x.y() - x.z());
            W[2] += 0.04 * std::sin(2.3 * x.x() + 0.7 * x.z());
            W[3] += 0.03 * std::cos(x.x() + x.y() + x.z());
            W[4] *= 1.0 + 0.05 * std::cos(2.1 * x.x() - 1.3 * x.y());
            U.col(n) = manta::euler::conservative(W, gamma_air);
        }
    }
    [[nodiscard]] Domain domain() const { return {&m, &d, m.n_nodes(), &halo}; }
};

bool same_bits(const NodeStates& a, const NodeStates& b) {
    return a.size() == b.size() &&
           std::memcmp(a.data(), b.data(), static_cast<std::size_t>(a.size()) * sizeof(double)) ==
               0;
}
bool same_bits(const BlockMatrix& a, const BlockMatrix& b) {
    return a.values().size() == b.values().size() &&
           std::memcmp(a.values().data(), b.values().data(), a.values().size() * sizeof(float)) ==
               0;
}
bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

SpatialOptions with_wall(SpatialOptions o, WallTangency w) {
    o.wall = w;
    o.sharp_edge_deg = 30.0;  // the box's edges (90 deg between the faces) are sharp edges
    return o;
}

/// Residual (with strong tangency applied), spectral radii and Jacobian (with tangency rows) of
/// one operator.
struct Evaluation {
    NodeStates R;
    std::vector<double> lambda;
    BlockMatrix J;
};
Evaluation evaluate(SpatialOperator& op, const NodeStates& U) {
    Evaluation e{NodeStates(), {}, op.make_jacobian_matrix()};
    op.residual(U, e.R);
    op.spectral_radii(U, e.lambda);
    op.apply_wall_tangency(U, e.lambda, e.R);
    op.jacobian(U, e.J);
    op.apply_wall_tangency(e.lambda, 10.0, e.J);
    return e;
}

const std::vector<std::pair<const char*, SpatialOptions>>& all_options() {
    static const std::vector<std::pair<const char*, SpatialOptions>> o{
        {"Roe order 2, least squares, weak walls", roe(2)},
        {"Roe order 2, Green-Gauss", roe(2, GradientMethod::green_gauss)},
        {"Roe order 1, strong walls", with_wall(roe(1), WallTangency::strong)},
        {"Roe order 2, mixed walls", with_wall(roe(2), WallTangency::mixed)},
        {"JST (strong walls)", jst()},
        {"JST, mixed walls", with_wall(jst(), WallTangency::mixed)},
    };
    return o;
}

TEST(SpatialAle, ZeroGridFluxesGiveTheFixedMeshBitForBit) {
    const Walled c;
    DualFaceValues zero;
    zero.resize_for(c.d);
    for (const auto& [name, o] : all_options()) {
        SCOPED_TRACE(name);
        SpatialOperator fixed(c.domain(), c.kinds, w_inf(), gamma_air, o);
        SpatialOperator moving(c.domain(), c.kinds, w_inf(), gamma_air, o);
        moving.set_grid_fluxes(&zero);
        const Evaluation a = evaluate(fixed, c.U), b = evaluate(moving, c.U);
        EXPECT_TRUE(same_bits(a.R, b.R));
        EXPECT_TRUE(same_bits(a.lambda, b.lambda));
        EXPECT_TRUE(same_bits(a.J, b.J));
        EXPECT_GT(a.R.cwiseAbs().maxCoeff(), 1e-3);  // a residual that means something
    }
}

TEST(SpatialAle, UpdateGeometryEqualsAFreshOperatorWithoutAllocating) {
    Walled c;
    const auto x0 = coordinates(c.m);
    DualFaceValues g;
    g.resize_for(c.d);
    for (const auto& [name, o] : all_options()) {
        SCOPED_TRACE(name);
        c.m.set_coordinates(x0);
        update_dual_metrics(c.m, c.d);
        SpatialOperator moved(c.domain(), c.kinds, w_inf(), gamma_air, o);
        NodeStates R;
        moved.residual(c.U, R);  // work arrays sized
        const auto xb = rigid(deformed(x0, 0.02), 4.0);
        swept_volumes(c.m, c.d, x0, xb, g);
        c.m.set_coordinates(xb);
        update_dual_metrics(c.m, c.d);
        moved.set_grid_fluxes(&g);
        const long before = n_allocations.load();
        moved.update_geometry();
        EXPECT_EQ(n_allocations.load() - before, 0);
        SpatialOperator fresh(c.domain(), c.kinds, w_inf(), gamma_air, o);
        fresh.set_grid_fluxes(&g);
        EXPECT_EQ(moved.sharp_edge_nodes(), fresh.sharp_edge_nodes());
        const Evaluation a = evaluate(moved, c.U), b = evaluate(fresh, c.U);
        EXPECT_TRUE(same_bits(a.R, b.R));
        EXPECT_TRUE(same_bits(a.lambda, b.lambda));
        EXPECT_TRUE(same_bits(a.J, b.J));
        for (Index n = 0; n < c.m.n_nodes(); n += 7)
            EXPECT_EQ(moved.gradient(n), fresh.gradient(n));
    }
    c.m.set_coordinates(x0);
}

TEST(SpatialAle, GridFluxSizesChecked) {
    const Walled c;
    SpatialOperator op(c.domain(), c.kinds, w_inf(), gamma_air, roe(2));
    DualFaceValues g;
    g.resize_for(c.d);
    g.edges.pop_back();
    EXPECT_THROW(op.set_grid_fluxes(&g), manta::InputError);
    g.resize_for(c.d);
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, 4);
    EXPECT_THROW(op.set_grid_fluxes(&g, &v), manta::InputError);
    EXPECT_NO_THROW(op.set_grid_fluxes(&g));
    EXPECT_NO_THROW(op.set_grid_fluxes(nullptr));
    EXPECT_EQ(op.grid_fluxes(), nullptr);
}

/// Central finite difference of the residual along v.
Eigen::VectorXd fd_product(SpatialOperator& op, const NodeStates& U, const Eigen::VectorXd& v) {
    const double h = 1e-6;
    NodeStates Up = U, Um = U, Rp, Rm;
    Eigen::Map<Eigen::VectorXd>(Up.data(), Up.size()) += h * v;
    Eigen::Map<Eigen::VectorXd>(Um.data(), Um.size()) -= h * v;
    op.residual(Up, Rp);
    op.residual(Um, Rm);
    const NodeStates d = (Rp - Rm) / (2.0 * h);
    return Eigen::Map<const Eigen::VectorXd>(d.data(), d.size());
}

// At a uniform state the first-order Jacobian is exact (the frozen dissipation multiplies
// U_R - U_L = 0), with grid fluxes too: J v against finite differences of R, walls and far field
// on a moving mesh.
TEST(SpatialAle, JacobianAtUniformStateWithGridFluxes) {
    Walled c;
    const auto x0 = coordinates(c.m);
    const auto xb = rigid(deformed(x0, 0.02), 4.0);
    DualFaceValues g;
    swept_volumes(c.m, c.d, x0, xb, g);
    for (double& v : g.edges) v /= 0.05;
    for (auto& b : g.boundary)
        for (double& v : b) v /= 0.05;
    c.m.set_coordinates(xb);
    update_dual_metrics(c.m, c.d);
    Vec5 W0 = w_inf();
    W0[0] = 1.1;
    const Vec5 U0 = manta::euler::conservative(W0, gamma_air);
    NodeStates U(5, c.m.n_nodes());
    for (Index n = 0; n < c.m.n_nodes(); ++n) U.col(n) = U0;
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::VectorXd v(U.size());
    for (Index k = 0; k < v.size(); ++k) v[k] = u(rng) * std::abs(U.data()[k]) + 1e-3 * u(rng);
    // JST without dissipation (k2 = k4 = 0): its Jacobian's dissipation part is the scalar
    // approximation that drops distance-two couplings (spatial.hpp); the central part and the
    // boundary blocks are exact.
    SpatialOptions central = jst();
    central.flux.jst_k2 = 0.0;
    central.flux.jst_k4 = 0.0;
    central.wall = WallTangency::weak;
    for (const auto& [name, o] : {std::pair{"Roe", roe(1)}, std::pair{"JST central", central}}) {
        SCOPED_TRACE(name);
        SpatialOperator op(c.domain(), c.kinds, w_inf(), gamma_air, o);
        op.set_grid_fluxes(&g);
        NodeStates R;
        op.residual(U, R);
        BlockMatrix J = op.make_jacobian_matrix();
        op.jacobian(U, J);
        Eigen::VectorXd Jv(5 * J.n_rows());
        J.multiply(std::span<const double>(v.data(), static_cast<std::size_t>(v.size())),
                   std::span<double>(Jv.data(), static_cast<std::size_t>(Jv.size())));
        const Eigen::VectorXd fd = fd_product(op, U, v);
        const double d = (Jv - fd).norm() / fd.norm();
        std::printf("%s, uniform state, moving mesh: |J v - FD| / |FD| = %.3g\n", name, d);
        // Blocks are single precision (block_matrix.hpp): 1e-6 relative is their resolution.
        EXPECT_LT(d, 2e-6);
    }
}

// Strong tangency on a moving wall: with the node grid velocities given, the momentum rows of a
// wall node carry lambda rho (u - v_grid) . e; a state moving with the wall there zeroes them.
TEST(SpatialAle, StrongTangencyImposesTheRelativeNormalVelocity) {
    Walled c;
    DualFaceValues g;
    g.resize_for(c.d);
    Eigen::Matrix3Xd vg(3, c.m.n_nodes());
    for (Index n = 0; n < c.m.n_nodes(); ++n) vg.col(n) = Eigen::Vector3d(0.1, -0.2, 0.15);
    SpatialOperator op(c.domain(), c.kinds, w_inf(), gamma_air,
                       with_wall(roe(2), WallTangency::strong));
    op.set_grid_fluxes(&g, &vg);
    NodeStates U = c.U;
    // At every wall and symmetry node: the state's velocity = the grid velocity, plus a part
    // tangent to both box planes there (none at the box's edges).
    const int ymin = c.m.find_marker("ymin"), zmin = c.m.find_marker("zmin"),
              ymax = c.m.find_marker("ymax");
    std::vector<int> on(c.m.n_nodes(), 0);
    for (int mk : {ymin, zmin, ymax})
        for (Index n : c.d.boundary[mk].nodes) ++on[n];
    for (Index n = 0; n < c.m.n_nodes(); ++n) {
        if (!on[n]) continue;
        Vec5 W = manta::euler::primitive(U.col(n), gamma_air);
        W.segment<3>(1) = vg.col(n);
        U.col(n) = manta::euler::conservative(W, gamma_air);
    }
    std::vector<double> lambda;
    op.spectral_radii(U, lambda);
    NodeStates R, Rf;
    op.residual(U, R);
    op.apply_wall_tangency(U, lambda, R);
    // Without the node velocities and grid fluxes the targets are 0: u . e = 0 is imposed.
    SpatialOperator fixed(c.domain(), c.kinds, w_inf(), gamma_air,
                          with_wall(roe(2), WallTangency::strong));
    fixed.residual(U, Rf);
    fixed.apply_wall_tangency(U, lambda, Rf);
    // At nodes on one of the markers only, e is the marker's unit dual normal: the momentum
    // residual's normal part is lambda rho (u - v_grid) . e = 0 with the targets, and
    // lambda rho v_grid . e without.
    int checked = 0;
    double worst = 0.0;
    for (int mk : {ymin, zmin, ymax}) {
        const auto& bv = c.d.boundary[mk];
        for (std::size_t k = 0; k < bv.nodes.size(); ++k) {
            const Index n = bv.nodes[k];
            if (on[n] != 1) continue;
            const Eigen::Vector3d e = bv.normals.col(static_cast<Index>(k)).normalized();
            const double scale = lambda[n] * U(0, n);
            worst = std::max(worst, std::abs(R.col(n).segment<3>(1).dot(e)) / scale);
            EXPECT_NEAR(Rf.col(n).segment<3>(1).dot(e), scale * vg.col(n).dot(e), 1e-10 * scale)
                << n;
            ++checked;
        }
    }
    std::printf("moving strong wall: largest |R_m . e| / (lambda rho) = %.2e at %d nodes\n", worst,
                checked);
    EXPECT_LT(worst, 1e-14);
    EXPECT_GT(checked, 10);
}

}  // namespace
