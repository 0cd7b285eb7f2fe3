#include "manta/vlm/dynamic.hpp"

#include "manta/vlm/source.hpp"

namespace manta::vlm {

aero::ForcedOscillationOptions oscillation_options(const Model& model,
                                                   const ForcedOscillationOptions& o) {
    aero::ForcedOscillationOptions a;
    a.axis = o.axis;
    a.amplitude = o.amplitude;
    a.reduced_frequency = o.reduced_frequency;
    a.alpha0 = o.alpha0;
    a.speed = o.speed;
    a.mach = o.solver.mach;
    a.n_periods = o.n_periods;
    a.steps_per_period = o.steps_per_period;
    a.chord = model.reference.chord;
    a.span = model.reference.span;
    return a;
}

ForcedOscillationResult forced_oscillation(const Model& model, const Lattice& lattice,
                                           const ForcedOscillationOptions& o,
                                           const aero::ForcedOscillationCallback& progress) {
    const aero::ForcedOscillationOptions a = oscillation_options(model, o);
    aero::check_options(a);  // before the source is built
    VlmSource source(model, lattice);
    UnsteadyOptions so = o.solver;
    so.speed = o.speed;
    source.set_unsteady_options(so);
    return aero::forced_oscillation(source, a, progress);
}

}  // namespace manta::vlm
