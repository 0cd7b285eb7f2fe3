/// @file test_mesh_motion.cpp
/// MeshMotion: rigid motion against hand-computed rotations, node velocities against finite
/// differences, the flap's exact rotation about its hinge, the fixed wall, cell validity at the
/// Ranger 2000's limits (paper, Table 3: elevator and ailerons -25/+15 deg, rudder +-17.5 deg),
/// and the one-line errors.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "flap_meshes.hpp"
#include "manta/core/error.hpp"
#include "manta/meshmotion/mesh_motion.hpp"

namespace {

using Eigen::Matrix3d;
using Eigen::Matrix3Xd;
using Eigen::Vector3d;
using manta::InputError;
using manta::aero::Motion;
using manta::mesh::Index;
using manta::meshmotion::ControlSurfaceSpec;
using manta::meshmotion::MeshMotion;
using manta::meshmotion::MotionPlacement;

constexpr double deg = std::numbers::pi / 180.0;

/// A motion of `n` samples over [0, 1] s with every column zero.
Motion still_motion(int n = 5) {
    Motion m;
    for (int i = 0; i < n; ++i) m.t.push_back(static_cast<double>(i) / (n - 1));
    for (auto& c : m.position) c.assign(m.t.size(), 0.0);
    for (auto& c : m.angles) c.assign(m.t.size(), 0.0);
    for (const char* name : {"elevator", "aileron", "rudder"})
        m.add_mode(name, std::vector<double>(m.t.size(), 0.0));
    return m;
}

/// A motion holding a constant deflection of `mode` after a ramp from zero over [0, 0.5] s.
Motion deflection_motion(const std::string& mode, double delta) {
    Motion m = still_motion(11);
    if (m.find_mode(mode) < 0) m.add_mode(mode, std::vector<double>(m.t.size(), 0.0));
    auto& col = m.modes[static_cast<std::size_t>(m.find_mode(mode))];
    for (std::size_t i = 0; i < m.t.size(); ++i) col[i] = delta * std::min(1.0, m.t[i] / 0.5);
    return m;
}

const manta::mesh::Mesh& wing() {
    static const manta::mesh::Mesh m = manta::test::flap_wing(1.0);
    return m;
}

/// The flap of flap_wing: hinge on the camber line at x = 0.75 from y = 1 to y = 2 (toward +y,
/// so that a positive deflection is trailing edge down).
ControlSurfaceSpec wing_flap(const std::string& mode = "elevator") {
    ControlSurfaceSpec s;
    s.mode = mode;
    s.marker = "flap";
    s.hinge = {Vector3d(0.75, 1.0, 0.0), Vector3d(0.75, 2.0, 0.0)};
    s.source = "test";
    return s;
}

std::vector<char> marker_nodes(const manta::mesh::Mesh& m, const std::string& name) {
    std::vector<char> on(static_cast<std::size_t>(m.n_nodes()), 0);
    const int k = m.find_marker(name);
    for (Index f = 0; f < m.n_faces(); ++f)
        if (m.face_marker(f) == k)
            for (const Index v : m.face(f)) on[static_cast<std::size_t>(v)] = 1;
    return on;
}

// ------------------------------------------------------------------------------------- rigid

TEST(RigidMotion, PitchRaisesTheNoseAboutTheReferencePoint) {
    // theta = alpha > 0 is nose up (docs/formats.md, motion frame): a point 1 m ahead of the
    // reference point (geometry x aft, z up) goes to (-cos theta, 0, sin theta) from it.
    Motion m = still_motion();
    const double theta = 0.3;
    m.angles[1].assign(m.t.size(), theta);
    const Vector3d g(0.25, 0.0, 0.1);
    const manta::meshmotion::RigidPose p = manta::meshmotion::rigid_pose(m.at(0.5), g);
    const Vector3d nose = p.translation + p.rotation * (g + Vector3d(-1.0, 0.0, 0.0));
    EXPECT_NEAR((nose - g - Vector3d(-std::cos(theta), 0.0, std::sin(theta))).norm(), 0.0, 1e-15);
    // Plunge: z_ref positive is down in the motion frame, so the mesh moves to -z.
    m.angles[1].assign(m.t.size(), 0.0);
    m.position[2].assign(m.t.size(), 0.2);
    const auto q = manta::meshmotion::rigid_pose(m.at(0.5), g);
    EXPECT_NEAR((q.translation - Vector3d(0.0, 0.0, -0.2)).norm(), 0.0, 1e-15);
}

TEST(RigidMotion, MatchesAnIndependentRotationAndKeepsTheMeshRigid) {
    // x = g + D r + D Rz(psi) Ry(theta) Rx(phi) D (x0 - g): the 3-2-1 sequence from the motion
    // frame to body axes, inverted as the product of active rotations (Eigen's AngleAxis), with
    // D = diag(-1, 1, -1) between geometry and body/motion axes (docs/conventions.md).
    const manta::mesh::Mesh mesh = manta::test::flap_plate(6, 4, 3);
    Motion m = still_motion(9);
    for (std::size_t i = 0; i < m.t.size(); ++i) {
        const double t = m.t[i];
        m.position[0][i] = 0.4 * t;
        m.position[1][i] = -0.2 * t * t;
        m.position[2][i] = 0.1 * std::sin(3.0 * t);
        m.angles[0][i] = 0.5 * t;
        m.angles[1][i] = -0.3 + 0.6 * t * t;
        m.angles[2][i] = 0.8 * std::sin(t);
    }
    const Vector3d g(0.5, 0.4, 0.3);
    const MeshMotion mm(mesh, m, MotionPlacement{g, "motion"}, {});
    Matrix3Xd x;
    const double t = 0.63;
    mm.coordinates_at(t, x);
    const auto s = m.at(t);
    const Matrix3d Dm = Vector3d(-1.0, 1.0, -1.0).asDiagonal();
    const Matrix3d body_to_motion = (Eigen::AngleAxisd(s.euler[2], Vector3d::UnitZ()) *
                                     Eigen::AngleAxisd(s.euler[1], Vector3d::UnitY()) *
                                     Eigen::AngleAxisd(s.euler[0], Vector3d::UnitX()))
                                        .toRotationMatrix();
    const Vector3d r(s.position[0], s.position[1], s.position[2]);
    double err = 0.0, stretch = 0.0;
    for (Index i = 0; i < mesh.n_nodes(); ++i) {
        const Vector3d expected = g + Dm * r + Dm * body_to_motion * Dm * (mesh.node(i) - g);
        err = std::max(err, (x.col(i) - expected).norm());
        if (i > 0)
            stretch = std::max(stretch, std::abs((x.col(i) - x.col(0)).norm() -
                                                 (mesh.node(i) - mesh.node(0)).norm()));
    }
    EXPECT_LT(err, 1e-14);
    EXPECT_LT(stretch, 1e-14);
    EXPECT_EQ(mm.n_checked_cells(), 0U);  // nothing deforms: no cell to check
}

TEST(RigidMotion, VelocitiesAreTheTimeDerivativeOfTheCoordinates) {
    Motion m = deflection_motion("elevator", -20.0 * deg);
    for (std::size_t i = 0; i < m.t.size(); ++i) {
        const double t = m.t[i];
        m.position[2][i] = 0.05 * t * t;
        m.angles[0][i] = 0.2 * t;
        m.angles[1][i] = 0.1 * t * t * t;
        m.angles[2][i] = -0.1 * t;
    }
    const manta::mesh::Mesh mesh = manta::test::flap_plate(12, 8, 4);
    ControlSurfaceSpec flap;
    flap.mode = "elevator";
    flap.marker = "flap";
    flap.hinge = {Vector3d(1.0, 0.25, 0.0), Vector3d(1.0, 0.75, 0.0)};
    const MeshMotion mm(mesh, m, MotionPlacement{Vector3d(1.0, 0.5, 0.0), "motion"}, {flap});
    Matrix3Xd x, v, xp, xm;
    const double t = 0.33, h = 1e-5;
    mm.state_at(t, x, v);
    mm.coordinates_at(t + h, xp);
    mm.coordinates_at(t - h, xm);
    const Matrix3Xd fd = (xp - xm) / (2.0 * h);
    EXPECT_LT((fd - v).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, v.cwiseAbs().maxCoeff()));
    Matrix3Xd x2;
    mm.coordinates_at(t, x2);
    EXPECT_EQ((x - x2).cwiseAbs().maxCoeff(), 0.0);
}

