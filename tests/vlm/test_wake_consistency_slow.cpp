// The steady and the unsteady vortex lattice in steady flight (MANTA issue 16) on the Ranger
// 2000's full-density lattice (12 chordwise vortices, strips of 0.01 b: 1 956 vortices; the
// steady solver's default, docs/vlm.md) at Mach 0.457: an unsteady run held at a constant angle
// of attack converges to the steady solution, Cm within 0.002 and CL within 0.1 %, over alpha
// -6..14 deg. The replay's coarser lattice, with sideslip: test_wake_consistency_validation.cpp.
// About a minute (slow label).

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "wake_consistency.hpp"

namespace {

using namespace manta::vlm::testing;

TEST(VlmWakeConsistency, FullDensityLatticeOverAlphaSweep) {
    const manta::vlm::Model m = ranger_model(12, 0.01);
    const std::vector<double> alphas{-6, -2, 2, 6, 10, 14};
    const Sweep sw = sweep(m, alphas, 0.0, 10.0);
    for (std::size_t k = 0; k < alphas.size(); ++k) {
        SCOPED_TRACE(alphas[k]);
        EXPECT_NEAR(sw.unsteady[k].Cm, sw.steady[k].Cm, 0.002);
        EXPECT_NEAR(sw.unsteady[k].CL, sw.steady[k].CL, 1e-3 * std::abs(sw.steady[k].CL) + 1e-4);
    }
}

}  // namespace
