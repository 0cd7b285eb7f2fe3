/// @file test_rotating_frame.cpp
/// The rotating frame of the steady solver (rotating_frame.hpp): the grid fluxes of a rigid
/// rotation close every dual cell to round-off and agree with the swept volumes of a small
/// rotation; a uniform free stream stays a solution with the grid fluxes and the frame's source
/// (and does not with the turbomachinery source -omega x rho u alone); omega = 0 is the fixed
/// mesh bit for bit.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "manta/euler/rotating_frame.hpp"
#include "manta/euler/solver.hpp"
#include "manta/mesh/dual.hpp"
#include "manta/parallel/communicator.hpp"
#include "test_meshes.hpp"

namespace {

using namespace manta;
using euler::Index;
using euler::NodeStates;
using euler::Vec3;
using euler::Vec5;

euler::RotatingFrame frame() {
    euler::RotatingFrame f;
    f.omega = Vec3(0.13, -0.21, 0.17);
    f.center = Vec3(0.25, 0.1, -0.05);
    return f;
}

/// Largest |sum of the grid fluxes out of a dual cell| over the nodes, relative to the largest
/// |g| of a face at that node.
double closure(const mesh::DualMetrics& d, const mesh::DualFaceValues& g) {
    std::vector<double> sum(d.dual_volumes.size(), 0.0), scale(d.dual_volumes.size(), 0.0);
    for (Index e = 0; e < d.n_edges(); ++e) {
        const auto [i, j] = d.edges[static_cast<std::size_t>(e)];
        const double v = g.edges[static_cast<std::size_t>(e)];
        sum[static_cast<std::size_t>(i)] += v;
        sum[static_cast<std::size_t>(j)] -= v;
        for (Index n : {i, j})
            scale[static_cast<std::size_t>(n)] =
                std::max(scale[static_cast<std::size_t>(n)], std::abs(v));
    }
    for (std::size_t mk = 0; mk < d.boundary.size(); ++mk)
        for (std::size_t k = 0; k < d.boundary[mk].nodes.size(); ++k) {
            const auto n = static_cast<std::size_t>(d.boundary[mk].nodes[k]);
            sum[n] += g.boundary[mk][k];
            scale[n] = std::max(scale[n], std::abs(g.boundary[mk][k]));
        }
    double worst = 0.0;
    for (std::size_t n = 0; n < sum.size(); ++n)
        if (scale[n] > 0) worst = std::max(worst, std::abs(sum[n]) / scale[n]);
    return worst;
}

TEST(RotatingFrame, GridFluxesCloseEveryCellAndMatchTheSweptVolumes) {
    for (std::uint32_t seed : {1u, 2u}) {
        const mesh::Mesh m = test::irregular_box(4, 0.15, seed);
        const mesh::DualMetrics d = mesh::compute_dual_metrics(m);
        const euler::RotatingFrame f = frame();
        mesh::DualFaceValues g;
        euler::rotation_grid_fluxes(m, d, f, g);
        const double c = closure(d, g);
        std::printf("seed %u: grid-flux closure defect %.2e\n", seed, c);
        EXPECT_LT(c, 1e-13);
        // Against the swept volumes of the linearised motion x -/+ h v_g over 2 h: equal to
        // O(h^2) (the area vectors of the linear motion differ from the rotation's at second
        // order), and the sign and orientation of every face the same.
        const double h = 1e-4;
        std::vector<double> xa(m.coordinates().begin(), m.coordinates().end()), xb = xa;
        for (Index n = 0; n < m.n_nodes(); ++n) {
            const Vec3 v = f.omega.cross(m.node(n) - f.center);
            for (int k = 0; k < 3; ++k) {
                xa[3 * static_cast<std::size_t>(n) + k] -= h * v[k];
                xb[3 * static_cast<std::size_t>(n) + k] += h * v[k];
            }
        }
        mesh::DualFaceValues s;
        mesh::swept_volumes(m, d, xa, xb, s);
        double worst = 0.0, largest = 0.0;
        for (std::size_t e = 0; e < g.edges.size(); ++e) {
            worst = std::max(worst, std::abs(s.edges[e] / (2 * h) - g.edges[e]));
            largest = std::max(largest, std::abs(g.edges[e]));
        }
        for (std::size_t mk = 0; mk < g.boundary.size(); ++mk)
            for (std::size_t k = 0; k < g.boundary[mk].size(); ++k)
                worst = std::max(worst, std::abs(s.boundary[mk][k] / (2 * h) - g.boundary[mk][k]));
        std::printf("seed %u: |swept / dt - g| <= %.2e of the largest |g| %.3f\n", seed,
                    worst / largest, largest);
        EXPECT_LT(worst / largest, 1e-7);
        EXPECT_GT(largest, 1e-3);
    }
}

/// Largest |R*| of the uniform free stream with the frame's grid fluxes and `source`, over the
/// largest |F.n| of an edge.
double free_stream_defect(const mesh::Mesh& m, const mesh::DualMetrics& d,
                          const euler::SpatialOptions& o, const euler::RotatingFrame& f,
                          bool full_source) {
    const parallel::SerialHalo halo;
    const parallel::SerialCommunicator comm;
    euler::CaseSetup setup;
    setup.flow.mach = 0.3;
    setup.flow.alpha = 4.0 * M_PI / 180.0;
    setup.flow.beta = 2.0 * M_PI / 180.0;
    setup.roles.assign(m.markers().size(), euler::BoundaryKind::farfield);
    setup.reference.area = 3.0;
    setup.spatial = o;
    const euler::Domain domain{&m, &d, m.n_nodes(), &halo};
    euler::PseudoTimeStep step(domain, comm, setup);
    mesh::DualFaceValues g;
    Eigen::Matrix3Xd vg;
    euler::rotation_grid_fluxes(m, d, f, g);
    euler::rotation_node_velocities(m, f, vg);
    step.set_grid_fluxes(&g, &vg);
    const Vec5 W = step.free_stream_primitive();
    NodeStates U(5, m.n_nodes());
    for (Index n = 0; n < m.n_nodes(); ++n) U.col(n) = euler::conservative(W, setup.flow.gamma);
    NodeStates S;
    const Vec3 u_inf = full_source ? Vec3(W.segment<3>(1)) : Vec3::Zero();
    euler::rotation_source(U, d.dual_volumes, f, u_inf, m.n_nodes(), S);
    euler::IterationState it = step.initial_state();
    step.begin(it);
    const euler::StopRule stop = [](const euler::StepStatus&) {
        return euler::StopDecision{true, true, "residual only"};
    };
    euler::StepTerms terms;
    terms.source = &S;
    const euler::StepOutcome out = step.step(U, it, stop, terms);
    EXPECT_EQ(out.result, euler::StepResult::stopped);
    double scale = 0.0;
    for (Index e = 0; e < d.n_edges(); ++e)
        scale = std::max(
            scale,
            euler::physical_flux(W, d.edge_normals.col(e), setup.flow.gamma).cwiseAbs().maxCoeff());
    return step.residual().cwiseAbs().maxCoeff() / scale;
}

TEST(RotatingFrame, UniformFreeStreamStaysASolutionOnAWingMesh) {
    // The AR-6 wing's mesh (8 881 nodes; its wall marked far field, so that the uniform flow is
    // a solution without rotation too), rotating at a rate whose grid speed at the far field
    // (10 m away) is of the free stream's size (M 0.3).
    const mesh::Mesh m = test::wing_box(0);
    const mesh::DualMetrics d = mesh::compute_dual_metrics(m);
    euler::RotatingFrame f;
    f.omega = Vec3(0.01, 0.02, -0.015);
    f.center = Vec3(0.25, 0.0, 0.0);
    euler::SpatialOptions roe;
    euler::SpatialOptions jst;
    jst.flux.scheme = euler::FluxScheme::jst;
    for (const auto& [name, o] : {std::pair{"Roe order 2", roe}, std::pair{"JST", jst}}) {
        const double with = free_stream_defect(m, d, o, f, true);
        const double plain = free_stream_defect(m, d, o, f, false);
        std::printf(
            "%s: free-stream residual %.2e with the frame's source, %.2e with -omega x "
            "rho u alone\n",
            name, with, plain);
        EXPECT_LT(with, 1e-13) << name;
        EXPECT_GT(plain, 1e-4) << name;
    }
}

TEST(RotatingFrame, ZeroRateIsTheFixedMeshBitForBit) {
    const mesh::Mesh m = test::bump_channel(0, 0.1);
    const mesh::DualMetrics d = mesh::compute_dual_metrics(m);
    const parallel::SerialHalo halo;
    const parallel::SerialCommunicator comm;
    euler::CaseSetup setup;
    setup.flow.mach = 0.5;
    for (const std::string& name : m.markers())
        setup.roles.push_back(name.find("flow") != std::string::npos ? euler::BoundaryKind::farfield
                              : name.find("sym") != std::string::npos
                                  ? euler::BoundaryKind::symmetry
                                  : euler::BoundaryKind::wall);
    setup.reference.area = 0.1;
    setup.solver.max_iterations = 30;
    const euler::Domain domain{&m, &d, m.n_nodes(), &halo};
    euler::SteadySolver a(domain, comm, setup), b(domain, comm, setup);
    b.set_rotating_frame(euler::RotatingFrame{});
    (void)a.solve();
    (void)b.solve();
    EXPECT_EQ((a.state() - b.state()).cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
