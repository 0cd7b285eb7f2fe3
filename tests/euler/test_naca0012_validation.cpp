/// @file test_naca0012_validation.cpp
/// NACA 0012 aerofoil, inviscid, in the 3-D solver as a one-cell-thick slab between two
/// symmetry planes (`test::naca0012_slab(0)`, 3 863 nodes per plane): the transonic case
/// M 0.8, alpha 1.25 deg (AGARD AR-211, "Test cases for inviscid flow field methods", 1985,
/// test case 1) and the subsonic case M 0.5, alpha 2 deg.
///
/// The slab mesh lies in the x-y plane (y up) and is extruded along +z; the solver's lift
/// direction is +z, so the nodes are rotated by +90 deg about x ((x, y, z) -> (x, -z, y)) before
/// the solve: the aerofoil's upper side then faces +z and the slab spans y in [-1, 0] m.
/// Reference area: chord x slab thickness = 1 m^2; moment point (0.25, 0, 0) (quarter chord).
///
/// Reference values: the published AGARD AR-211 and Vassberg & Jameson (J. Aircraft 47(4),
/// 2010) coefficients could not be retrieved when this test was written, so the transonic
/// bounds guard MANTA's measured level-0 values (docs/validation.md) and the subsonic lift is
/// compared with thin-aerofoil theory with the Prandtl-Glauert factor and AVL's thickness rule,
/// cl = 2 pi (1 + 0.77 t/c) alpha / sqrt(1 - M^2) (M. Drela and H. Youngren, "AVL 3.36 User
/// Primer", 2017, keyword CLAF): 0.2768 at M 0.5, alpha 2 deg.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "manta/euler/solver.hpp"
#include "manta/mesh/dual.hpp"
#include "test_meshes.hpp"

namespace {

using namespace manta;

/// The slab turned z up ((x, y, z) -> (x, -z, y)), as test_meshes.hpp's turn_y_up_to_z_up.
mesh::Mesh rotate_y_up_to_z_up(const mesh::Mesh& m) {
    return test::turn_y_up_to_z_up(m);
}

struct Result {
    euler::SolveOutcome outcome;
    double area = 0;
};

/// Solve the slab at level 0 at Mach `mach` and incidence `alpha_deg` (deg).
Result solve(double mach, double alpha_deg) {
    const mesh::Mesh m = rotate_y_up_to_z_up(test::naca0012_slab(0));
    const mesh::DualMetrics dual = mesh::compute_dual_metrics(m);
    parallel::SerialHalo halo;
    parallel::SerialCommunicator comm;
    euler::CaseSetup setup;
    setup.flow.mach = mach;
    setup.flow.alpha = alpha_deg * M_PI / 180.0;
    for (const std::string& name : m.markers()) {
        euler::BoundaryKind k{};
        EXPECT_TRUE(euler::default_role(name, k)) << name;
        setup.roles.push_back(k);
    }
    setup.reference.area = 1.0;  // chord 1 m x slab thickness 1 m
    setup.reference.moment_point = {0.25, 0.0, 0.0};
    euler::SteadySolver solver({&m, &dual, m.n_nodes(), &halo}, comm, setup);
    Result r;
    r.area = solver.reference_area();
    r.outcome = solver.solve();
    const euler::ForceCoefficients& f = r.outcome.forces;
    std::printf(
        "NACA 0012 M %.2f alpha %.2f deg (level 0, %d nodes): CL %.5f CD %.6f Cm %.5f "
        "CY %.2e, %d iterations, %.2f orders, %.1f s\n",
        mach, alpha_deg, static_cast<int>(m.n_nodes()), f.CL, f.CD, f.Cm(), f.CY,
        r.outcome.iterations, r.outcome.residual_drop, r.outcome.wall_s);
    return r;
}

TEST(Naca0012Validation, RotationKeepsTheMeshValidAndPutsTheSlabAlongY) {
    const mesh::Mesh a = test::naca0012_slab(0, 0.5);
    const mesh::Mesh b = rotate_y_up_to_z_up(a);
    EXPECT_NEAR(b.volume(), a.volume(), 1e-12 * a.volume());
    double ymin = 1e300, ymax = -1e300;
    for (mesh::Index i = 0; i < b.n_nodes(); ++i) {
        ymin = std::min(ymin, b.node(i).y());
        ymax = std::max(ymax, b.node(i).y());
    }
    EXPECT_NEAR(ymin, -0.5, 1e-12);
    EXPECT_NEAR(ymax, 0.0, 1e-12);
}

TEST(Naca0012Validation, TransonicMach080Alpha125) {
    const Result r = solve(0.8, 1.25);
    const euler::ForceCoefficients& f = r.outcome.forces;
    ASSERT_TRUE(r.outcome.converged) << r.outcome.reason;
    RecordProperty("CL", std::to_string(f.CL));
    RecordProperty("CD", std::to_string(f.CD));
    RecordProperty("Cm", std::to_string(f.Cm()));
    EXPECT_NEAR(f.CY, 0.0, 1e-6);
    // Measured on level 0: CL 0.3709, CD 0.02438 (shock wave drag), Cm -0.0439 (c/4).
    EXPECT_NEAR(f.CL, 0.3709, 0.03 * 0.3709);
    EXPECT_NEAR(f.CD, 0.0244, 0.10 * 0.0244);
    EXPECT_NEAR(f.Cm(), -0.0439, 0.10 * 0.0439);
}

TEST(Naca0012Validation, SubsonicMach050Alpha2) {
    const Result r = solve(0.5, 2.0);
    const euler::ForceCoefficients& f = r.outcome.forces;
    ASSERT_TRUE(r.outcome.converged) << r.outcome.reason;
    RecordProperty("CL", std::to_string(f.CL));
    RecordProperty("CD", std::to_string(f.CD));
    RecordProperty("Cm", std::to_string(f.Cm()));
    EXPECT_NEAR(f.CY, 0.0, 1e-6);
    const double beta = std::sqrt(1.0 - 0.5 * 0.5);
    const double cl_theory = 2.0 * M_PI * (1.0 + 0.77 * 0.12) * (2.0 * M_PI / 180.0) / beta;
    EXPECT_NEAR(f.CL, cl_theory, 0.04 * cl_theory);  // measured 0.2818, +1.8 %
    // Shock-free: the exact drag is zero; what remains is spurious (numerical entropy at the
    // leading edge and the far field): measured 0.0018 on level 0.
    EXPECT_GT(f.CD, -1e-3);
    EXPECT_LT(f.CD, 3e-3);
    EXPECT_NEAR(f.Cm(), 0.0, 0.01);  // thin-aerofoil theory: 0 about c/4; measured -0.0027
}

}  // namespace
