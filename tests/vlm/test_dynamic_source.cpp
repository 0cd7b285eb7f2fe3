// vlm::forced_oscillation through the source-generic driver (aero::forced_oscillation on a
// VlmSource) against the direct unsteady-lattice run it replaced (UnsteadySolver::run and
// aero::analyse_oscillation, as src/vlm/dynamic.cpp did before): the same histories and
// derivatives bit for bit on every axis. The values themselves are validated in
// test_dynamic_validation.cpp (against the steady lattice's rotary derivatives; Katz & Plotkin,
// Low-Speed Aerodynamics, 2nd ed., ch. 13; Da Ronch et al., Prog. Aerosp. Sci. 47, 2011).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "manta/core/error.hpp"
#include "manta/vlm/dynamic.hpp"
#include "manta/vlm/source.hpp"

namespace {

using namespace manta;
using namespace manta::vlm;
using Eigen::Vector3d;

Model wing() {
    Model m;
    m.name = "rectangle";
    m.reference = {6.0, 6.0, 1.0, Vector3d(0.25, 0, 0)};
    Surface s;
    s.name = "wing";
    s.n_chord = 3;
    s.chord_spacing = 0.0;
    s.n_span = 8;
    s.span_spacing = 1.0;
    s.y_duplicate = 0.0;
    Section root, tip;
    root.chord = 1.0;
    tip.chord = 1.0;
    tip.leading_edge = Vector3d(0, 3.0, 0);
    s.sections = {root, tip};
    m.surfaces.push_back(s);
    return m;
}

/// The direct run, as vlm::forced_oscillation computed it before the generic driver.
std::array<aero::OscillationResult, 6> direct(const Model& model, const Lattice& lattice,
                                              const ForcedOscillationOptions& o,
                                              UnsteadyHistory& history) {
    const bool lateral =
        o.axis == aero::OscillationAxis::roll || o.axis == aero::OscillationAxis::yaw;
    const double lref = lateral ? model.reference.span : model.reference.chord;
    const double omega = 2.0 * o.speed * o.reduced_frequency / lref;
    const double period = 2.0 * std::numbers::pi / omega;
    const double mean = o.axis == aero::OscillationAxis::pitch ? o.alpha0 : 0.0;
    const bool plunge = o.axis == aero::OscillationAxis::plunge;
    const double motion_amplitude = plunge ? o.amplitude * o.speed / omega : o.amplitude;
    aero::Motion motion = aero::harmonic_motion(o.axis, motion_amplitude, omega, o.n_periods,
                                                o.steps_per_period, mean);
    if (o.axis != aero::OscillationAxis::pitch && o.alpha0 != 0.0)
        for (double& th : motion.angles[1]) th = o.alpha0;
    motion.metadata.v0 = o.speed;
    UnsteadyOptions so = o.solver;
    so.speed = o.speed;
    so.dt = period / o.steps_per_period;
    UnsteadySolver solver(model, lattice, so);
    history = solver.run(motion);
    aero::OscillationSpec spec;
    spec.x0 = mean;
    spec.amplitude = o.amplitude;
    spec.omega = omega;
    spec.reduced_frequency = o.reduced_frequency;
    spec.n_periods = o.n_periods - 1;
    if (plunge) {
        spec.x0 = o.alpha0;
        spec.phase = 0.5 * std::numbers::pi;
    }
    const std::vector<double> t = history.time();
    std::array<std::vector<double>, 6> c;
    for (const auto& s : history.steps) {
        c[0].push_back(s.CL);
        c[1].push_back(s.CD);
        c[2].push_back(s.CY);
        c[3].push_back(s.body.Cl);
        c[4].push_back(s.body.Cm);
        c[5].push_back(s.body.Cn);
    }
    std::array<aero::OscillationResult, 6> r;
    for (std::size_t k = 0; k < 6; ++k) r[k] = aero::analyse_oscillation(t, c[k], spec);
    return r;
}

TEST(VlmDynamicSource, GenericDriverEqualsTheDirectRunBitForBit) {
    const Model m = wing();
    const Lattice L = build_lattice(m);
    for (const auto axis : {aero::OscillationAxis::pitch, aero::OscillationAxis::plunge,
                            aero::OscillationAxis::roll, aero::OscillationAxis::yaw}) {
        SCOPED_TRACE(std::string(aero::to_string(axis)));
        ForcedOscillationOptions o;
        o.axis = axis;
        o.reduced_frequency = 0.1;
        o.amplitude = 1.0 * std::numbers::pi / 180.0;
        o.alpha0 = 3.0 * std::numbers::pi / 180.0;
        o.steps_per_period = 16;
        o.solver.mach = 0.3;
        UnsteadyHistory h;
        const auto ref = direct(m, L, o, h);
        const ForcedOscillationResult r = forced_oscillation(m, L, o);
        ASSERT_EQ(r.history.size(), h.steps.size());
        for (std::size_t i = 0; i < h.steps.size(); ++i) {
            const UnsteadyStep& a = h.steps[i];
            const aero::UnsteadySample& b = r.history[i];
            ASSERT_EQ(b.t, a.t) << i;
            ASSERT_EQ(b.wind.CL, a.CL) << i;
            ASSERT_EQ(b.wind.CD, a.CD) << i;
            ASSERT_EQ(b.body.Cl, a.body.Cl) << i;
            ASSERT_EQ(b.body.Cm, a.body.Cm) << i;
            ASSERT_EQ(b.body.Cn, a.body.Cn) << i;
        }
        for (std::size_t k = 0; k < 6; ++k) {
            EXPECT_EQ(r.coefficients[k].mean, ref[k].mean) << k;
            EXPECT_EQ(r.coefficients[k].fourier.in_phase, ref[k].fourier.in_phase) << k;
            EXPECT_EQ(r.coefficients[k].fourier.out_of_phase, ref[k].fourier.out_of_phase) << k;
            EXPECT_EQ(r.coefficients[k].regression.in_phase, ref[k].regression.in_phase) << k;
            EXPECT_EQ(r.coefficients[k].regression.out_of_phase, ref[k].regression.out_of_phase)
                << k;
        }
        EXPECT_EQ(r.omega,
                  2.0 * o.speed * o.reduced_frequency /
                      (axis == aero::OscillationAxis::roll || axis == aero::OscillationAxis::yaw
                           ? m.reference.span
                           : m.reference.chord));
    }
}

TEST(VlmDynamicSource, SourceOnAGivenLatticeIsTheModelsSource) {
    const Model m = wing();
    const VlmSource a(m), b(m, build_lattice(m));
    EXPECT_EQ(a.fingerprint(), b.fingerprint());
    EXPECT_EQ(a.lattice().size(), b.lattice().size());
}

TEST(VlmDynamicSource, OptionsOutOfRangeAreInputErrors) {
    const Model m = wing();
    const Lattice L = build_lattice(m);
    ForcedOscillationOptions o;
    o.n_periods = 1;
    EXPECT_THROW((void)forced_oscillation(m, L, o), InputError);
    o = {};
    o.reduced_frequency = 0.0;
    EXPECT_THROW((void)forced_oscillation(m, L, o), InputError);
    o = {};
    o.steps_per_period = 7;
    EXPECT_THROW((void)forced_oscillation(m, L, o), InputError);
}

}  // namespace
