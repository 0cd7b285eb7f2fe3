#include "manta/vlm/dynamic.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "manta/core/error.hpp"

namespace manta::vlm {

ForcedOscillationResult forced_oscillation(const Model& model, const Lattice& lattice,
                                           const ForcedOscillationOptions& o) {
    if (!(o.amplitude > 0.0 && o.reduced_frequency > 0.0 && o.speed > 0.0))
        throw InputError(fmt::format(
            "forced oscillation: amplitude {}, reduced frequency {}, speed {}; expected all > 0",
            o.amplitude, o.reduced_frequency, o.speed));
    if (o.n_periods < 2 || o.steps_per_period < 8)
        throw InputError(fmt::format(
            "forced oscillation: {} periods of {} steps; expected >= 2 periods of >= 8 steps",
            o.n_periods, o.steps_per_period));
    const bool lateral =
        o.axis == aero::OscillationAxis::roll || o.axis == aero::OscillationAxis::yaw;
    const double lref = lateral ? model.reference.span : model.reference.chord;
    const double omega = 2.0 * o.speed * o.reduced_frequency / lref;
    const double period = 2.0 * std::numbers::pi / omega;
    const double mean = o.axis == aero::OscillationAxis::pitch ? o.alpha0 : 0.0;
    // Plunge: the angle-of-attack amplitude A needs a height amplitude h = A V / omega, and the
    // angle of attack leads the height by a quarter period.
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
    ForcedOscillationResult r;
    r.options = o;
    r.omega = omega;
    r.history = solver.run(motion);

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
    const std::vector<double> t = r.history.time();
    const std::vector<double> c[6] = {r.history.column(&UnsteadyStep::CL),
                                      r.history.column(&UnsteadyStep::CD),
                                      r.history.column(&UnsteadyStep::CY),
                                      [&] {
                                          std::vector<double> v;
                                          for (const auto& s : r.history.steps)
                                              v.push_back(s.body.Cl);
                                          return v;
                                      }(),
                                      [&] {
                                          std::vector<double> v;
                                          for (const auto& s : r.history.steps)
                                              v.push_back(s.body.Cm);
                                          return v;
                                      }(),
                                      [&] {
                                          std::vector<double> v;
                                          for (const auto& s : r.history.steps)
                                              v.push_back(s.body.Cn);
                                          return v;
                                      }()};
    for (int k = 0; k < 6; ++k)
        r.coefficients[static_cast<std::size_t>(k)] = aero::analyse_oscillation(t, c[k], spec);
    return r;
}

}  // namespace manta::vlm
