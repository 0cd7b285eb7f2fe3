/// @file test_source_campaign.cpp
/// The Euler source fills a whole table campaign (static, control increments, dynamic
/// derivatives; 4 static and 4 control samples, the fewest the models fit; 2 x 1 (alpha, Mach)
/// points in the control and dynamic tables) on a coarse wing with flaps: `test::flap_wing(2)` of
/// the meshmotion tests (the aft 25 % of the chord between y = 1 and 2 m) mirrored about y = 0,
/// both flaps driven by the elevator with hinges along +y, so that a positive deflection is
/// trailing edge down (docs/conventions.md). Every column filled and finite, CL_delta_e > 0,
/// Cm_delta_e < 0 (the flaps' lift acts aft of the quarter-chord moment point), CL_q > 0,
/// Cm_q < 0, Cl_p < 0 and Cn_r < 0 (the damping derivatives).
/// Also: the source refuses a deflection of a mode with no control surface, naming the mode and
/// the configuration, and alpha_dot_hat.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "flap_meshes.hpp"
#include "manta/core/error.hpp"
#include "manta/euler/config.hpp"
#include "manta/euler/source.hpp"
#include "manta/tables/generator.hpp"
#include "mirror.hpp"

namespace {

using namespace manta;

/// The whole wing: the half model and its mirror image, the left flap the marker `flap_left`
/// (roll and yaw rates need the whole span; a symmetry plane mirrors the flow).
const mesh::Mesh& flap_mesh() {
    static const mesh::Mesh m =
        test::mirrored_about_y(test::flap_wing(2.0), "symmetry", {{"flap", "flap_left"}});
    return m;
}

euler::EulerSource make_source() {
    const mesh::Mesh& m = flap_mesh();
    euler::CfdConfig cfg;
    cfg.markers = {{"flap", euler::BoundaryKind::wall}, {"flap_left", euler::BoundaryKind::wall}};
    euler::CaseSetup setup;
    setup.roles = euler::resolve_roles(m, cfg);
    setup.reference.area = 6.0;
    setup.reference.chord = 1.0;
    setup.reference.span = 6.0;
    setup.reference.moment_point = {0.25, 0.0, 0.0};
    setup.spatial.order = 1;  // a coarse mesh and a short test: first order converges fastest
    setup.solver.residual_drop = 4.0;
    setup.solver.coefficient_tolerance = 1e-4;
    meshmotion::ControlSurfaceSpec flap;
    flap.mode = "elevator";
    flap.marker = "flap";
    flap.hinge = {Eigen::Vector3d(0.75, 1.0, 0.0), Eigen::Vector3d(0.75, 2.0, 0.0)};
    meshmotion::ControlSurfaceSpec left = flap;  // hinge along +y as well: trailing edge down
    left.marker = "flap_left";
    left.hinge = {Eigen::Vector3d(0.75, -2.0, 0.0), Eigen::Vector3d(0.75, -1.0, 0.0)};
    return euler::EulerSource(m, setup, "flap_wing(2) mirrored", {flap, left}, "test cfd.yaml");
}

TEST(EulerSourceCampaign, FillsStaticControlAndDynamicTables) {
    const euler::EulerSource src = make_source();
    std::printf("flap_wing(2) mirrored: %d nodes\n", static_cast<int>(flap_mesh().n_nodes()));
    const tables::Campaign c = tables::parse_campaign(
        "schema_version: 1\nname: euler flap wing\n"
        "source: {type: euler, mesh: flap.su2}\n"
        "static: {alpha_deg: [0, 2, 4, 6], mach: [0.3], beta_deg: [0], budget: 4,\n"
        "         initial_design: {size: 4}}\n"
        "controls:\n  elevator: {deflection_deg: [-5, 0, 5], alpha_deg: [0, 4], samples: 4}\n"
        "dynamic: {alpha_deg: [0, 4], rate_step: 0.02}\n",
        "campaign.yaml");
    const auto dir = std::filesystem::temp_directory_path() / "manta_euler_source_campaign";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    auto store = tables::SampleStore::open(dir / "samples.sqlite", src.name(), src.fingerprint());
    tables::RunOptions o;
    o.jobs = 2;
    const auto t0 = std::chrono::steady_clock::now();
    const tables::CampaignResult r = tables::run_campaign(c, src, *store, o);
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const euler::EulerSourceStats st = src.stats();
    std::printf("campaign: %d samples, %d warm starts, %d iterations, %.1f s\n", st.evaluations,
                st.warm_starts, st.iterations, wall);
    EXPECT_EQ(r.failed, 0);
    ASSERT_EQ(r.tables.size(), 3u);  // static, elevator, dynamic
    for (const auto& t : r.tables) {
        ASSERT_FALSE(t.table.values.empty()) << t.table.name;
        for (double v : t.table.values) EXPECT_TRUE(std::isfinite(v)) << t.table.name;
    }
    // Elevator increments: axes alpha, Mach, deflection; 6 coefficients per entry.
    const aero::Table& e = r.tables[1].table;
    ASSERT_EQ(e.axes[2].axis, aero::Axis::elevator);
    const double d = e.axes[2].breakpoints.back();
    for (std::size_t a = 0; a < 2; ++a) {
        const std::size_t entry = a * 3 + 2;  // (alpha a, M 0.3, +5 deg)
        const double dCL = e.values[entry * 6 + 0], dCm = e.values[entry * 6 + 4];
        std::printf("alpha %g deg: CL_de %.4f /rad, Cm_de %.4f /rad\n",
                    e.axes[0].breakpoints[a] * 180 / M_PI, dCL / d, dCm / d);
        EXPECT_GT(dCL, 0.0);  // trailing edge down: more lift
        EXPECT_LT(dCm, 0.0);  // aft of the moment point: nose down
    }
    // Dynamic derivatives at both incidences: every one of the 18 columns finite, Cm_q < 0.
    const aero::Table& dyn = r.tables[2].table;
    ASSERT_EQ(dyn.columns.size(), 18u);
    const auto col = [&](const std::string& n) {
        return static_cast<std::size_t>(std::find(dyn.columns.begin(), dyn.columns.end(), n) -
                                        dyn.columns.begin());
    };
    for (std::size_t g = 0; g < dyn.n_points(); ++g) {
        const double Cmq = dyn.values[g * 18 + col("Cm_q")];
        const double CLq = dyn.values[g * 18 + col("CL_q")];
        std::printf("point %zu: CL_q %.4f, Cm_q %.4f, Cl_p %.4f, Cn_r %.4f\n", g, CLq, Cmq,
                    dyn.values[g * 18 + col("Cl_p")], dyn.values[g * 18 + col("Cn_r")]);
        EXPECT_LT(Cmq, 0.0);
        EXPECT_GT(CLq, 0.0);
        EXPECT_LT(dyn.values[g * 18 + col("Cl_p")], 0.0);  // roll damping
        EXPECT_LT(dyn.values[g * 18 + col("Cn_r")], 0.0);  // yaw damping
    }
}

TEST(EulerSourceCampaign, RefusesModesWithoutASurfaceAndAlphaDot) {
    const euler::EulerSource src = make_source();
    aero::AeroQuery<double> q;
    q.mach = 0.3;
    q.rudder = 0.05;
    try {
        (void)src.evaluate(q, {});
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("rudder"), std::string::npos) << m;
        EXPECT_NE(m.find("test cfd.yaml"), std::string::npos) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
    q.rudder = 0.0;
    q.alpha_dot_hat = 0.01;
    EXPECT_THROW((void)src.evaluate(q, {}), InputError);
    // Roll and yaw rates on a half model: refused, naming the symmetry plane.
    const mesh::Mesh half = test::flap_wing(2.0);
    euler::CfdConfig cfg;
    cfg.markers = {{"flap", euler::BoundaryKind::wall}};
    euler::CaseSetup setup;
    setup.roles = euler::resolve_roles(half, cfg);
    setup.reference.area = 3.0;
    const euler::EulerSource hs(half, setup, "flap_wing(2)");
    aero::AeroQuery<double> r;
    r.mach = 0.3;
    r.p_hat = 0.01;
    try {
        (void)hs.evaluate(r, {});
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("'symmetry'"), std::string::npos) << e.what();
    }
    // The fingerprint names the control surfaces and the rotating frame, so samples of sources
    // before them are not reused.
    EXPECT_NE(src.fingerprint().find("rotating-frame"), std::string::npos);
    EXPECT_NE(src.fingerprint().find("elevator:flap"), std::string::npos);
}

}  // namespace
