/// @file test_flap_slab_motion.cpp
/// A control surface on a 2-D slab (the flapped NACA 0012 of test_meshes.hpp, turned z up):
/// every node of the slab lies on one of its two symmetry planes, which are normal to the
/// flap's hinge. Those planes slide (docs/mesh-motion.md, "Sliding planes"): the flap's nodes
/// are not held as seam nodes there, the planes' nodes move with the volume, and nothing
/// leaves its plane. Before that change no node of a slab flap could move (every one was a
/// seam node), and MeshMotion refused the control surface.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <set>
#include <string>

#include "manta/aero/motion.hpp"
#include "manta/core/error.hpp"
#include "manta/meshmotion/mesh_motion.hpp"
#include "test_meshes.hpp"

namespace {

using namespace manta;
constexpr double deg = std::numbers::pi / 180.0;

aero::Motion flap_motion(double delta) {
    aero::Motion motion;
    motion.t = {0.0, 1.0};
    for (auto& p : motion.position) p = {0.0, 0.0};
    for (auto& a : motion.angles) a = {0.0, 0.0};
    for (const char* mode : {"elevator", "aileron", "rudder"}) motion.add_mode(mode, {0.0, 0.0});
    motion.add_mode("flap", {delta, delta});
    return motion;
}

meshmotion::ControlSurfaceSpec flap_spec() {
    meshmotion::ControlSurfaceSpec s;
    s.mode = "flap";
    s.marker = "flap";
    s.hinge = {Eigen::Vector3d(0.75, -1.0, 0.0), Eigen::Vector3d(0.75, 0.0, 0.0)};
    s.hinge_blend = 0.005;
    s.edge_blend = 0.01;
    return s;
}

std::set<mesh::Index> marker_nodes(const mesh::Mesh& m, const std::string& name) {
    std::set<mesh::Index> s;
    const int k = m.find_marker(name);
    for (mesh::Index f = 0; f < m.n_faces(); ++f)
        if (m.face_marker(f) == k)
            for (const mesh::Index v : m.face(f)) s.insert(v);
    return s;
}

TEST(FlapSlabMotion, TheFlapRotatesAboutItsHingeAndTheSlabPlanesSlide) {
    const mesh::Mesh m = test::turn_y_up_to_z_up(test::naca0012_slab(0, 1.0, 0.75));
    const double delta = 10.0 * deg;
    meshmotion::DeformationOptions options;  // the slab planes are symmetry planes: they slide
    options.symmetry_markers = {"symmetry_back", "symmetry_front"};
    const meshmotion::MeshMotion mm(m, flap_motion(delta), {}, {flap_spec()}, options);
    ASSERT_EQ(mm.info().size(), 1u);
    const meshmotion::ControlSurfaceInfo& info = mm.info().front();
    EXPECT_EQ(info.n_seam_nodes, 4);  // the hinge nodes, upper and lower, on both planes
    EXPECT_GT(info.n_affected, info.n_marker_nodes);  // the volume deforms too

    Eigen::Matrix3Xd y;
    mm.coordinates_at(0.5, y);  // the cell check passes
    const auto flap = marker_nodes(m, "flap");
    const auto airfoil = marker_nodes(m, "airfoil");
    const Eigen::Matrix3d R = Eigen::AngleAxisd(delta, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const Eigen::Vector3d a(0.75, 0.0, 0.0);
    double rotation_error = 0.0, plane_error = 0.0, fixed_error = 0.0, te_drop = 0.0;
    for (mesh::Index v = 0; v < m.n_nodes(); ++v) {
        const Eigen::Vector3d x0 = m.node(v), x = y.col(v);
        plane_error = std::max(plane_error, std::abs(x.y() - x0.y()));  // stays in its plane
        if (airfoil.count(v)) fixed_error = std::max(fixed_error, (x - x0).norm());
        if (flap.count(v) && !airfoil.count(v) && x0.x() > 0.76) {
            rotation_error = std::max(rotation_error, (x - (a + R * (x0 - a))).norm());
            if (x0.x() == 1.0) te_drop = x0.z() - x.z();
        }
    }
    EXPECT_LT(rotation_error, 1e-12);  // exact rotation outside the 5-10 mm blend band
    EXPECT_LT(plane_error, 1e-12);
    EXPECT_EQ(fixed_error, 0.0);
    EXPECT_NEAR(te_drop, 0.25 * std::sin(delta), 1e-12);  // trailing edge down
}

TEST(FlapSlabMotion, NoCellFoldsUpToTwentyDegrees) {
    const mesh::Mesh m = test::turn_y_up_to_z_up(test::naca0012_slab(0, 1.0, 0.75));
    for (const double d : {-20.0, 20.0}) {
        meshmotion::DeformationOptions options;
        options.symmetry_markers = {"symmetry_back", "symmetry_front"};
        const meshmotion::MeshMotion mm(m, flap_motion(d * deg), {}, {flap_spec()}, options);
        EXPECT_NO_THROW(mm.check_motion()) << d << " deg";
    }
}

TEST(FlapSlabMotion, TheFlapMarkerNeedsAHingeInRange) {
    EXPECT_THROW((void)test::naca0012_slab(0, 1.0, 0.99), InputError);
    const mesh::Mesh m = test::naca0012_slab(0, 1.0, 0.75);
    EXPECT_GE(m.find_marker("flap"), 0);
    EXPECT_GE(m.find_marker("airfoil"), 0);
}

}  // namespace