TEST(RigidMotion, PlungeRateRaisesTheAngleOfAttackAsTheLatticeDoes) {
    // The air moves at (+v0, 0, 0) in the flow frame; relative to the mesh, in axes fixed to it,
    // it is R^T ((v0, 0, 0) - v_mesh): the vortex lattice's v_inf = -D C ((v0, 0, 0) + dr/dt)
    // (src/vlm/unsteady.cpp), so a sinking rate z_dot gives alpha = atan(z_dot / v0).
    Motion m = still_motion(9);
    const double v0 = 50.0, zdot = 2.0, theta = 0.05;
    for (std::size_t i = 0; i < m.t.size(); ++i) {
        m.position[2][i] = zdot * m.t[i];
        m.angles[1][i] = theta;
    }
    const auto p = manta::meshmotion::rigid_pose(m.at(0.5), Vector3d::Zero());
    const Vector3d air = p.rotation.transpose() * (Vector3d(v0, 0.0, 0.0) - p.velocity);
    EXPECT_NEAR(std::atan2(air.z(), air.x()), theta + std::atan(zdot / v0), 1e-12);
}

// -------------------------------------------------------------------------------------- flap

TEST(FlapWing, FlapRotatesExactlyAboutItsHingeAndTheWingStaysFixed) {
    const manta::mesh::Mesh& mesh = wing();
    const ControlSurfaceSpec flap = wing_flap();
    const auto t0 = std::chrono::steady_clock::now();
    const MeshMotion mm(mesh, deflection_motion("elevator", -25.0 * deg), {}, {flap});
    const double setup =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto& info = mm.info().at(0);
    std::printf(
        "flap_wing: %d nodes; flap %d nodes (%d seam), %d candidates, %d points, %d nodes "
        "moved, error ratio %.3f; set-up %.3f s\n",
        mesh.n_nodes(), info.n_marker_nodes, info.n_seam_nodes, info.n_candidates, info.n_points,
        info.n_affected, info.error_ratio, setup);
    EXPECT_LE(info.error_ratio, 1.0);
    EXPECT_NEAR(info.chord, 0.25, 0.01);
    const auto on_flap = marker_nodes(mesh, "flap");
    const auto on_wing = marker_nodes(mesh, "wing");
    const Vector3d a = flap.hinge[0], e = (flap.hinge[1] - flap.hinge[0]).normalized();
    for (const double delta : {-25.0 * deg, 15.0 * deg}) {
        Matrix3Xd y;
        mm.deformed({delta}, y);
        const Matrix3d R = Eigen::AngleAxisd(delta, e).toRotationMatrix();
        double rot_err = 0.0, dist_err = 0.0, fixed = 0.0;
        int n_rigid = 0;
        for (Index i = 0; i < mesh.n_nodes(); ++i) {
            const auto ii = static_cast<std::size_t>(i);
            const Vector3d p = mesh.node(i);
            if (on_wing[ii] && !on_flap[ii]) fixed = std::max(fixed, (y.col(i) - p).norm());
            if (!on_flap[ii]) continue;
            // Outside the blend band (0.125 m at most from the side edges y = 1, 2; 0.0625 m at
            // most from the hinge-line seams x = 0.75) the flap rotates rigidly.
            if (p.y() < 1.0 + 0.13 || p.y() > 2.0 - 0.13 || p.x() < 0.75 + 0.13) continue;
            ++n_rigid;
            const Vector3d rp = (p - a) - e * e.dot(p - a);
            const Vector3d q = y.col(i);
            const Vector3d rq = (q - a) - e * e.dot(q - a);
            dist_err = std::max(dist_err, std::abs(rq.norm() - rp.norm()));
            rot_err = std::max(rot_err, (q - (a + R * (p - a))).norm());
        }
        EXPECT_GT(n_rigid, 20);
        EXPECT_LT(dist_err, 1e-12) << delta / deg;
        EXPECT_LT(rot_err, 1e-12) << delta / deg;
        EXPECT_EQ(fixed, 0.0);  // the wing's own nodes, seams included, never move
    }
}

