/// @file test_unsteady_moving.cpp
/// Dual time stepping on moving meshes (unsteady.hpp, ADR 0003 item 4): a uniform free stream
/// stays uniform to round-off over 10 steps on a rigidly pitching mesh, on a mesh deformed by a
/// control-surface mode (meshmotion's exact-rotation mode with inverse-distance weighting), and
/// on both at once, with BDF1 and BDF2; the discrete geometric conservation law
/// (3 V^(n+1) - 4 V^n + V^(n-1)) / 2 = dt sum g holds to round-off every step; a solver restored
/// from its time levels continues bit for bit; bad input is refused.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "flap_meshes.hpp"
#include "manta/aero/motion.hpp"
#include "manta/core/error.hpp"
#include "manta/euler/config.hpp"
#include "manta/euler/unsteady.hpp"
#include "manta/mesh/dual.hpp"
#include "manta/meshmotion/mesh_motion.hpp"

namespace {

using namespace manta;
using euler::BoundaryKind;
constexpr double deg = 3.14159265358979323846 / 180.0;

/// The flat-plate flap box of the meshmotion tests ([0, 3] x [0, 1] x [0, 1] m, hexahedra) with
/// a motion: pitch `pitch` sin(2 t) about (1, 0.5, 0.5) and the flap (hinge x = 1 on the plate)
/// deflected by `flap` sin(3 t). Far field everywhere unless `walls`.
struct MovingBox {
    mesh::Mesh mesh = test::flap_plate(6, 4, 4);
    mesh::DualMetrics dual = mesh::compute_dual_metrics(mesh);
    parallel::SerialHalo halo;
    parallel::SerialCommunicator comm;
    euler::CaseSetup setup;
    std::unique_ptr<meshmotion::MeshMotion> motion;

