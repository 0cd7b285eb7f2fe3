/// @file test_deforming_motion.cpp
/// MeshMotion's deforming body motion (docs/mesh-motion.md, "Deforming body motion"): on the
/// half-model flap wing the walls move exactly as the rigid motion moves them, the far field does
/// not move, the nodes of the symmetry plane stay in it (sliding), the blend between is smooth
/// enough that no cell folds at 10 deg of pitch, the node velocities are the time derivative of
/// the coordinates, the control-surface modes ride on top, and the one-line errors (a symmetry
/// marker that is not plane, a wall that touches the far field, radii that do not fit, a motion
/// that folds cells); a flap spanning a one-cell slab slides on its symmetry planes.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "flap_meshes.hpp"
#include "manta/core/error.hpp"
#include "manta/meshmotion/mesh_motion.hpp"

namespace {

using Eigen::Matrix3Xd;
using Eigen::Vector3d;
using manta::InputError;
using manta::aero::Motion;
using manta::mesh::Index;
using manta::meshmotion::BodyMotion;
using manta::meshmotion::DeformationOptions;
using manta::meshmotion::MeshMotion;
using manta::meshmotion::MotionPlacement;

constexpr double deg = std::numbers::pi / 180.0;

/// Pitch `theta` sin(2 pi t), roll `phi` sin(2 pi t), plunge 0.1 sin(2 pi t) m and the elevator
/// `flap` sin(2 pi t), 41 samples over [0, 1] s.
Motion motion(double theta, double phi = 0.0, double flap = 0.0, double plunge = 0.1) {
    Motion m;
    for (int i = 0; i <= 40; ++i) m.t.push_back(i / 40.0);
    for (auto& c : m.position) c.assign(m.t.size(), 0.0);
    for (auto& c : m.angles) c.assign(m.t.size(), 0.0);
    std::vector<double> e(m.t.size());
    for (std::size_t i = 0; i < m.t.size(); ++i) {
        const double s = std::sin(2.0 * std::numbers::pi * m.t[i]);
        m.angles[0][i] = phi * s;
        m.angles[1][i] = theta * s;
        m.position[2][i] = plunge * s;
        e[i] = flap * s;
    }
    m.add_mode("elevator", e);
    m.add_mode("aileron", std::vector<double>(m.t.size(), 0.0));
    m.add_mode("rudder", std::vector<double>(m.t.size(), 0.0));
    return m;
}

const manta::mesh::Mesh& wing() {
    static const manta::mesh::Mesh m = manta::test::flap_wing(1.0);
    return m;
}

DeformationOptions deforming() {
    DeformationOptions o;
    o.body = BodyMotion::deforming;
    o.wall_markers = {"wing", "flap"};
    o.symmetry_markers = {"symmetry"};
    return o;
}

std::vector<char> on_marker(const manta::mesh::Mesh& m, const std::string& name) {
    std::vector<char> on(static_cast<std::size_t>(m.n_nodes()), 0);
    const int k = m.find_marker(name);
    for (Index f = 0; f < m.n_faces(); ++f)
        if (m.face_marker(f) == k)
            for (const Index v : m.face(f)) on[static_cast<std::size_t>(v)] = 1;
    return on;
}

const Vector3d g(0.25, 0.0, 0.0);

/// Largest distance of the wall nodes from their rigid image, of the far-field nodes from their
/// reference place, of the symmetry nodes from the plane y = 0.
struct Errors {
    double wall = 0, wall_off_plane = 0, farfield = 0, symmetry = 0, moved = 0;
};
Errors errors(const MeshMotion& mm, const Motion& m, double t) {
    const auto& mesh = wing();
    Matrix3Xd x;
    mm.coordinates_at(t, x);
    const auto pose = manta::meshmotion::rigid_pose(m.at(t), g);
    const auto wing_nodes = on_marker(mesh, "wing"), flap = on_marker(mesh, "flap"),
               far = on_marker(mesh, "farfield"), sym = on_marker(mesh, "symmetry");
    Errors e;
    for (Index i = 0; i < mesh.n_nodes(); ++i) {
        const auto k = static_cast<std::size_t>(i);
        const Vector3d x0 = mesh.node(i);
        e.moved = std::max(e.moved, (x.col(i) - x0).norm());
        if (wing_nodes[k] || flap[k]) {
            const double d = (x.col(i) - (pose.translation + pose.rotation * x0)).norm();
            e.wall = std::max(e.wall, d);
            if (!sym[k]) e.wall_off_plane = std::max(e.wall_off_plane, d);
        }
        if (far[k]) e.farfield = std::max(e.farfield, (x.col(i) - x0).norm());
        if (sym[k]) e.symmetry = std::max(e.symmetry, std::abs(x(1, i)));
    }
    return e;
}

TEST(DeformingMotion, WallsMoveRigidlyTheFarFieldStaysAndTheSymmetryPlaneSlides) {
    const Motion m = motion(10.0 * deg);
    const MeshMotion mm(wing(), m, MotionPlacement{g, "pitch.csv"}, {}, deforming());
    const auto& b = mm.body_info();
    std::printf(
        "flap wing: %d wall nodes, %d sliding, %d fixed, %d blended, radii %.3f and %.3f m, "
        "%zu cells checked, set-up %.3f s\n",
        b.n_wall_nodes, b.n_sliding_nodes, b.n_fixed_nodes, b.n_blended_nodes, b.rigid_radius,
        b.fixed_radius, mm.n_checked_cells(), mm.setup_seconds());
    EXPECT_GT(b.n_wall_nodes, 500);
    EXPECT_GT(b.n_sliding_nodes, 100);
    // The far field is the box x in [-10, 11], y in [0, 10], z in [-10, 10] m; the wing's box
    // ends at y = 3 m (the tip's nodes within 1e-3 m of it): the nearest far-field node is 7 m
    // away (the box face y = 10).
    EXPECT_NEAR(b.fixed_radius, 7.0, 1e-3);
    EXPECT_GT(b.rigid_radius, 1.0);
    mm.check_motion();  // no cell folds at any sample
    for (const double t : {0.25, 0.6}) {
        const Errors e = errors(mm, m, t);
        EXPECT_GT(e.moved, 0.1);
        EXPECT_LT(e.wall, 1e-12);  // pitch and plunge are in the symmetry plane: nothing lost
        EXPECT_EQ(e.farfield, 0.0);
        EXPECT_LT(e.symmetry, 1e-15);
    }
}

TEST(DeformingMotion, AMotionOutOfTheSymmetryPlaneIsProjectedOntoIt) {
    // Roll moves the root section out of y = 0: the symmetry nodes stay in the plane, the walls
    // away from it move rigidly.
    const Motion m = motion(0.0, 5.0 * deg);
    const MeshMotion mm(wing(), m, MotionPlacement{g, "roll.csv"}, {}, deforming());
    const Errors e = errors(mm, m, 0.25);
    EXPECT_LT(e.symmetry, 1e-15);
    EXPECT_LT(e.wall_off_plane, 1e-12);
    EXPECT_GT(e.wall, 1e-3);  // the root's nodes were held in the plane
}

TEST(DeformingMotion, VelocitiesAreTheTimeDerivativeOfTheCoordinates) {
    const Motion m = motion(8.0 * deg, 2.0 * deg, -15.0 * deg);
    manta::meshmotion::ControlSurfaceSpec flap;
    flap.mode = "elevator";
    flap.marker = "flap";
    flap.hinge = {Vector3d(0.75, 1.0, 0.0), Vector3d(0.75, 2.0, 0.0)};
    const MeshMotion mm(wing(), m, MotionPlacement{g, "motion"}, {flap}, deforming());
    Matrix3Xd x, v, xp, xm, vd;
    const double t = 0.37, h = 1e-5;
    mm.state_at(t, x, v);
    mm.coordinates_at(t + h, xp);
    mm.coordinates_at(t - h, xm);
    Matrix3Xd xc;
    mm.coordinates_at(t, xc);
    EXPECT_EQ((x - xc).cwiseAbs().maxCoeff(), 0.0);
    const double err = ((xp - xm) / (2.0 * h) - v).cwiseAbs().maxCoeff();
    EXPECT_LT(err, 1e-6 * v.cwiseAbs().maxCoeff()) << err;
    // The flap on top: its nodes away from the blend band sit at the rigid image of their
    // deflected place.
    std::vector<double> delta{m.at(t).modes[0]};
    Matrix3Xd y;
    mm.deformed(delta, y);
    const auto pose = manta::meshmotion::rigid_pose(m.at(t), g);
    const auto fl = on_marker(wing(), "flap");
    double flap_err = 0.0;
    for (Index i = 0; i < wing().n_nodes(); ++i)
        if (fl[static_cast<std::size_t>(i)])
            flap_err = std::max(flap_err,
                                (x.col(i) - (pose.translation + pose.rotation * y.col(i))).norm());
    EXPECT_LT(flap_err, 1e-12);
}

std::string error_of(const manta::mesh::Mesh& mesh, const Motion& m, const DeformationOptions& o,
                     bool run = false) {
    try {
        const MeshMotion mm(mesh, m, MotionPlacement{g, "pitch.csv"}, {}, o);
        if (run) mm.check_motion();
    } catch (const InputError& e) {
        const std::string s = e.what();
        EXPECT_EQ(s.find('\n'), std::string::npos) << s;
        return s;
    }
    return "";
}

TEST(DeformingMotion, BadInputIsAOneLineError) {
    const Motion m = motion(2.0 * deg);
    // A symmetry marker that is not plane: one node 1 cm off y = 0.
    manta::mesh::Mesh bent = wing();
    const auto sym = on_marker(bent, "symmetry");
    Index off = -1;
    for (Index i = 0; i < bent.n_nodes() && off < 0; ++i)
        if (sym[static_cast<std::size_t>(i)] && bent.node(i).x() > 3.0) off = i;
    bent.set_node(off, bent.node(off) + Vector3d(0.0, 0.01, 0.0));
    std::string e = error_of(bent, m, deforming());
    EXPECT_NE(e.find("symmetry marker 'symmetry' is not plane"), std::string::npos) << e;
    EXPECT_NE(e.find(fmt::format("node {}", off)), std::string::npos) << e;

    // The flap plate's wall meets the far field on the box's edges.
    DeformationOptions plate = deforming();
    plate.wall_markers = {"flap", "wall"};
    plate.symmetry_markers = {};
    e = error_of(manta::test::flap_plate(6, 4, 4), m, plate);
    EXPECT_NE(e.find("holds fixed"), std::string::npos) << e;

    DeformationOptions o = deforming();
    o.fixed_radius = 8.0;  // the far field is 7 m away
    e = error_of(wing(), m, o);
    EXPECT_NE(e.find("fixed_radius 8 m reaches past the fixed boundary"), std::string::npos) << e;
    o = deforming();
    o.rigid_radius = 7.5;
    e = error_of(wing(), m, o);
    EXPECT_NE(e.find("rigid_radius 7.5 m; expected less than fixed_radius 7.0001"),
              std::string::npos)
        << e;
    o = deforming();
    o.wall_markers = {"wings"};
    e = error_of(wing(), m, o);
    EXPECT_NE(e.find("wall marker 'wings'"), std::string::npos) << e;

    // A pitch of 80 deg squeezed into a 0.5 m band folds cells: the step's error names the
    // cell, the node and the largest fraction of the motion that still worked.
    o = deforming();
    o.rigid_radius = 1.0;
    o.fixed_radius = 1.5;
    const Motion big = motion(80.0 * deg, 0.0, 0.0, 0.0);
    e = error_of(wing(), big, o, true);
    EXPECT_NE(e.find("pitch.csv: t = "), std::string::npos) << e;
    EXPECT_NE(e.find("folds at node"), std::string::npos) << e;
    EXPECT_NE(e.find("the largest fraction of the motion that keeps every cell valid is"),
              std::string::npos)
        << e;
    std::printf("%s\n", e.c_str());
    const MeshMotion mm(wing(), big, MotionPlacement{g, "pitch.csv"}, {}, o);
    Matrix3Xd x;
    try {
        mm.coordinates_at(0.25, x, 10);
        ADD_FAILURE() << "no fold";
    } catch (const InputError& err) {
        EXPECT_NE(std::string(err.what()).find("pitch.csv, step 10: t = 0.25 s"), std::string::npos)
            << err.what();
    }
}

/// A one-cell slab of hexahedra, [0, 3] x [0, 1] x [0, 1] m, n_x cells along x and n_z along z:
/// the wall z = 0 is `flap` for 1 <= x <= 2 (hinge along y at x = 1) and `wall` elsewhere, the
/// planes y = 0 and y = 1 are `symmetry_back` and `symmetry_front`, the rest `farfield`. Every
/// node of the flap lies on a symmetry plane.
manta::mesh::Mesh flap_slab(int n_x, int n_z) {
    using manta::mesh::CellType;
    using manta::mesh::FaceType;
    manta::mesh::Mesh m("flap_slab");
    auto id = [&](int i, int j, int k) { return static_cast<Index>(i + (n_x + 1) * (j + 2 * k)); };
    for (int k = 0; k <= n_z; ++k)
        for (int j = 0; j <= 1; ++j)
            for (int i = 0; i <= n_x; ++i) m.add_node(Vector3d(3.0 * i / n_x, j, 1.0 * k / n_z));
    const int wall = m.add_marker("wall"), flap = m.add_marker("flap"),
              back = m.add_marker("symmetry_back"), front = m.add_marker("symmetry_front"),
              far = m.add_marker("farfield");
    auto quad = [&](Index a, Index b, Index c, Index d, int marker) {
        m.add_face(FaceType::quad, std::array<Index, 4>{a, b, c, d}, marker);
    };
    for (int k = 0; k < n_z; ++k)
        for (int i = 0; i < n_x; ++i) {
            m.add_cell(CellType::hexa,
                       std::array<Index, 8>{id(i, 0, k), id(i + 1, 0, k), id(i + 1, 1, k),
                                            id(i, 1, k), id(i, 0, k + 1), id(i + 1, 0, k + 1),
                                            id(i + 1, 1, k + 1), id(i, 1, k + 1)});
            quad(id(i, 0, k), id(i + 1, 0, k), id(i + 1, 0, k + 1), id(i, 0, k + 1), back);
            quad(id(i, 1, k), id(i + 1, 1, k), id(i + 1, 1, k + 1), id(i, 1, k + 1), front);
        }
    for (int i = 0; i < n_x; ++i) {
        quad(id(i, 0, 0), id(i + 1, 0, 0), id(i + 1, 1, 0), id(i, 1, 0),
             3 * i >= n_x && 3 * i < 2 * n_x ? flap : wall);
        quad(id(i, 0, n_z), id(i + 1, 0, n_z), id(i + 1, 1, n_z), id(i, 1, n_z), far);
    }
    for (int k = 0; k < n_z; ++k) {
        quad(id(0, 0, k), id(0, 1, k), id(0, 1, k + 1), id(0, 0, k + 1), far);
        quad(id(n_x, 0, k), id(n_x, 1, k), id(n_x, 1, k + 1), id(n_x, 0, k + 1), far);
    }
    m.finalize();
    return m;
}

TEST(SymmetrySliding, AFlapSpanningAOneCellSlabSlidesOnItsPlanes) {
    // Before symmetry planes slid, every node of this flap was a seam node (shared with a
    // symmetry marker) and held fixed: nothing could move. Now the nodes away from the seams with
    // the wall (x = 1 and x = 2) rotate exactly about the hinge, every node stays in its plane.
    const manta::mesh::Mesh slab = flap_slab(12, 8);
    manta::meshmotion::ControlSurfaceSpec flap;
    flap.mode = "elevator";
    flap.marker = "flap";
    flap.hinge = {Vector3d(1.0, 0.0, 0.0), Vector3d(1.0, 1.0, 0.0)};  // toward +y: TE down
    flap.source = "cfd.yaml:7";
    const double delta = 10.0 * deg;
    const Motion m = motion(0.0, 0.0, delta, 0.0);
    try {
        const MeshMotion held(slab, m, MotionPlacement{g, "flap.csv"}, {flap});
        ADD_FAILURE() << "without symmetry markers the flap cannot move";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("no node of marker 'flap' is free to move"),
                  std::string::npos)
            << e.what();
    }
    DeformationOptions o;
    o.symmetry_markers = {"symmetry_back", "symmetry_front"};
    const MeshMotion mm(slab, m, MotionPlacement{g, "flap.csv"}, {flap}, o);
    mm.check_motion();
    Matrix3Xd y;
    mm.deformed({delta}, y);
    double exact = 0.0, off_plane = 0.0, moved = 0.0;
    int n_exact = 0;
    for (Index i = 0; i < slab.n_nodes(); ++i) {
        const Vector3d x0 = slab.node(i);
        off_plane = std::max(off_plane, std::abs(y(1, i) - x0.y()));
        moved = std::max(moved, (y.col(i) - x0).norm());
        if (x0.z() == 0.0 && std::abs(x0.x() - 1.5) < 1e-12) {
            // Rotation by delta about the hinge (x = 1, z = 0) toward +y: trailing edge down.
            const Vector3d r = x0 - Vector3d(1.0, x0.y(), 0.0);
            const Vector3d expected =
                Vector3d(1.0, x0.y(), 0.0) +
                Vector3d(r.x() * std::cos(delta), 0.0, -r.x() * std::sin(delta));
            exact = std::max(exact, (y.col(i) - expected).norm());
            ++n_exact;
        }
    }
    EXPECT_EQ(n_exact, 2);
    EXPECT_LT(exact, 1e-12);
    EXPECT_LT(off_plane, 1e-15);
    EXPECT_GT(moved, 0.05);
    // The slab with its symmetry planes in the deforming body motion: the walls are `wall` and
    // `flap`, which touch the far field at x = 0 and x = 3: refused.
    DeformationOptions d = o;
    d.body = BodyMotion::deforming;
    d.wall_markers = {"wall", "flap"};
    EXPECT_THROW((void)MeshMotion(slab, m, MotionPlacement{g, "flap.csv"}, {flap}, d), InputError);
}

}  // namespace
