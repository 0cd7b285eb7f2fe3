#pragma once
/// @file oscillation.hpp
/// Dynamic derivatives from forced-oscillation time histories (theory, equations and references:
/// docs/forced-oscillation.md).
///
/// The motion variable oscillates harmonically, x(t) = x0 + A sin(omega t + phase) (x = alpha or
/// an attitude angle [rad]), with the non-dimensional rate xdot_hat = xdot lref / (2V) =
/// A k cos(omega t + phase), k = omega lref / (2V) the reduced frequency. A coefficient history
/// C(t) is reduced over the last whole periods to
///
///     C ~ C0 + C_x (x - x0) + C_xdot_hat xdot_hat,
///
/// C_x the in-phase derivative and C_xdot_hat the out-of-phase (damping) one, which for a motion
/// that changes an angle and a rate together is a combination: a pitch oscillation (x = theta =
/// alpha, lref = c) gives Cm_alpha and Cm_q + Cm_alphadot (per q_hat = q c / 2V). The other
/// axes of `harmonic_motion` are worked out in docs/forced-oscillation.md.
///
/// Two estimates are returned: (a) Fourier analysis, C0 + Ca sin + Cb cos projected with the
/// trapezoidal rule, C_x = Ca / A, C_xdot_hat = Cb / (A k); (b) weighted linear least squares of
/// C on (1, x - x0, xdot_hat), with the residual RMS and R^2.

#include <cstddef>
#include <span>

namespace manta::aero {

/// Reduced frequency k = omega lref / (2 V): omega [rad/s], lref [m] (c for pitch, b for roll and
/// yaw), airspeed V [m/s] > 0.
[[nodiscard]] double reduced_frequency(double omega, double lref, double airspeed);

/// The harmonic motion and the analysis window.
struct OscillationSpec {
    double x0 = 0.0;                 ///< mean of the motion variable [rad]
    double amplitude = 0.0;          ///< A > 0 [rad]
    double omega = 0.0;              ///< angular frequency > 0 [rad/s]
    double reduced_frequency = 0.0;  ///< k = omega lref / (2V) > 0
    double phase = 0.0;              ///< x = x0 + A sin(omega t + phase) [rad]
    /// Analyse the last `n_periods` whole periods of the history (ending at its last sample); 0:
    /// as many whole periods as the history holds.
    int n_periods = 0;
    /// How near a sample must lie to the window start t_end - n T, relative to the period T.
    double period_tolerance = 1e-6;
};

/// Fourier estimate: C ~ c0 + c_sin sin(omega t + phase) + c_cos cos(omega t + phase).
struct FourierEstimate {
    double c0 = 0.0;
    double c_sin = 0.0;         ///< Ca
    double c_cos = 0.0;         ///< Cb
    double in_phase = 0.0;      ///< C_x = Ca / A [1/rad]
    double out_of_phase = 0.0;  ///< C_xdot_hat = Cb / (A k)
};

/// Least-squares estimate: C ~ c0 + in_phase (x - x0) + out_of_phase xdot_hat.
struct RegressionEstimate {
    double c0 = 0.0;
    double in_phase = 0.0;      ///< C_x [1/rad]
    double out_of_phase = 0.0;  ///< C_xdot_hat
    double residual_rms = 0.0;  ///< time-weighted RMS of C minus the fit
    double r_squared = 0.0;     ///< 1 - SS_res / SS_tot (time-weighted); 1 when C is constant
};

/// Result of `analyse_oscillation`.
struct OscillationResult {
    double mean = 0.0;  ///< time average of C over the window (trapezoidal rule)
    FourierEstimate fourier;
    RegressionEstimate regression;
    int n_periods = 0;             ///< whole periods analysed
    double t_begin = 0.0;          ///< window start [s] (a sample)
    double t_end = 0.0;            ///< window end [s] (the last sample)
    std::size_t first_sample = 0;  ///< index of the window's first sample
    std::size_t n_samples = 0;     ///< samples in the window, both ends included
};

/// Analyse C(t) sampled at strictly increasing times `t` (uniform or not) under the harmonic of
/// `spec`; the regression uses x - x0 = A sin(omega t + phase) and xdot_hat = A k cos(omega t +
/// phase). InputError (one line) for mismatched sizes, fewer than 3 samples, non-finite or
/// non-increasing times, non-finite values, a bad spec, a window that does not begin on a sample
/// (not whole periods) or reaches before the first sample, or too few samples per period.
[[nodiscard]] OscillationResult analyse_oscillation(std::span<const double> t,
                                                    std::span<const double> c,
                                                    const OscillationSpec& spec);

/// As above, with the regression on given histories x(t) [rad] and xdot_hat(t) (e.g. the motion
/// as the solver actually ran it); the Fourier estimate still uses the harmonic of `spec`.
[[nodiscard]] OscillationResult analyse_oscillation(std::span<const double> t,
                                                    std::span<const double> c,
                                                    std::span<const double> x,
                                                    std::span<const double> xdot_hat,
                                                    const OscillationSpec& spec);

}  // namespace manta::aero
