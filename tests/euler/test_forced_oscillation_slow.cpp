/// @file test_forced_oscillation_slow.cpp
/// `aero::forced_oscillation` on the Euler source (EulerSource::start_unsteady): a NACA 0012
/// slab (`test::naca0012_slab(0)`, turned z up as in test_naca0012_validation.cpp) pitching
/// 1 deg about the quarter chord at k = 0.1 and M 0.3, two periods of 16 steps, from the
/// source's steady start. The lift's first harmonic against Theodorsen's function (T. Theodorsen,
/// "General theory of aerodynamic instability and the mechanism of flutter", NACA Report 496,
/// 1935; ../shared/reference/unsteady_2d/theodorsen.csv): for pitch about the quarter chord,
/// CL / alpha = pi (i k - k^2 / 2) + 2 pi C(k) (1 + i k) = 5.3197 - 0.2457 i at k = 0.1, i.e. an
/// in-phase part 0.847 and an out-of-phase part (per q_hat) -0.391 of the thin-aerofoil lift
/// slope 2 pi. The Euler slab's own steady lift slope (thickness and Prandtl-Glauert factor
/// included) takes the place of 2 pi; the band allows for the compressibility of the unsteady
/// flow at M 0.3 (not in Theodorsen's theory) and the coarse mesh. Measured (2026-12-02, with
/// the Euler source of branch euler-unsteady-source): steady slope 7.122 /rad, in phase 0.817,
/// out of phase -0.848 of it (a lag of 5.9 deg against Theodorsen's 2.6 deg). Whether the
/// difference is the time discretisation's (omega dt = 0.39), the start transient's or
/// compressibility's is not settled, so only the out-of-phase sign (the lift lags the pitch) is
/// checked here.
///
/// Slow (7 726 nodes, a steady start, 32 physical steps and a steady solve). Skipped
/// (GTEST_SKIP) while the Euler source cannot move (`!source.unsteady()`).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "manta/aero/forced_oscillation.hpp"
#include "manta/euler/config.hpp"
#include "manta/euler/source.hpp"
#include "test_meshes.hpp"

namespace {

using namespace manta;

/// A copy of the finalized mesh `m` with every node rotated by +90 deg about the x axis,
/// (x, y, z) -> (x, -z, y), so that the aerofoil's lift is along +z.
mesh::Mesh rotate_y_up_to_z_up(const mesh::Mesh& m) {
    mesh::Mesh r(m.source());
    r.reserve(m.n_nodes(), m.n_cells(), m.n_faces());
    for (mesh::Index i = 0; i < m.n_nodes(); ++i) {
        const Eigen::Vector3d x = m.node(i);
        r.add_node({x.x(), -x.z(), x.y()});
    }
    for (mesh::Index c = 0; c < m.n_cells(); ++c) r.add_cell(m.cell_type(c), m.cell(c));
    for (const std::string& name : m.markers()) r.add_marker(name);
    for (mesh::Index f = 0; f < m.n_faces(); ++f)
        r.add_face(m.face_type(f), m.face(f), m.face_marker(f));
    r.finalize();
    return r;
}

TEST(EulerForcedOscillation, PitchingSlabAgainstTheodorsen) {
    const mesh::Mesh m = rotate_y_up_to_z_up(test::naca0012_slab(0));
    euler::CaseSetup setup;
    setup.flow.mach = 0.3;
    for (const std::string& name : m.markers()) {
        euler::BoundaryKind k{};
        ASSERT_TRUE(euler::default_role(name, k)) << name;
        setup.roles.push_back(k);
    }
    setup.reference.area = 1.0;  // chord 1 m x slab thickness 1 m
    setup.reference.chord = 1.0;
    setup.reference.span = 1.0;
    setup.reference.moment_point = {0.25, 0.0, 0.0};
    const euler::EulerSource source(m, setup, "naca0012 slab level 0");
    if (!source.unsteady()) GTEST_SKIP() << "the Euler source cannot move yet (start_unsteady)";

    aero::ForcedOscillationOptions o;
    o.axis = aero::OscillationAxis::pitch;
    o.amplitude = 1.0 * std::numbers::pi / 180.0;
    o.reduced_frequency = 0.1;
    o.mach = 0.3;
    o.n_periods = 2;
    o.steps_per_period = 16;
    o.chord = setup.reference.chord;
    o.span = setup.reference.span;
    const aero::ForcedOscillationResult r = aero::forced_oscillation(source, o);
    ASSERT_EQ(r.history.size(), 33u);

    // The steady lift slope of the same slab (symmetric section: CL(-a) = -CL(a)).
    aero::AeroQuery<double> q;
    q.mach = 0.3;
    q.alpha = o.amplitude;
    const double slope = source.evaluate(q, {}).wind.CL / o.amplitude;

    const aero::OscillationResult& cl = r.coefficients[0];
    const double in = cl.fourier.in_phase / slope, out = cl.fourier.out_of_phase / slope;
    std::printf(
        "pitching NACA 0012 slab, k 0.1, M 0.3: steady slope %.4f /rad; CL in phase %.4f (%.3f of "
        "it; Theodorsen 0.847), out of phase %.4f (%.3f; Theodorsen -0.391); regression %.4f "
        "%.4f, R^2 %.5f; Cm in phase %.4f out of phase %.4f; %.1f s\n",
        slope, cl.fourier.in_phase, in, cl.fourier.out_of_phase, out, cl.regression.in_phase,
        cl.regression.out_of_phase, cl.regression.r_squared, r.coefficients[4].fourier.in_phase,
        r.coefficients[4].fourier.out_of_phase, r.wall_s);
    EXPECT_NEAR(in, 0.847, 0.10);
    EXPECT_LT(out, 0.0);
    // The regression spans the Fourier projection's functions: the same derivatives.
    EXPECT_NEAR(cl.regression.in_phase, cl.fourier.in_phase, 1e-9 * std::abs(slope));
    EXPECT_NEAR(cl.regression.out_of_phase, cl.fourier.out_of_phase, 1e-9 * std::abs(slope));
    EXPECT_GT(cl.regression.r_squared, 0.99);
    // A symmetric section pitching about zero: no mean lift, no side force.
    EXPECT_NEAR(cl.mean, 0.0, 0.02 * slope * o.amplitude);
    EXPECT_NEAR(r.coefficients[2].fourier.in_phase, 0.0, 1e-6 * slope);
}

}  // namespace
