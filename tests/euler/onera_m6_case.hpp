#pragma once
/// @file onera_m6_case.hpp
/// The ONERA M6 case of the coarse and fine validation tests: M 0.8395, alpha 3.06 deg, marker
/// roles from the names (WING, SYMMETRY, FARFIELD), moments about (0.25, 0, 0) as in SU2's
/// configuration (../shared/reference/onera_m6/inv_ONERAM6_gmsh.cfg).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "manta/euler/solver.hpp"
#include "manta/mesh/dual.hpp"
#include "manta/mesh/mesh.hpp"
#include "manta/mesh/readers.hpp"
#include "manta/mesh/reorder.hpp"

namespace manta::test {

/// Fill `setup` for the ONERA M6 case on mesh `m` (a fatal test failure if a marker has no
/// default role).
inline void onera_m6_setup(const mesh::Mesh& m, euler::CaseSetup& setup) {
    setup.flow.mach = 0.8395;
    setup.flow.alpha = 3.06 * M_PI / 180.0;
    for (const std::string& name : m.markers()) {
        euler::BoundaryKind k{};
        ASSERT_TRUE(euler::default_role(name, k)) << name;
        setup.roles.push_back(k);
    }
    setup.reference.moment_point = {0.25, 0.0, 0.0};
}

/// Solve the case on the mesh `file` (nodes renumbered first if `reorder`) with `scheme` and
/// `wall` tangency (automatic: the scheme's default), check the reference area against SU2's
/// `su2_area` (m^2, 0.2 %) and print the coefficients after `label`.
inline euler::SolveOutcome onera_m6_solve(
    const std::filesystem::path& file, euler::FluxScheme scheme, bool reorder, double su2_area,
    const char* label, euler::WallTangency wall = euler::WallTangency::automatic) {
    const mesh::Mesh m = reorder ? mesh::reorder_reverse_cuthill_mckee(mesh::read_mesh(file)).mesh
                                 : mesh::read_mesh(file);
    const mesh::DualMetrics dual = mesh::compute_dual_metrics(m);
    parallel::SerialHalo halo;
    parallel::SerialCommunicator comm;
    euler::CaseSetup setup;
    onera_m6_setup(m, setup);
    setup.spatial.flux.scheme = scheme;
    setup.spatial.wall = wall;
    euler::SteadySolver solver({&m, &dual, m.n_nodes(), &halo}, comm, setup);
    // SU2's REF_AREA = 0: the z-projection of the wing.
    EXPECT_NEAR(solver.reference_area(), su2_area, 0.002 * su2_area);
    const euler::SolveOutcome oc = solver.solve();
    std::printf("ONERA M6 %s: CL %.6f CD %.6f CMy %.6f in %d iterations, %.1f s\n", label,
                oc.forces.CL, oc.forces.CD, oc.forces.CMy, oc.iterations, oc.wall_s);
    return oc;
}

}  // namespace manta::test
