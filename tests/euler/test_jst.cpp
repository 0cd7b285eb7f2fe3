/// @file test_jst.cpp
/// The JST scheme (spatial.hpp) under the steady implicit iteration (solver.hpp): on the subsonic
/// bump channel of test_solver.cpp it converges six orders with the default CFL ramp, its own
/// implicit Jacobian steering the iteration, and conserves mass; its configuration keys.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "manta/core/error.hpp"
#include "manta/euler/config.hpp"
#include "manta/euler/solver.hpp"
#include "manta/mesh/dual.hpp"
#include "test_meshes.hpp"

namespace {

using namespace manta;
using euler::BoundaryKind;

/// The JST scheme on the subsonic (M 0.5) bump channel: walls below and above.
euler::CaseSetup jst_bump_setup(const mesh::Mesh& mesh) {
    euler::CfdConfig c;
    c.markers = {{"lower", BoundaryKind::wall}, {"upper", BoundaryKind::wall}};
    euler::CaseSetup setup;
    setup.roles = euler::resolve_roles(mesh, c);
    setup.flow.mach = 0.5;
    setup.reference.area = 0.1;
    setup.spatial.flux.scheme = euler::FluxScheme::jst;
    return setup;
}

TEST(JstConfig, KeysParseAndAreChecked) {
    const euler::CfdConfig c =
        euler::parse_cfd_config("numerics: {flux: jst, jst_k2: 0.6, jst_k4: 0.03}\n", "case.yaml");
    EXPECT_EQ(c.spatial.flux.scheme, euler::FluxScheme::jst);
    EXPECT_DOUBLE_EQ(c.spatial.flux.jst_k2, 0.6);
    EXPECT_DOUBLE_EQ(c.spatial.flux.jst_k4, 0.03);
    const euler::CfdConfig d = euler::parse_cfd_config("numerics: {flux: jst}\n", "case.yaml");
    EXPECT_DOUBLE_EQ(d.spatial.flux.jst_k2, 0.5);
    EXPECT_DOUBLE_EQ(d.spatial.flux.jst_k4, 0.02);
    try {
        (void)euler::parse_cfd_config("numerics:\n  jst_k4: 0.9\n", "case.yaml");
        FAIL();
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("case.yaml:2"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("jst_k4"), std::string::npos) << e.what();
    }
}

TEST(JstSolver, SubsonicBumpChannelConvergesSixOrders) {
    const mesh::Mesh mesh = test::bump_channel(0, 0.1);
    const mesh::DualMetrics dual = mesh::compute_dual_metrics(mesh);
    const parallel::SerialHalo halo;
    parallel::SerialCommunicator comm;
    euler::CaseSetup setup = jst_bump_setup(mesh);
    euler::SteadySolver s({&mesh, &dual, mesh.n_nodes(), &halo}, comm, setup);
    const euler::SolveOutcome oc = s.solve();
    std::printf("JST bump channel: %d iterations, %.2f orders, CL %.6f CD %.6f\n", oc.iterations,
                oc.residual_drop, oc.forces.CL, oc.forces.CD);
    ASSERT_TRUE(oc.converged) << oc.reason;
    EXPECT_GE(oc.residual_drop, 6.0);
    EXPECT_LT(oc.iterations, 120);  // 70 measured
    // Mass conservation: inflow = outflow from the converged node states.
    double in = 0, out = 0;
    const auto& U = s.state();
    for (const auto& bv : dual.boundary) {
        const std::string& name = mesh.markers()[static_cast<std::size_t>(bv.marker)];
        for (std::size_t k = 0; k < bv.nodes.size(); ++k) {
            const double f =
                U.col(bv.nodes[k]).segment<3>(1).dot(bv.normals.col(static_cast<Eigen::Index>(k)));
            if (name == "inflow") in += f;
            if (name == "outflow") out += f;
        }
    }
    EXPECT_LT(in, 0.0);
    EXPECT_NEAR(out, -in, 0.02 * std::abs(in));
}

}  // namespace

