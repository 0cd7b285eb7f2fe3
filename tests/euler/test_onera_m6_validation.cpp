/// @file test_onera_m6_validation.cpp
/// ONERA M6 wing, inviscid, M 0.8395, alpha 3.06 deg, on the coarse gmsh mesh of
/// ../shared/reference/onera_m6 (10 421 nodes), against SU2 v8.1.0 run on the same mesh
/// (../shared/reference/onera_m6/README.md and su2_v8.1.0_history_coarse.csv: JST, CL 0.278600,
/// CD 0.005098, CMy -0.063475, reference area 0.749716 m^2). The configuration: V.
/// Schmitt and F. Charpin, "Pressure distributions on the ONERA-M6-wing at transonic Mach numbers",
/// AGARD AR-138, 1979.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "manta/euler/solver.hpp"
#include "manta/mesh/dual.hpp"
#include "manta/mesh/readers.hpp"
#include "onera_m6_case.hpp"

namespace {

using namespace manta;

const std::filesystem::path file = std::filesystem::path(MANTA_SHARED_DIR) /
                                   "reference/onera_m6/mesh_ONERAM6_inv_gmsh_coarse.su2.gz";

/// Solve the coarse case with `scheme` and `wall` tangency (automatic: the scheme's default).
euler::SolveOutcome solve_coarse(euler::FluxScheme scheme, const char* label,
                                 euler::WallTangency wall = euler::WallTangency::automatic) {
    return test::onera_m6_solve(file, scheme, false, 0.749716,
                                (std::string("coarse, ") + label).c_str(), wall);
}

// The criterion, with SU2's scheme: JST (k2 0.5, k4 0.02) and strong wall tangency, as
// SU2 v8.1 runs it. Measured: CL 0.278490 (-0.04 %), CD 0.004984 (SU2 0.005098), CMy -0.063506.
TEST(OneraM6Validation, CoarseMeshJstLiftWithinOnePercentOfSu2) {
    if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " not found";
    const euler::SolveOutcome oc = solve_coarse(euler::FluxScheme::jst, "JST");
    ASSERT_TRUE(oc.converged) << oc.reason;
    EXPECT_GE(oc.residual_drop, 6.0);
    RecordProperty("CL", std::to_string(oc.forces.CL));
    EXPECT_NEAR(oc.forces.CL, 0.278600, 0.01 * 0.278600);
    EXPECT_NEAR(oc.forces.CMy, -0.063475, 0.01 * 0.063475);
    EXPECT_NEAR(oc.forces.CD, 0.005098, 0.0005);
}

// MANTA's default upwind scheme (Roe, MUSCL, Venkatakrishnan, weak tangency) on the same mesh:
// CL 0.28172, 1.1 % above SU2's JST value, CMy -0.06569, CD 0.0236, 20 times SU2's Roe value
// (issue 16, still open: docs/validation.md). The bounds guard these values.
TEST(OneraM6Validation, CoarseMeshRoeAgainstSu2) {
    if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " not found";
    const euler::SolveOutcome oc = solve_coarse(euler::FluxScheme::roe, "Roe");
    ASSERT_TRUE(oc.converged) << oc.reason;
    EXPECT_GE(oc.residual_drop, 6.0);
    EXPECT_NEAR(oc.forces.CL, 0.278600, 0.015 * 0.278600);
    EXPECT_NEAR(oc.forces.CMy, -0.063475, 0.05 * 0.063475);
    EXPECT_GT(oc.forces.CD, 0.0);
}

// Roe with strong tangency (SU2 v8.1's wall treatment, with the wall nodes' density and
// pressure gradients free of their normal part, spatial.hpp) against SU2 v8's own Roe scheme
// (MUSCL, Venkatakrishnan, entropy fix 0.05) on the same mesh
// (../shared/reference/onera_m6/su2_v8_roe_history_coarse.csv, inv_ONERAM6_gmsh_coarse_roe.cfg:
// CL 0.26239, CD 0.0011982, CMy -0.064706 after 300 iterations, its residual stalled 3.1 orders
// down). Measured: CL 0.260917 (-0.56 %), CD 0.000891, CMy -0.062228 (-3.8 %). Without the
// gradient condition: CD -0.0098.
TEST(OneraM6Validation, CoarseMeshRoeStrongWallsAgainstSu2Roe) {
    if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " not found";
    const euler::SolveOutcome oc =
        solve_coarse(euler::FluxScheme::roe, "Roe, strong walls", euler::WallTangency::strong);
    ASSERT_TRUE(oc.converged) << oc.reason;
    EXPECT_GE(oc.residual_drop, 6.0);
    RecordProperty("CD", std::to_string(oc.forces.CD));
    EXPECT_NEAR(oc.forces.CL, 0.26239, 0.01 * 0.26239);
    EXPECT_NEAR(oc.forces.CMy, -0.064706, 0.05 * 0.064706);
    EXPECT_NEAR(oc.forces.CD, 0.0011982, 0.001);
}

// Roe with mixed tangency (spatial.hpp: strong, except at the 109 sharp-edge nodes, 103 of them
// on the trailing edge, where the flow leaves along the edge's bisector instead of stagnating):
// CL 0.257397 (-1.9 % of SU2's Roe), CD 0.009300, CMy -0.061984 (-4.2 %). The CD is 7.8 times
// SU2 Roe's 0.0012, which has the trailing-edge stagnation point of strong tangency: on this
// mesh the trailing-edge nodes' treatment alone moves CD by 0.0084 (issue 16, docs/euler.md).
// The bounds guard these values.
TEST(OneraM6Validation, CoarseMeshRoeMixedWalls) {
    if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " not found";
    const euler::SolveOutcome oc =
        solve_coarse(euler::FluxScheme::roe, "Roe, mixed walls", euler::WallTangency::mixed);
    ASSERT_TRUE(oc.converged) << oc.reason;
    EXPECT_GE(oc.residual_drop, 6.0);
    RecordProperty("CD", std::to_string(oc.forces.CD));
    EXPECT_NEAR(oc.forces.CL, 0.26239, 0.03 * 0.26239);
    EXPECT_NEAR(oc.forces.CMy, -0.064706, 0.06 * 0.064706);
    EXPECT_NEAR(oc.forces.CD, 0.0093, 0.001);
}

}  // namespace