TEST(FlapWing, NoCellFoldsAtTheRangersElevatorLimits) {
    // Ranger 2000 elevator and ailerons -25/+15 deg (paper, Table 3).
    const manta::mesh::Mesh& mesh = wing();
    for (const double delta : {-25.0 * deg, 15.0 * deg}) {
        const MeshMotion mm(mesh, deflection_motion("elevator", delta), {}, {wing_flap()});
        Matrix3Xd x;
        const auto t0 = std::chrono::steady_clock::now();
        constexpr int n_steps = 20;
        for (int k = 0; k < n_steps; ++k) mm.coordinates_at(0.5 + 0.5 * k / n_steps, x, k);
        const double step =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / n_steps;
        EXPECT_NO_THROW(mm.check_motion());
        // The smallest cell volume relative to its reference.
        double ratio = 1e300;
        for (Index c = 0; c < mesh.n_cells(); ++c) {
            const auto n = mesh.cell(c);
            const Vector3d p0 = x.col(n[0]);
            const double v = (x.col(n[1]) - p0).cross(x.col(n[2]) - p0).dot(x.col(n[3]) - p0) / 6.0;
            ratio = std::min(ratio, v / mesh.cell_volume(c));
        }
        std::printf(
            "flap at %+.0f deg: smallest cell volume / reference %.3f; %zu cells "
            "checked; %.2f ms per step\n",
            delta / deg, ratio, mm.n_checked_cells(), 1e3 * step);
        EXPECT_GT(ratio, 0.1);
    }
}