    MovingBox(double pitch, double flap, bool walls = false) {
        euler::CfdConfig c;
        c.markers = {{"flap", walls ? BoundaryKind::wall : BoundaryKind::farfield},
                     {"wall", walls ? BoundaryKind::wall : BoundaryKind::farfield},
                     {"farfield", BoundaryKind::farfield}};
        setup.roles = euler::resolve_roles(mesh, c);
        setup.flow.mach = 0.5;
        setup.reference.area = 1.0;
        setup.spatial.limiter = false;
        aero::Motion m;
        for (int i = 0; i <= 200; ++i) m.t.push_back(0.01 * i);
        for (auto& p : m.position) p.assign(m.t.size(), 0.0);
        for (auto& a : m.angles) a.assign(m.t.size(), 0.0);
        std::vector<double> e(m.t.size());
        for (std::size_t i = 0; i < m.t.size(); ++i) {
            m.angles[1][i] = pitch * std::sin(2.0 * m.t[i]);
            e[i] = flap * std::sin(3.0 * m.t[i]);
        }
        m.add_mode("elevator", e);
        m.add_mode("aileron", std::vector<double>(m.t.size(), 0.0));
        m.add_mode("rudder", std::vector<double>(m.t.size(), 0.0));
        std::vector<meshmotion::ControlSurfaceSpec> surfaces;
        if (flap != 0.0) {
            meshmotion::ControlSurfaceSpec s;
            s.mode = "elevator";
            s.marker = "flap";
            s.hinge = {Eigen::Vector3d(1.0, 0.25, 0.0), Eigen::Vector3d(1.0, 0.75, 0.0)};
            surfaces.push_back(s);
        }
        motion = std::make_unique<meshmotion::MeshMotion>(
            mesh, m, meshmotion::MotionPlacement{Eigen::Vector3d(1.0, 0.5, 0.5), "test motion"},
            surfaces);
    }
    [[nodiscard]] euler::Domain domain() const { return {&mesh, &dual, mesh.n_nodes(), &halo}; }
    [[nodiscard]] euler::MovingMesh moving() {
        return {&mesh, &dual, [this](double t, long step, Eigen::Matrix3Xd& x) {
                    motion->coordinates_at(t, x, step);
                }};
    }
};

/// 10 steps of dt = 0.05 from the free stream; the largest deviation from it over the steps,
/// the largest GCL defect and how far the mesh moved.
struct FreeStreamRun {
    double deviation = 0, gcl = 0, moved = 0;
    double volume_change = 0;  ///< largest |V^(n+1) - V^n| / V^n of a step
    bool converged = true;
};
FreeStreamRun free_stream_run(double pitch, double flap, int order) {
    MovingBox b(pitch, flap);
    const Eigen::Matrix3Xd x0 =
        Eigen::Map<const Eigen::Matrix3Xd>(b.mesh.coordinates().data(), 3, b.mesh.n_nodes());
    euler::UnsteadySettings t;
    t.dt = 0.05;
    t.order = order;
    euler::UnsteadySolver s(b.domain(), b.comm, b.setup, t);
    s.set_moving_mesh(b.moving());
    const euler::NodeStates U0 = s.state();
    FreeStreamRun r;
    for (int n = 0; n < 10; ++n) {
        const std::vector<double> V = b.dual.dual_volumes;
        const euler::TimeStepRecord rec = s.advance();
        for (std::size_t i = 0; i < V.size(); ++i)
            r.volume_change =
                std::max(r.volume_change, std::abs(b.dual.dual_volumes[i] - V[i]) / V[i]);
        r.converged = r.converged && rec.converged;
        r.gcl = std::max(r.gcl, rec.gcl_defect);
        r.deviation = std::max(r.deviation, (s.state() - U0).cwiseAbs().maxCoeff());
        const Eigen::Matrix3Xd x =
            Eigen::Map<const Eigen::Matrix3Xd>(b.mesh.coordinates().data(), 3, b.mesh.n_nodes());
        r.moved = std::max(r.moved, (x - x0).cwiseAbs().maxCoeff());
    }
    EXPECT_NEAR(s.time(), 0.5, 1e-15);
    std::printf(
        "pitch %.0f deg, flap %.0f deg, BDF%d: max |U - U_inf| %.2e, GCL defect %.2e, "
        "nodes moved up to %.3f m, dual volumes changed up to %.1e per step\n",
        pitch / deg, flap / deg, order, r.deviation, r.gcl, r.moved, r.volume_change);
    return r;
}

TEST(UnsteadyMoving, FreeStreamStaysUniformOnAPitchingMesh) {
    for (int order : {1, 2}) {
        const FreeStreamRun r = free_stream_run(10.0 * deg, 0.0, order);
        EXPECT_TRUE(r.converged);
        EXPECT_GT(r.moved, 0.2);  // the mesh did move
        EXPECT_LT(r.gcl, 1e-13);
        EXPECT_LT(r.deviation, 1e-12);
    }
}

TEST(UnsteadyMoving, FreeStreamStaysUniformOnADeformingMesh) {
    for (int order : {1, 2}) {
        const FreeStreamRun r = free_stream_run(0.0, 15.0 * deg, order);
        EXPECT_TRUE(r.converged);
        EXPECT_GT(r.moved, 0.05);
        // The volumes change: without grid fluxes balancing V^(n+1) U - V^n U^n the free stream
        // would not stay.
        EXPECT_GT(r.volume_change, 1e-3);
        EXPECT_LT(r.gcl, 1e-13);
        EXPECT_LT(r.deviation, 1e-12);
    }
    const FreeStreamRun both = free_stream_run(10.0 * deg, 15.0 * deg, 2);
    EXPECT_LT(both.gcl, 1e-13);
    EXPECT_LT(both.deviation, 1e-12);
}

TEST(UnsteadyMoving, RestoredTimeLevelsContinueBitForBit) {
    // Walls on the plate: a flow that changes. 6 steps at once against 3, restore on a fresh
    // mesh and solver, and 3 more.
    euler::UnsteadySettings t;
    t.dt = 0.05;
    t.max_inner = 8;
    MovingBox a(3.0 * deg, 10.0 * deg, true);
    euler::UnsteadySolver sa(a.domain(), a.comm, a.setup, t);
    sa.set_moving_mesh(a.moving());
    std::vector<euler::TimeStepRecord> ra;
    for (int n = 0; n < 6; ++n) ra.push_back(sa.advance());

    euler::TimeLevels levels;
    euler::NodeStates U3;
    {
        MovingBox b(3.0 * deg, 10.0 * deg, true);
        euler::UnsteadySolver sb(b.domain(), b.comm, b.setup, t);
        sb.set_moving_mesh(b.moving());
        for (int n = 0; n < 3; ++n) (void)sb.advance();
        levels = sb.time_levels();
        U3 = sb.state();
    }
    MovingBox c(3.0 * deg, 10.0 * deg, true);
    euler::UnsteadySolver sc(c.domain(), c.comm, c.setup, t);
    sc.set_moving_mesh(c.moving());
    sc.restore(U3, levels);
    EXPECT_EQ(sc.steps(), 3);
    for (int n = 3; n < 6; ++n) {
        const euler::TimeStepRecord r = sc.advance();
        EXPECT_EQ(r.inner_iterations, ra[static_cast<std::size_t>(n)].inner_iterations);
        EXPECT_EQ(r.forces.CL, ra[static_cast<std::size_t>(n)].forces.CL);
        EXPECT_EQ(r.forces.CMy, ra[static_cast<std::size_t>(n)].forces.CMy);
    }
    EXPECT_EQ((sc.state() - sa.state()).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_NE(ra[5].forces.CL, ra[2].forces.CL);
    EXPECT_EQ(a.mesh.coordinates()[17], c.mesh.coordinates()[17]);
}

TEST(UnsteadyMoving, BadInputIsRefused) {
    MovingBox b(1.0 * deg, 0.0);
    euler::UnsteadySettings t;
    t.dt = 0.05;
    euler::UnsteadySolver s(b.domain(), b.comm, b.setup, t);
    mesh::DualMetrics other = b.dual;
    EXPECT_THROW(s.set_moving_mesh({&b.mesh, &other, b.moving().coordinates}), InputError);
    EXPECT_THROW(s.set_moving_mesh({&b.mesh, &b.dual, {}}), InputError);
    EXPECT_THROW(s.set_moving_mesh(
                     {&b.mesh, &b.dual, [](double, long, Eigen::Matrix3Xd& x) { x.resize(3, 4); }}),
                 InputError);
    s.set_moving_mesh(b.moving());
    euler::TimeLevels l = s.time_levels();
    l.x.resize(3, 5);
    EXPECT_THROW(s.restore(s.state(), l), InputError);
}

}  // namespace

namespace {

TEST(UnsteadyMoving, ConfigurationKeys) {
    const manta::euler::CfdConfig c = manta::euler::parse_cfd_config(
        "mesh: {up: y}\n"
        "unsteady: {order: 1, max_inner: 12, inner_drop: 2.5, coefficient_window: 4,\n"
        "           coefficient_tolerance: 1e-5, output_every: 5, extrapolate: true,\n"
        "           jacobian_interval: 2}\n"
        "control_surfaces:\n"
        "  - {mode: elevator, marker: flap, hinge: [[1, 0.25, 0], [1, 0.75, 0]], gain: -1}\n",
        "cfd.yaml");
    EXPECT_EQ(c.mesh_up, "y");
    EXPECT_EQ(c.unsteady.order, 1);
    EXPECT_EQ(c.unsteady.max_inner, 12);
    EXPECT_EQ(c.unsteady.inner_drop, 2.5);
    EXPECT_EQ(c.unsteady.coefficient_window, 4);
    EXPECT_EQ(c.unsteady.coefficient_tolerance, 1e-5);
    EXPECT_TRUE(c.unsteady.extrapolate);
    EXPECT_EQ(c.unsteady.jacobian_interval, 2);
    EXPECT_EQ(c.output_every, 5);
    ASSERT_EQ(c.control_surfaces.size(), 1U);
    EXPECT_EQ(c.control_surfaces[0].marker, "flap");
    EXPECT_EQ(c.control_surfaces[0].gain, -1.0);
    EXPECT_EQ(c.control_surfaces[0].hinge[1].y(), 0.75);
    for (const char* bad :
         {"unsteady: {order: 3}\n", "unsteady: {jacobian_interval: 0}\n", "mesh: {up: x}\n",
          "unsteady: {max_steps: 3}\n", "control_surfaces: [{mode: elevator}]\n"}) {
        try {
            (void)manta::euler::parse_cfd_config(bad, "cfd.yaml");
            ADD_FAILURE() << bad;
        } catch (const manta::ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find("cfd.yaml"), std::string::npos) << e.what();
        } catch (const manta::InputError& e) {
            EXPECT_NE(std::string(e.what()).find("cfd.yaml"), std::string::npos) << e.what();
        }
    }
}

}  // namespace