namespace {

/// Largest |u . n| / |u| over the wall nodes of the converged bump channel, with the JST scheme
/// and wall tangency `wall`; the iteration count through `iterations`.
double wall_normal_velocity(euler::WallTangency wall, int& iterations) {
    const mesh::Mesh mesh = test::bump_channel(0, 0.1);
    const mesh::DualMetrics dual = mesh::compute_dual_metrics(mesh);
    const parallel::SerialHalo halo;
    parallel::SerialCommunicator comm;
    euler::CaseSetup setup = jst_bump_setup(mesh);
    setup.spatial.wall = wall;
    euler::SteadySolver s({&mesh, &dual, mesh.n_nodes(), &halo}, comm, setup);
    const euler::SolveOutcome oc = s.solve();
    EXPECT_TRUE(oc.converged) << oc.reason;
    iterations = oc.iterations;
    double worst = 0.0;
    for (const auto& bv : dual.boundary) {
        if (setup.roles[static_cast<std::size_t>(bv.marker)] != BoundaryKind::wall) continue;
        for (std::size_t k = 0; k < bv.nodes.size(); ++k) {
            const Eigen::Vector3d m = s.state().col(bv.nodes[k]).segment<3>(1);
            const Eigen::Vector3d n = bv.normals.col(static_cast<Eigen::Index>(k)).normalized();
            // The channel is a slab in z between symmetry planes: every wall node also lies on
            // one, and its wall normal lies in the x-y plane.
            if (std::abs(n.z()) > 1e-12) continue;
            worst = std::max(worst, std::abs(m.dot(n)) / m.norm());
        }
    }
    return worst;
}

}  // namespace

// Strong tangency (spatial.hpp; the default with JST) holds u . n = 0 at the converged wall nodes
// to the convergence level; the weak form leaves a discretisation-level normal velocity.
TEST(JstSolver, StrongWallTangencyZeroesTheNormalVelocity) {
    int it_strong = 0, it_weak = 0;
    const double strong = wall_normal_velocity(euler::WallTangency::automatic, it_strong);
    const double weak = wall_normal_velocity(euler::WallTangency::weak, it_weak);
    std::printf("bump channel wall |u.n|/|u|: strong %.2e (%d iterations), weak %.2e (%d)\n",
                strong, it_strong, weak, it_weak);
    EXPECT_LT(strong, 1e-6);
    EXPECT_GT(weak, 1e-4);
}

TEST(JstConfig, WallTangencyKey) {
    EXPECT_EQ(euler::parse_cfd_config("numerics: {wall: strong}\n", "c.yaml").spatial.wall,
              euler::WallTangency::strong);
    const euler::CfdConfig d = euler::parse_cfd_config("numerics: {flux: jst}\n", "c.yaml");
    EXPECT_EQ(d.spatial.wall, euler::WallTangency::automatic);
    EXPECT_TRUE(d.spatial.strong_walls());
    EXPECT_FALSE(
        euler::parse_cfd_config("numerics: {flux: roe}\n", "c.yaml").spatial.strong_walls());
    EXPECT_FALSE(euler::parse_cfd_config("numerics: {flux: jst, wall: weak}\n", "c.yaml")
                     .spatial.strong_walls());
    const euler::CfdConfig mx =
        euler::parse_cfd_config("numerics: {wall: mixed, sharp_edge_deg: 30}\n", "c.yaml");
    EXPECT_EQ(mx.spatial.resolved_wall(), euler::WallTangency::mixed);
    EXPECT_TRUE(mx.spatial.strong_walls());
    EXPECT_EQ(mx.spatial.sharp_edge_deg, 30.0);
    euler::SpatialOptions bad;
    bad.sharp_edge_deg = 200.0;
    try {
        bad.validate();
        FAIL();
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("sharp_edge_deg = 200"), std::string::npos)
            << e.what();
    }
    try {
        (void)euler::parse_cfd_config("numerics:\n  wall: strng\n", "c.yaml");
        FAIL();
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("did you mean 'strong'"), std::string::npos)
            << e.what();
    }
}

TEST(CfdConfig, LowMachFixKey) {
    EXPECT_FALSE(
        euler::parse_cfd_config("numerics: {flux: roe}\n", "c.yaml").spatial.flux.low_mach_fix);
    EXPECT_TRUE(euler::parse_cfd_config("numerics: {low_mach_fix: true}\n", "c.yaml")
                    .spatial.flux.low_mach_fix);
    try {
        (void)euler::parse_cfd_config("numerics:\n  low_mach_fix: maybe\n", "c.yaml");
        FAIL();
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("c.yaml:2"), std::string::npos) << e.what();
    }
}
