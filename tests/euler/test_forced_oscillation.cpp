/// @file test_forced_oscillation.cpp
/// `aero::forced_oscillation` on the Euler source (EulerSource::start_unsteady) on the meshmotion
/// tests' flat-plate box (`test::flap_plate(6, 4, 4)`, 175 nodes): a pitch oscillation about the
/// plate's mid-chord, two periods of 16 steps from the steady start, analysed as
/// docs/forced-oscillation.md says (Da Ronch et al., Prog. Aerosp. Sci. 47, 2011: Fourier and
/// regression over whole periods give the same derivatives on the same functions); a run stopped
/// after a checkpoint and started again continues from it and gives the uninterrupted history
/// and derivatives bit for bit (the Euler run's save/restore inside the driver's checkpoint).
/// The values against theory: test_forced_oscillation_slow.cpp (Theodorsen).
///
/// Skipped (GTEST_SKIP) while the Euler source cannot move (`!source.unsteady()`).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <stdexcept>
#include <string>

#include <unistd.h>

#include "flap_meshes.hpp"
#include "manta/aero/forced_oscillation.hpp"
#include "manta/euler/config.hpp"
#include "manta/euler/source.hpp"

namespace {

using namespace manta;

euler::EulerSource plate_source() {
    const mesh::Mesh m = test::flap_plate(6, 4, 4);
    euler::CfdConfig c;
    c.markers = {{"flap", euler::BoundaryKind::wall},
                 {"wall", euler::BoundaryKind::wall},
                 {"farfield", euler::BoundaryKind::farfield}};
    euler::CaseSetup setup;
    setup.roles = euler::resolve_roles(m, c);
    setup.flow.mach = 0.5;
    setup.reference.area = 1.0;
    setup.reference.chord = 1.0;
    setup.reference.span = 1.0;
    setup.reference.moment_point = {1.5, 0.5, 0.0};
    return euler::EulerSource(m, setup, "flap plate 6x4x4");
}

aero::ForcedOscillationOptions plate_options() {
    aero::ForcedOscillationOptions o;
    o.axis = aero::OscillationAxis::pitch;
    o.amplitude = 1.0 * std::numbers::pi / 180.0;
    o.reduced_frequency = 0.1;
    o.speed = 170.0;
    o.mach = 0.5;
    o.n_periods = 2;
    o.steps_per_period = 16;
    o.chord = 1.0;
    o.span = 1.0;
    return o;
}

struct Interrupted : std::runtime_error {
    Interrupted() : std::runtime_error("interrupted") {}
};

TEST(EulerForcedOscillation, PlatePitchRunsAnalysesAndResumesBitForBit) {
    const euler::EulerSource source = plate_source();
    if (!source.unsteady()) GTEST_SKIP() << "the Euler source cannot move yet (start_unsteady)";
    const aero::ForcedOscillationOptions o = plate_options();
    const aero::ForcedOscillationResult whole = aero::forced_oscillation(source, o);
    ASSERT_EQ(whole.history.size(), 33u);
    const aero::OscillationResult& cl = whole.coefficients[0];
    const aero::OscillationResult& cm = whole.coefficients[4];
    std::printf(
        "plate pitch k 0.1 M 0.5: CL in phase %.5f out of phase %.5f (regression %.5f %.5f, R^2 "
        "%.5f); Cm in phase %.5f out of phase %.5f; %.2f s\n",
        cl.fourier.in_phase, cl.fourier.out_of_phase, cl.regression.in_phase,
        cl.regression.out_of_phase, cl.regression.r_squared, cm.fourier.in_phase,
        cm.fourier.out_of_phase, whole.wall_s);
    EXPECT_EQ(cl.n_periods, 1);  // the first period discarded
    EXPECT_EQ(cl.first_sample, 16u);
    // The pitching wall moves the lift (the plate lies on the box's face z = 0, so no sign is
    // asserted: the flow is on one side only).
    EXPECT_TRUE(std::isfinite(cl.fourier.in_phase));
    EXPECT_GT(std::abs(cl.fourier.in_phase), 0.01);
    for (std::size_t k = 0; k < 6; ++k) {
        const auto& c = whole.coefficients[k];
        const double scale = std::abs(c.fourier.in_phase) + std::abs(c.fourier.out_of_phase);
        EXPECT_NEAR(c.regression.in_phase, c.fourier.in_phase, 1e-9 * scale + 1e-12) << k;
        EXPECT_NEAR(c.regression.out_of_phase, c.fourier.out_of_phase, 1e-9 * scale + 1e-12) << k;
    }

    aero::ForcedOscillationOptions oc = o;
    oc.checkpoint = std::filesystem::temp_directory_path() /
                    ("manta_euler_oscillation_" + std::to_string(::getpid()) + ".ckpt");
    std::filesystem::remove(oc.checkpoint);
    oc.checkpoint_seconds = 0.0;
    EXPECT_THROW((void)aero::forced_oscillation(source, oc,
                                                [](const aero::ForcedOscillationProgress& p) {
                                                    if (p.step == 20) throw Interrupted();
                                                }),
                 Interrupted);
    const aero::ForcedOscillationResult resumed = aero::forced_oscillation(source, oc);
    EXPECT_EQ(resumed.resumed_from, 20);
    EXPECT_EQ(resumed.steps_computed, 12);
    ASSERT_EQ(resumed.history.size(), whole.history.size());
    for (std::size_t i = 0; i < whole.history.size(); ++i) {
        EXPECT_EQ(resumed.history[i].t, whole.history[i].t) << i;
        EXPECT_EQ(resumed.history[i].wind.CL, whole.history[i].wind.CL) << i;
        EXPECT_EQ(resumed.history[i].wind.CD, whole.history[i].wind.CD) << i;
        EXPECT_EQ(resumed.history[i].body.Cm, whole.history[i].body.Cm) << i;
    }
    for (std::size_t k = 0; k < 6; ++k) {
        EXPECT_EQ(resumed.coefficients[k].fourier.in_phase, whole.coefficients[k].fourier.in_phase);
        EXPECT_EQ(resumed.coefficients[k].fourier.out_of_phase,
                  whole.coefficients[k].fourier.out_of_phase);
    }
    std::filesystem::remove(oc.checkpoint);
}

}  // namespace
