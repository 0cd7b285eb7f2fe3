#pragma once
/// @file dynamic.hpp
/// Dynamic derivatives by forced harmonic oscillation with the unsteady vortex lattice, extracted
/// from the force histories by Fourier analysis and by linear regression (aero/oscillation.hpp),
/// as the paper does with its CFD (docs/forced-oscillation.md).

#include <array>

#include "manta/aero/motion.hpp"
#include "manta/aero/oscillation.hpp"
#include "manta/vlm/lattice.hpp"
#include "manta/vlm/model.hpp"
#include "manta/vlm/unsteady.hpp"

namespace manta::vlm {

struct ForcedOscillationOptions {
    aero::OscillationAxis axis = aero::OscillationAxis::pitch;
    /// Amplitude of the oscillating angle [rad] (1 deg); for plunge, of the angle of attack
    /// (height amplitude A V / omega).
    double amplitude = 0.0174533;
    /// Reduced frequency k = omega l / (2 V), l = c_ref for pitch and plunge, b_ref for roll and
    /// yaw.
    double reduced_frequency = 0.05;
    double alpha0 = 0.0;   ///< mean angle of attack [rad] (a constant pitch attitude)
    double speed = 100.0;  ///< v0 [m/s] (the lattice is scale-free; only k and M matter)
    int n_periods = 3;     ///< simulated; the first is discarded as the start transient
    int steps_per_period = 48;
    UnsteadyOptions solver;  ///< dt and speed are set from the above
};

/// In-phase and out-of-phase derivatives of the six coefficients {CL CD CY Cl Cm Cn}, per radian
/// of the oscillating angle and per non-dimensional rate (see docs/forced-oscillation.md for the
/// combination each axis measures: pitch C_q + C_alphadot, roll C_p + C_betadot sin alpha0, yaw
/// C_r cos alpha0 - C_p sin alpha0 - C_betadot, about the motion's axes).
struct ForcedOscillationResult {
    ForcedOscillationOptions options;
    double omega = 0.0;  ///< [rad/s]
    std::array<aero::OscillationResult, 6> coefficients;
    UnsteadyHistory history;
};

/// Run the oscillation and analyse it. InputError for options out of range.
[[nodiscard]] ForcedOscillationResult forced_oscillation(const Model& model, const Lattice& lattice,
                                                         const ForcedOscillationOptions& options);

}  // namespace manta::vlm