TEST(FlapWing, AFoldingDeflectionNamesTheNodeAndTheLargestValidDeflection) {
    // A flap plate sealed on four edges rotated up by 85 deg with 0.1 m blend bands: its middle
    // rises 0.7 m within 0.25 m of its fixed side edges.
    const manta::mesh::Mesh mesh = manta::test::flap_plate(12, 8, 4);
    ControlSurfaceSpec flap;
    flap.mode = "elevator";
    flap.marker = "flap";
    flap.hinge = {Vector3d(1.0, 0.25, 0.0), Vector3d(1.0, 0.75, 0.0)};
    flap.hinge_blend = 0.1;
    flap.edge_blend = 0.1;
    const MeshMotion mm(mesh, deflection_motion("elevator", -85.0 * deg),
                        MotionPlacement{Vector3d::Zero(), "pitch.csv"}, {flap});
    Matrix3Xd x;
    EXPECT_NO_THROW(mm.coordinates_at(0.05, x, 1));
    try {
        mm.coordinates_at(1.0, x, 7);
        FAIL() << "no error";
    } catch (const InputError& e) {
        const std::string msg = e.what();
        std::printf("%s\n", msg.c_str());
        EXPECT_NE(msg.find("pitch.csv, step 7: t = 1 s"), std::string::npos) << msg;
        EXPECT_NE(msg.find("folds at node"), std::string::npos) << msg;
        EXPECT_NE(msg.find("elevator -85 deg"), std::string::npos) << msg;
        EXPECT_NE(msg.find("largest deflection that keeps every cell valid"), std::string::npos)
            << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos);
    }
    EXPECT_THROW(mm.check_motion(), InputError);
}

TEST(FlapPlate, HexahedraAndPrismsStayValidWithAnExactRotation) {
    // The plate's flap is sealed on all four edges (its trailing edge too), so it bulges; with
    // 0.1 m blend bands its middle x in [1.2, 1.8], y in [0.4, 0.6] rotates rigidly.
    for (const bool prisms : {false, true}) {
        const manta::mesh::Mesh mesh = manta::test::flap_plate(24, 16, 8, prisms);
        ControlSurfaceSpec s;
        s.mode = "rudder";
        s.marker = "flap";
        s.hinge = {Vector3d(1.0, 0.25, 0.0), Vector3d(1.0, 0.75, 0.0)};
        s.hinge_blend = 0.1;
        s.edge_blend = 0.1;
        for (const double delta : {-10.0 * deg, 10.0 * deg}) {
            const MeshMotion mm(mesh, deflection_motion("rudder", delta), {}, {s});
            Matrix3Xd x;
            EXPECT_NO_THROW(mm.coordinates_at(1.0, x)) << prisms << " " << delta / deg;
            const auto on = marker_nodes(mesh, "flap");
            const Matrix3d R = Eigen::AngleAxisd(delta, Vector3d::UnitY()).toRotationMatrix();
            const Vector3d a(1.0, 0.25, 0.0);
            double err = 0.0;
            int n = 0;
            for (Index i = 0; i < mesh.n_nodes(); ++i) {
                const Vector3d p = mesh.node(i);
                if (!on[static_cast<std::size_t>(i)] || p.x() < 1.2 || p.x() > 1.8 || p.y() < 0.4 ||
                    p.y() > 0.6)
                    continue;
                ++n;
                err = std::max(err, (x.col(i) - (a + R * (p - a))).norm());
            }
            EXPECT_GT(n, 10);
            EXPECT_LT(err, 1e-12);
        }
    }
}

