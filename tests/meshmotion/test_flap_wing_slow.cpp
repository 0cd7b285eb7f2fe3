/// @file test_flap_wing_slow.cpp
/// MeshMotion on a wing mesh of more than 100 000 nodes with a flap: set-up and per-step time
/// (printed; speed itself is not a pass/fail criterion), cell validity at the Ranger 2000's
/// elevator limits -25/+15 deg (paper, Table 3) together with a rigid pitch and plunge.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "flap_meshes.hpp"
#include "manta/meshmotion/mesh_motion.hpp"

namespace {

using Eigen::Vector3d;
using manta::meshmotion::ControlSurfaceSpec;
using manta::meshmotion::MeshMotion;

constexpr double deg = std::numbers::pi / 180.0;

TEST(FlapWingLarge, SetUpAndStepTimesAndNoFoldAtTheLimits) {
    auto t0 = std::chrono::steady_clock::now();
    const manta::mesh::Mesh mesh = manta::test::flap_wing(0.4);
    const double t_mesh =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_GE(mesh.n_nodes(), 100000);
    ControlSurfaceSpec flap;
    flap.mode = "elevator";
    flap.marker = "flap";
    flap.hinge = {Vector3d(0.75, 1.0, 0.0), Vector3d(0.75, 2.0, 0.0)};
    // Elevator from -25 to +15 deg and back over one second while pitching and plunging.
    manta::aero::Motion m;
    constexpr int n = 41;
    for (int i = 0; i < n; ++i) {
        const double t = static_cast<double>(i) / (n - 1);
        m.t.push_back(t);
        m.position[0].push_back(0.0);
        m.position[1].push_back(0.0);
        m.position[2].push_back(0.05 * std::sin(2.0 * std::numbers::pi * t));
        m.angles[0].push_back(0.0);
        m.angles[1].push_back(5.0 * deg * std::sin(2.0 * std::numbers::pi * t));
        m.angles[2].push_back(0.0);
    }
    std::vector<double> elevator;
    for (const double t : m.t)
        elevator.push_back((-5.0 - 20.0 * std::cos(2.0 * std::numbers::pi * t)) * deg);
    m.add_mode("elevator", elevator);
    m.add_mode("aileron", std::vector<double>(n, 0.0));
    m.add_mode("rudder", std::vector<double>(n, 0.0));

    const MeshMotion mm(mesh, m, {Vector3d(0.25, 0.0, 0.0), "motion"}, {flap});
    const auto& info = mm.info().at(0);
    // 600 points (the default cap) leave the interpolation error on the surface at a few
    // tenths of the local edge length on this mesh; the cells stay valid.
    EXPECT_LE(info.error_ratio, 5.0);
    Eigen::Matrix3Xd x(3, mesh.n_nodes());
    constexpr int n_steps = 100;
    t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < n_steps; ++k) EXPECT_NO_THROW(mm.coordinates_at(k * 0.01, x, k));
    const double t_step =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / n_steps;
    EXPECT_NO_THROW(mm.check_motion());
    // Smallest cell volume relative to its reference at -25 deg (t = 0) and +15 deg (t = 0.5).
    double ratio[2] = {1e300, 1e300};
    for (int k = 0; k < 2; ++k) {
        mm.coordinates_at(0.5 * k, x);
        for (manta::mesh::Index c = 0; c < mesh.n_cells(); ++c) {
            const auto nd = mesh.cell(c);
            const Vector3d p0 = x.col(nd[0]);
            const double v =
                (x.col(nd[1]) - p0).cross(x.col(nd[2]) - p0).dot(x.col(nd[3]) - p0) / 6.0;
            ratio[k] = std::min(ratio[k], v / mesh.cell_volume(c));
        }
        EXPECT_GT(ratio[k], 0.1);
    }
    std::printf(
        "flap_wing(0.4): %d nodes, %d cells (mesh %.1f s); flap %d nodes, %d candidates, "
        "%d points, %d nodes moved, %zu cells checked; error ratio %.3f; set-up %.3f s; "
        "%.2f ms per step (deformation, check, rigid motion); smallest volume ratio %.3f at "
        "-25 deg, %.3f at +15 deg\n",
        mesh.n_nodes(), mesh.n_cells(), t_mesh, info.n_marker_nodes, info.n_candidates,
        info.n_points, info.n_affected, mm.n_checked_cells(), info.error_ratio, mm.setup_seconds(),
        1e3 * t_step, ratio[0], ratio[1]);
}

}  // namespace
