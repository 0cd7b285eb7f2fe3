// Dynamic derivatives from forced harmonic oscillations of the unsteady vortex lattice, against
// the steady lattice's rotary derivatives: at a low reduced frequency the out-of-phase part of a
// roll oscillation is C_p (alpha0 = 0) and of a pitch oscillation C_q + C_alphadot, whose C_q
// part the steady solver gives (issue 3: within 5 %).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "manta/vlm/dynamic.hpp"
#include "manta/vlm/steady.hpp"

namespace {

using namespace manta::vlm;
using Eigen::Vector3d;

Model wing(double AR) {
    Model m;
    m.name = "rectangle";
    m.reference = {AR, AR, 1.0, Vector3d(0.25, 0, 0)};
    Surface s;
    s.name = "wing";
    s.n_chord = 4;
    s.chord_spacing = 0.0;
    s.n_span = 16;
    s.span_spacing = 1.0;
    s.y_duplicate = 0.0;
    Section root, tip;
    root.chord = 1.0;
    tip.chord = 1.0;
    tip.leading_edge = Vector3d(0, 0.5 * AR, 0);
    s.sections = {root, tip};
    m.surfaces.push_back(s);
    return m;
}

TEST(VlmDynamicValidation, RollDampingMatchesSteadyClp) {
    const Model m = wing(8.0);
    const Lattice L = build_lattice(m);
    const double Clp = SteadySolver(m, L, 0.0).derivatives(FlowState{}).body(3, 2);
    ForcedOscillationOptions o;
    o.axis = manta::aero::OscillationAxis::roll;
    o.reduced_frequency = 0.02;
    o.amplitude = 2.0 * std::numbers::pi / 180.0;
    o.steps_per_period = 64;
    const ForcedOscillationResult r = forced_oscillation(m, L, o);
    const auto& cl = r.coefficients[3];
    std::printf("roll k %.3f: Clp fourier %.5f regression %.5f steady %.5f\n", o.reduced_frequency,
                cl.fourier.out_of_phase, cl.regression.out_of_phase, Clp);
    EXPECT_NEAR(cl.fourier.out_of_phase, Clp, 0.05 * std::abs(Clp));
    EXPECT_NEAR(cl.regression.out_of_phase, Clp, 0.05 * std::abs(Clp));
}

// Pitch gives C_q + C_alphadot, plunge C_alphadot alone (q = 0): their difference is C_q, which
// the steady lattice gives directly.
TEST(VlmDynamicValidation, PitchMinusPlungeMatchesSteadyCmq) {
    const Model m = wing(8.0);
    const Lattice L = build_lattice(m);
    const Derivatives d = SteadySolver(m, L, 0.0).derivatives(FlowState{});
    ForcedOscillationOptions o;
    o.reduced_frequency = 0.02;
    o.amplitude = 1.0 * std::numbers::pi / 180.0;
    o.steps_per_period = 64;
    o.axis = manta::aero::OscillationAxis::pitch;
    const ForcedOscillationResult pitch = forced_oscillation(m, L, o);
    o.axis = manta::aero::OscillationAxis::plunge;
    const ForcedOscillationResult plunge = forced_oscillation(m, L, o);
    for (const auto& [row, name] : {std::pair{0, "CL"}, std::pair{4, "Cm"}}) {
        const auto k = static_cast<std::size_t>(row);
        const double fourier = pitch.coefficients[k].fourier.out_of_phase -
                               plunge.coefficients[k].fourier.out_of_phase;
        const double regression = pitch.coefficients[k].regression.out_of_phase -
                                  plunge.coefficients[k].regression.out_of_phase;
        const double steady = d.body(row, 3);
        std::printf(
            "%s_q: pitch - plunge Fourier %.5f regression %.5f steady %.5f "
            "(%s_alphadot %.4f)\n",
            name, fourier, regression, steady, name, plunge.coefficients[k].fourier.out_of_phase);
        SCOPED_TRACE(name);
        EXPECT_NEAR(fourier, steady, 0.05 * std::abs(steady));
        EXPECT_NEAR(regression, steady, 0.05 * std::abs(steady));
    }
    // In-phase: the lift slope of the oscillation is the steady one at this low frequency.
    EXPECT_NEAR(pitch.coefficients[0].fourier.in_phase, d.body(0, 0), 0.03 * d.body(0, 0));
    EXPECT_NEAR(plunge.coefficients[0].fourier.in_phase, d.body(0, 0), 0.03 * d.body(0, 0));
}

}  // namespace
