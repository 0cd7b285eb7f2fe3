/// @file test_unsteady_deforming.cpp
/// Dual time stepping on a deforming mesh (meshmotion's deforming body motion,
/// docs/mesh-motion.md): a uniform free stream stays uniform to round-off over 10 steps on the
/// NACA 0012 slab whose aerofoil moves while its far field stays and its nodes slide on the
/// symmetry planes, with BDF1 and BDF2; the discrete geometric conservation law holds to
/// round-off every step (ADR 0003 item 4).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <span>

#include "manta/aero/motion.hpp"
#include "manta/core/error.hpp"
#include "manta/euler/config.hpp"
#include "manta/euler/unsteady.hpp"
#include "manta/mesh/dual.hpp"
#include "manta/meshmotion/mesh_motion.hpp"
#include "test_meshes.hpp"

namespace {

using namespace manta;
using euler::BoundaryKind;
constexpr double deg = 3.14159265358979323846 / 180.0;

TEST(UnsteadyDeforming, FreeStreamStaysUniformOnADeformingSlab) {
    // The NACA 0012 slab (x-y plane, symmetry planes z = 0 and z = 1) in the deforming body
    // motion: the aerofoil yaws 5 deg sin(2 t) about (0.25, 0, 0) (in the slab's plane) and
    // moves 0.05 sin(3 t) m across the stream, the far field at 50 chords stays, every node
    // slides on its symmetry plane, and the volume between blends. The solver's boundaries are
    // far fields and symmetry planes (a uniform flow is then exact), the aerofoil among them.
    mesh::Mesh mesh = test::naca0012_slab(0);
    mesh::DualMetrics dual = mesh::compute_dual_metrics(mesh);
    parallel::SerialHalo halo;
    parallel::SerialCommunicator comm;
    euler::CaseSetup setup;
    euler::CfdConfig c;
    c.markers = {{"airfoil", BoundaryKind::farfield},
                 {"farfield", BoundaryKind::farfield},
                 {"symmetry_back", BoundaryKind::symmetry},
                 {"symmetry_front", BoundaryKind::symmetry}};
    setup.roles = euler::resolve_roles(mesh, c);
    setup.flow.mach = 0.5;
    setup.reference.area = 1.0;
    setup.spatial.limiter = false;
    aero::Motion m;
    for (int i = 0; i <= 200; ++i) m.t.push_back(0.01 * i);
    for (auto& p : m.position) p.assign(m.t.size(), 0.0);
    for (auto& a : m.angles) a.assign(m.t.size(), 0.0);
    for (std::size_t i = 0; i < m.t.size(); ++i) {
        m.angles[2][i] = 5.0 * deg * std::sin(2.0 * m.t[i]);
        m.position[1][i] = 0.05 * std::sin(3.0 * m.t[i]);
    }
    for (const char* mode : {"elevator", "aileron", "rudder"})
        m.add_mode(mode, std::vector<double>(m.t.size(), 0.0));
    meshmotion::DeformationOptions o;
    o.body = meshmotion::BodyMotion::deforming;
    o.wall_markers = {"airfoil"};
    o.symmetry_markers = {"symmetry_back", "symmetry_front"};
    const meshmotion::MeshMotion motion(
        mesh, m, meshmotion::MotionPlacement{Eigen::Vector3d(0.25, 0.0, 0.0), "slab motion"}, {},
        o);
    EXPECT_EQ(motion.body_info().n_sliding_nodes,
              mesh.n_nodes() - motion.body_info().n_fixed_nodes);
    const Eigen::Matrix3Xd x0 =
        Eigen::Map<const Eigen::Matrix3Xd>(mesh.coordinates().data(), 3, mesh.n_nodes());
    for (int order : {1, 2}) {
        mesh.set_coordinates(
            std::span<const double>(x0.data(), static_cast<std::size_t>(x0.size())));
        dual = mesh::compute_dual_metrics(mesh);
        euler::UnsteadySettings t;
        t.dt = 0.05;
        t.order = order;
        euler::UnsteadySolver s({&mesh, &dual, mesh.n_nodes(), &halo}, comm, setup, t);
        s.set_moving_mesh({&mesh, &dual, [&](double time, long step, Eigen::Matrix3Xd& x) {
                               motion.coordinates_at(time, x, step);
                           }});
        const euler::NodeStates U0 = s.state();
        double deviation = 0, gcl = 0, volume_change = 0, moved = 0, far = 0, off_plane = 0;
        for (int n = 0; n < 10; ++n) {
            const std::vector<double> V = dual.dual_volumes;
            const euler::TimeStepRecord rec = s.advance();
            EXPECT_TRUE(rec.converged);
            for (std::size_t i = 0; i < V.size(); ++i)
                volume_change =
                    std::max(volume_change, std::abs(dual.dual_volumes[i] - V[i]) / V[i]);
            gcl = std::max(gcl, rec.gcl_defect);
            deviation = std::max(deviation, (s.state() - U0).cwiseAbs().maxCoeff());
            const Eigen::Matrix3Xd x =
                Eigen::Map<const Eigen::Matrix3Xd>(mesh.coordinates().data(), 3, mesh.n_nodes());
            moved = std::max(moved, (x - x0).cwiseAbs().maxCoeff());
            off_plane = std::max(off_plane, (x.row(2) - x0.row(2)).cwiseAbs().maxCoeff());
            for (mesh::Index f = 0; f < mesh.n_faces(); ++f)
                if (mesh.markers()[static_cast<std::size_t>(mesh.face_marker(f))] == "farfield")
                    for (const mesh::Index v : mesh.face(f))
                        far = std::max(far, (x.col(v) - x0.col(v)).norm());
        }
        std::printf(
            "deforming slab, BDF%d: max |U - U_inf| %.2e, GCL defect %.2e, nodes moved up to "
            "%.3f m (far field %.1e, off the planes %.1e), dual volumes changed up to %.1e per "
            "step\n",
            order, deviation, gcl, moved, far, off_plane, volume_change);
        EXPECT_GT(moved, 0.05);
        EXPECT_EQ(far, 0.0);
        EXPECT_LT(off_plane, 1e-15);
        EXPECT_GT(volume_change, 1e-5);  // the volume deforms
        EXPECT_LT(gcl, 1e-13);
        EXPECT_LT(deviation, 1e-12);
    }
}

TEST(UnsteadyDeforming, ConfigurationKeys) {
    const euler::CfdConfig c = euler::parse_cfd_config(
        "unsteady: {mesh_motion: deforming, rigid_radius: 1.5, fixed_radius: 15}\n", "cfd.yaml");
    EXPECT_EQ(c.mesh_motion, meshmotion::BodyMotion::deforming);
    EXPECT_EQ(c.rigid_radius, 1.5);
    EXPECT_EQ(c.fixed_radius, 15.0);
    EXPECT_EQ(euler::parse_cfd_config("unsteady: {order: 2}\n", "cfd.yaml").mesh_motion,
              meshmotion::BodyMotion::rigid);
    for (const char* bad : {"unsteady: {mesh_motion: elastic}\n", "unsteady: {rigid_radius: -1}\n",
                            "unsteady: {fixed_radius: .nan}\n"}) {
        try {
            (void)euler::parse_cfd_config(bad, "cfd.yaml");
            ADD_FAILURE() << bad;
        } catch (const ConfigError& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find("cfd.yaml"), std::string::npos) << m;
            EXPECT_EQ(m.find('\n'), std::string::npos) << m;
        }
    }
}

}  // namespace
