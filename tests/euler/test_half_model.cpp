/// @file test_half_model.cpp
/// The coefficients of a half model are the whole aircraft's (ReferenceValues::half_model):
/// the half of `test::flap_wing(2)` (symmetry plane y = 0, flap between y = 1 and 2 m) against
/// the same wing mirrored about y = 0 (both flaps deflected alike), first order, M 0.3,
/// alpha 3 deg, flaps 5 deg trailing edge down. The half model's side force, rolling and yawing
/// moments are 0 (the two halves' cancel); its lift, drag and pitching moment over half the
/// area are the whole wing's; they are those of the half without the flag, which only drops the
/// lateral components (the half alone has a side force: the plane's missing pressure).
/// A mesh companion of model `half` sets the flag; sideslip and a moment point off the plane
/// are one-line errors.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "flap_meshes.hpp"
#include "manta/core/error.hpp"
#include "manta/euler/config.hpp"
#include "manta/euler/source.hpp"
#include "manta/mesh/companion.hpp"
#include "mirror.hpp"

namespace {

using namespace manta;
constexpr double deg = M_PI / 180.0;

const mesh::Mesh& half_mesh() {
    static const mesh::Mesh m = test::flap_wing(2.0);
    return m;
}
const mesh::Mesh& whole_mesh() {
    static const mesh::Mesh m =
        test::mirrored_about_y(test::flap_wing(2.0), "symmetry", {{"flap", "flap_left"}});
    return m;
}

meshmotion::ControlSurfaceSpec right_flap() {
    meshmotion::ControlSurfaceSpec flap;
    flap.mode = "elevator";
    flap.marker = "flap";
    flap.hinge = {Eigen::Vector3d(0.75, 1.0, 0.0), Eigen::Vector3d(0.75, 2.0, 0.0)};
    return flap;
}

euler::CaseSetup setup_of(const mesh::Mesh& m, double area, bool half_model) {
    euler::CfdConfig cfg;
    cfg.markers = {{"flap", euler::BoundaryKind::wall}};
    if (m.find_marker("flap_left") >= 0) cfg.markers["flap_left"] = euler::BoundaryKind::wall;
    euler::CaseSetup setup;
    setup.roles = euler::resolve_roles(m, cfg);
    setup.reference.area = area;
    setup.reference.chord = 1.0;
    setup.reference.span = 6.0;
    setup.reference.moment_point = {0.25, 0.0, 0.0};
    setup.reference.half_model = half_model;
    setup.spatial.order = 1;
    setup.solver.residual_drop = 5.0;
    setup.solver.coefficient_tolerance = 1e-6;
    return setup;
}

aero::SourceResult solve(const mesh::Mesh& m, double area, bool half_model, double beta = 0.0) {
    std::vector<meshmotion::ControlSurfaceSpec> surfaces{right_flap()};
    if (m.find_marker("flap_left") >= 0) {
        meshmotion::ControlSurfaceSpec left = right_flap();
        left.marker = "flap_left";
        left.hinge = {Eigen::Vector3d(0.75, -2.0, 0.0), Eigen::Vector3d(0.75, -1.0, 0.0)};
        surfaces.push_back(left);
    }
    const euler::EulerSource src(m, setup_of(m, area, half_model), m.source(), surfaces,
                                 "test configuration");
    aero::AeroQuery<double> q;
    q.mach = 0.3;
    q.alpha = 3.0 * deg;
    q.beta = beta;
    q.elevator = 5.0 * deg;
    return src.evaluate(q, {});
}

TEST(HalfModel, CoefficientsAreTheWholeWingsAndTheLateralOnesVanish) {
    const aero::SourceResult half = solve(half_mesh(), 3.0, true);
    const aero::SourceResult plain = solve(half_mesh(), 3.0, false);
    const aero::SourceResult whole = solve(whole_mesh(), 6.0, false);
    std::printf("half (%d nodes): CL %.6f CD %.6f Cm %.6f CY %g Cl %g Cn %g\n",
                static_cast<int>(half_mesh().n_nodes()), half.wind.CL, half.wind.CD, half.body.Cm,
                half.wind.CY, half.body.Cl, half.body.Cn);
    std::printf("half alone: CY %.6f Cl %.6f Cn %.6f\n", plain.wind.CY, plain.body.Cl,
                plain.body.Cn);
    std::printf("whole (%d nodes): CL %.6f CD %.6f Cm %.6f CY %.2e Cl %.2e Cn %.2e\n",
                static_cast<int>(whole_mesh().n_nodes()), whole.wind.CL, whole.wind.CD,
                whole.body.Cm, whole.wind.CY, whole.body.Cl, whole.body.Cn);
    // The two halves' lateral force and moments cancel exactly.
    EXPECT_EQ(half.wind.CY, 0.0);
    EXPECT_EQ(half.body.CY, 0.0);
    EXPECT_EQ(half.body.Cl, 0.0);
    EXPECT_EQ(half.body.Cn, 0.0);
    // The flag drops the lateral components only; the half alone has a side force and a
    // rolling moment of its own (the flap's lift acts at y = 1.5 m).
    EXPECT_EQ(half.wind.CL, plain.wind.CL);
    EXPECT_EQ(half.wind.CD, plain.wind.CD);
    EXPECT_EQ(half.body.Cm, plain.body.Cm);
    EXPECT_GT(std::abs(plain.body.Cl), 0.01);
    // The mirrored whole wing: the same lift, drag and pitching moment within 1 % (measured
    // 0.4, 0.2, 0.3 %; the symmetry plane's
    // boundary treatment against interior nodes on y = 0: the discretisations differ there),
    // its own lateral coefficients zero to round-off (the mesh is mirror-symmetric).
    EXPECT_NEAR(half.wind.CL, whole.wind.CL, 0.01 * std::abs(whole.wind.CL));
    EXPECT_NEAR(half.wind.CD, whole.wind.CD, 0.01 * std::abs(whole.wind.CD));
    EXPECT_NEAR(half.body.Cm, whole.body.Cm, 0.01 * std::abs(whole.body.Cm));
    EXPECT_LT(std::abs(whole.body.Cl), 1e-6);
    EXPECT_LT(std::abs(whole.wind.CY), 1e-6);
}

TEST(HalfModel, SideslipAndAMomentPointOffThePlaneAreErrors) {
    try {
        (void)solve(half_mesh(), 3.0, true, 2.0 * deg);
        FAIL() << "sideslip on a half model was accepted";
    } catch (const InputError& e) {
        const std::string w = e.what();
        EXPECT_NE(w.find("sideslip 2 deg on a half model"), std::string::npos) << w;
        EXPECT_NE(w.find("--model full"), std::string::npos) << w;
    }
    euler::CaseSetup s = setup_of(half_mesh(), 3.0, true);
    s.reference.moment_point = {0.25, 0.5, 0.0};
    try {
        const euler::EulerSource src(half_mesh(), s, "half", {}, "test configuration");
        aero::AeroQuery<double> q;
        q.mach = 0.3;
        (void)src.evaluate(q, {});
        FAIL() << "a moment point off the plane was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("moment_point y = 0.5 m on a half model"),
                  std::string::npos)
            << e.what();
    }
}

TEST(HalfModel, TheCompanionOfAHalfModelSetsIt) {
    mesh::Companion c;
    c.model = "half";
    c.reference.area = 3.0;
    c.reference.chord = 1.0;
    c.reference.span = 6.0;
    euler::CfdConfig cfg;
    euler::apply_companion(cfg, c, "wing.mesh.yaml");
    EXPECT_TRUE(cfg.reference.half_model);
    // Also where the configuration gives its own reference values.
    euler::CfdConfig own;
    own.reference_given = true;
    euler::apply_companion(own, c, "wing.mesh.yaml");
    EXPECT_TRUE(own.reference.half_model);
    // A hand-made half mesh: the configuration's key.
    EXPECT_TRUE(euler::parse_cfd_config("reference: {area: 3, half_model: true}\n", "cfd.yaml")
                    .reference.half_model);
    EXPECT_FALSE(
        euler::parse_cfd_config("reference: {area: 3}\n", "cfd.yaml").reference.half_model);
    c.model = "full";
    euler::CfdConfig full;
    euler::apply_companion(full, c, "wing.mesh.yaml");
    EXPECT_FALSE(full.reference.half_model);
}

}  // namespace
