#pragma once
/// @file onera_m6_case.hpp
/// The ONERA M6 case of the coarse and fine validation tests: M 0.8395, alpha 3.06 deg, marker
/// roles from the names (WING, SYMMETRY, FARFIELD), moments about (0.25, 0, 0) as in SU2's
/// configuration (../shared/reference/onera_m6/inv_ONERAM6_gmsh.cfg).

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "manta/euler/solver.hpp"
#include "manta/mesh/mesh.hpp"

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

}  // namespace manta::test