TEST(FlapPlate, TheGainScalesTheDeflection) {
    // A surface with gain -1 driven by -delta moves as the surface with gain +1 driven by delta.
    const manta::mesh::Mesh mesh = manta::test::flap_plate(12, 8, 4);
    ControlSurfaceSpec s;
    s.mode = "aileron";
    s.marker = "flap";
    s.hinge = {Vector3d(1.0, 0.25, 0.0), Vector3d(1.0, 0.75, 0.0)};
    const MeshMotion plus(mesh, deflection_motion("aileron", 10.0 * deg), {}, {s});
    s.gain = -1.0;
    const MeshMotion minus(mesh, deflection_motion("aileron", -10.0 * deg), {}, {s});
    Matrix3Xd a, b;
    plus.coordinates_at(1.0, a);
    minus.coordinates_at(1.0, b);
    EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-15);
}

// ------------------------------------------------------------------------------------ errors

TEST(MeshMotionErrors, HingeOffTheSurfaceNamesTheMarkerAndTheDistance) {
    const manta::mesh::Mesh mesh = manta::test::flap_plate(12, 8, 4);
    ControlSurfaceSpec s;
    s.mode = "elevator";
    s.marker = "flap";
    s.source = "cfd.yaml:7";
    s.hinge = {Vector3d(1.0, 0.25, 0.5), Vector3d(1.0, 0.75, 0.5)};  // 0.5 m above the plate
    try {
        const MeshMotion mm(mesh, still_motion(), {}, {s});
        FAIL() << "no error";
    } catch (const InputError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("cfd.yaml:7"), std::string::npos) << msg;
        EXPECT_NE(msg.find("marker 'flap'"), std::string::npos) << msg;
        EXPECT_NE(msg.find("is 0.5 m from the nearest node"), std::string::npos) << msg;
    }
    s.hinge_tolerance = 0.6;  // an explicit tolerance accepts it
    EXPECT_NO_THROW(MeshMotion(mesh, still_motion(), {}, {s}));
}

TEST(MeshMotionErrors, ModesMarkersAndControlSurfacesMustMatch) {
    const manta::mesh::Mesh mesh = manta::test::flap_plate(12, 8, 4);
    ControlSurfaceSpec s;
    s.mode = "elevator";
    s.marker = "flap";
    s.hinge = {Vector3d(1.0, 0.25, 0.0), Vector3d(1.0, 0.75, 0.0)};
    auto message = [&](const Motion& m, const std::vector<ControlSurfaceSpec>& specs) {
        try {
            const MeshMotion mm(mesh, m, MotionPlacement{Vector3d::Zero(), "m.csv"}, specs);
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    // A mode that deflects with no control surface.
    std::string msg = message(deflection_motion("flap", 0.1), {s});
    EXPECT_NE(msg.find("mode 'flap' deflects"), std::string::npos) << msg;
    EXPECT_NE(msg.find("m.csv"), std::string::npos) << msg;
    // A control surface whose mode the motion lacks.
    s.mode = "flaps";
    msg = message(still_motion(), {s});
    EXPECT_NE(msg.find("mode 'flaps'"), std::string::npos) << msg;
    // A marker the mesh lacks; the same marker twice.
    s.mode = "elevator";
    s.marker = "flop";
    msg = message(still_motion(), {s});
    EXPECT_NE(msg.find("'flop' is not a marker"), std::string::npos) << msg;
    s.marker = "flap";
    msg = message(still_motion(), {s, s});
    EXPECT_NE(msg.find("two control surfaces"), std::string::npos) << msg;
    // Zero-valued modes need no control surface, nor round-off (a trimmed trajectory's 2e-25 rad
    // of aileron); 1e-8 rad does.
    EXPECT_EQ(message(still_motion(), {}), "");
    EXPECT_EQ(message(deflection_motion("flap", 2e-25), {}), "");
    EXPECT_NE(message(deflection_motion("flap", 1e-8), {}).find("mode 'flap' deflects"),
              std::string::npos);
}

}  // namespace
