// Forced-oscillation analysis: recovery of known in-phase and out-of-phase derivatives by Fourier
// projection and regression, whole-period windows, non-uniform samples, errors.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "manta/aero/motion.hpp"
#include "manta/aero/oscillation.hpp"
#include "manta/core/error.hpp"

namespace manta::aero {
namespace {

constexpr double pi = std::numbers::pi;

/// A synthetic coefficient C0 + a A sin(wt + ph) + b A k cos(wt + ph) + d sin(2 (wt + ph) + 0.3)
/// + a transient that vanishes after `t_transient`.
struct Signal {
    double c0 = 0.12, a = -1.3, b = -7.5, d = 0.0, transient = 0.0, t_transient = 0.0;
    OscillationSpec spec;
    [[nodiscard]] double operator()(double t) const {
        const double arg = spec.omega * t + spec.phase;
        const double A = spec.amplitude, k = spec.reduced_frequency;
        const double fade = t < t_transient ? (t_transient - t) * (t_transient - t) : 0.0;
        return c0 + a * A * std::sin(arg) + b * A * k * std::cos(arg) +
               d * std::sin(2 * arg + 0.3) + transient * fade;
    }
};

OscillationSpec pitch_spec() {
    OscillationSpec s;
    s.x0 = 0.05;
    s.amplitude = 2.0 * pi / 180.0;
    s.omega = 2.0 * pi * 1.5;                                     // 1.5 Hz
    s.reduced_frequency = reduced_frequency(s.omega, 2.0, 60.0);  // c = 2 m, V = 60 m/s
    return s;
}

std::vector<double> uniform_times(double period, int n_periods, int per_period, double t0 = 0.0) {
    std::vector<double> t;
    for (int i = 0; i <= n_periods * per_period; ++i) t.push_back(t0 + period * i / per_period);
    return t;
}

std::vector<double> sample(const Signal& f, const std::vector<double>& t) {
    std::vector<double> c;
    for (const double ti : t) c.push_back(f(ti));
    return c;
}

TEST(ForcedOscillation, ReducedFrequency) {
    EXPECT_DOUBLE_EQ(reduced_frequency(10.0, 2.0, 50.0), 0.2);
    EXPECT_THROW((void)reduced_frequency(1.0, 2.0, 0.0), InputError);
    EXPECT_THROW((void)reduced_frequency(1.0, -2.0, 10.0), InputError);
}

TEST(ForcedOscillation, FourierAndRegressionRecoverKnownDerivatives) {
    Signal f;
    f.spec = pitch_spec();
    f.d = 0.04;         // second harmonic: no bias over whole periods
    f.transient = 0.3;  // only in the first period, which the window leaves out
    const double period = 2 * pi / f.spec.omega;
    f.t_transient = period;
    f.spec.n_periods = 2;
    const auto t = uniform_times(period, 3, 40);
    const auto c = sample(f, t);
    const OscillationResult r = analyse_oscillation(t, c, f.spec);

    EXPECT_EQ(r.n_periods, 2);
    EXPECT_EQ(r.first_sample, 40u);
    EXPECT_EQ(r.n_samples, 81u);
    EXPECT_NEAR(r.t_begin, period, 1e-14);
    EXPECT_EQ(r.t_end, t.back());
    EXPECT_NEAR(r.mean, f.c0, 1e-14);

    EXPECT_NEAR(r.fourier.c0, f.c0, 1e-14);
    EXPECT_NEAR(r.fourier.c_sin, f.a * f.spec.amplitude, 1e-14);
    EXPECT_NEAR(r.fourier.c_cos, f.b * f.spec.amplitude * f.spec.reduced_frequency, 1e-14);
    EXPECT_NEAR(r.fourier.in_phase, f.a, 1e-12);
    EXPECT_NEAR(r.fourier.out_of_phase, f.b, 1e-10);

    EXPECT_NEAR(r.regression.c0, f.c0, 1e-14);
    EXPECT_NEAR(r.regression.in_phase, f.a, 1e-12);
    EXPECT_NEAR(r.regression.out_of_phase, f.b, 1e-10);
    // What is left is the second harmonic: RMS d / sqrt(2), and R^2 from the variances.
    EXPECT_NEAR(r.regression.residual_rms, f.d / std::sqrt(2.0), 1e-14);
    const double ca = f.a * f.spec.amplitude,
                 cb = f.b * f.spec.amplitude * f.spec.reduced_frequency;
    const double var = 0.5 * (ca * ca + cb * cb + f.d * f.d);
    EXPECT_NEAR(r.regression.r_squared, 1.0 - 0.5 * f.d * f.d / var, 1e-12);
}

TEST(ForcedOscillation, PureHarmonicFitsPerfectly) {
    Signal f;
    f.spec = pitch_spec();
    f.spec.phase = 0.7;
    const double period = 2 * pi / f.spec.omega;
    const auto t = uniform_times(period, 2, 17, 0.3);
    const auto c = sample(f, t);
    const OscillationResult r = analyse_oscillation(t, c, f.spec);
    EXPECT_EQ(r.n_periods, 2);  // n_periods = 0: every whole period
    EXPECT_NEAR(r.fourier.in_phase, f.a, 1e-12);
    EXPECT_NEAR(r.fourier.out_of_phase, f.b, 1e-10);
    EXPECT_NEAR(r.regression.in_phase, f.a, 1e-12);
    EXPECT_NEAR(r.regression.out_of_phase, f.b, 1e-10);
    EXPECT_LT(r.regression.residual_rms, 1e-15);
    EXPECT_NEAR(r.regression.r_squared, 1.0, 1e-14);
}

TEST(ForcedOscillation, EveryWholePeriodTheHistoryHolds) {
    Signal f;
    f.spec = pitch_spec();
    const double period = 2 * pi / f.spec.omega;
    // 3.5 periods, the last sample at 3.5 T: the window is the last 3 whole periods.
    std::vector<double> t;
    for (int i = 0; i <= 70; ++i) t.push_back(period * i / 20.0);
    const OscillationResult r = analyse_oscillation(t, sample(f, t), f.spec);
    EXPECT_EQ(r.n_periods, 3);
    EXPECT_EQ(r.first_sample, 10u);
    EXPECT_NEAR(r.fourier.out_of_phase, f.b, 1e-10);
}

TEST(ForcedOscillation, NonUniformSamples) {
    Signal f;
    f.spec = pitch_spec();
    f.spec.n_periods = 3;
    const double period = 2 * pi / f.spec.omega;
    // Jittered samples; the period boundaries are samples.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-0.35, 0.35);
    std::vector<double> t;
    const int per = 30;
    for (int p = 0; p < 3; ++p) {
        for (int i = 0; i < per; ++i) {
            const double u = i == 0 ? 0.0 : (i + jitter(rng)) / per;
            t.push_back(period * (p + u));
        }
    }
    t.push_back(3 * period);
    const OscillationResult r = analyse_oscillation(t, sample(f, t), f.spec);
    // A signal in the span of (1, sin, cos) is recovered exactly on any sampling.
    EXPECT_NEAR(r.fourier.c0, f.c0, 1e-13);
    EXPECT_NEAR(r.fourier.in_phase, f.a, 1e-11);
    EXPECT_NEAR(r.fourier.out_of_phase, f.b, 1e-9);
    EXPECT_NEAR(r.regression.in_phase, f.a, 1e-11);
    EXPECT_NEAR(r.regression.out_of_phase, f.b, 1e-9);
    EXPECT_NEAR(r.mean, f.c0, 1e-3);  // the plain trapezoidal mean carries quadrature error

    // A second harmonic leaks only through quadrature error, small at 30 samples a period.
    f.d = 0.02;
    const OscillationResult h = analyse_oscillation(t, sample(f, t), f.spec);
    EXPECT_NEAR(h.fourier.in_phase, f.a, 0.02 * std::abs(f.a));
    EXPECT_NEAR(h.fourier.out_of_phase, f.b, 0.02 * std::abs(f.b));
}

TEST(ForcedOscillation, GivenMotionHistories) {
    Signal f;
    f.spec = pitch_spec();
    f.spec.n_periods = 1;
    const double period = 2 * pi / f.spec.omega;
    const auto t = uniform_times(period, 2, 32);
    std::vector<double> x, xdot_hat;
    for (const double ti : t) {
        x.push_back(f.spec.x0 + f.spec.amplitude * std::sin(f.spec.omega * ti));
        xdot_hat.push_back(f.spec.amplitude * f.spec.reduced_frequency *
                           std::cos(f.spec.omega * ti));
    }
    const OscillationResult r = analyse_oscillation(t, sample(f, t), x, xdot_hat, f.spec);
    EXPECT_EQ(r.first_sample, 32u);
    EXPECT_NEAR(r.regression.c0, f.c0, 1e-14);
    EXPECT_NEAR(r.regression.in_phase, f.a, 1e-12);
    EXPECT_NEAR(r.regression.out_of_phase, f.b, 1e-10);
    EXPECT_NEAR(r.fourier.out_of_phase, f.b, 1e-10);

    // Collinear regressors are refused.
    std::vector<double> collinear(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) collinear[i] = 2.0 * (x[i] - f.spec.x0);
    EXPECT_THROW((void)analyse_oscillation(t, sample(f, t), x, collinear, f.spec), InputError);
}

TEST(ForcedOscillation, FromAHarmonicMotion) {
    // Pitch oscillation built by harmonic_motion; Cm = Cm0 + Cm_alpha theta + Cm_q q_hat with
    // q_hat from the motion's interpolated body rate.
    const double c_ref = 1.5, v = 80.0, amplitude = 0.03, omega = 6.0;
    const double cm0 = 0.02, cm_alpha = -0.9, cm_q = -12.0;
    const Motion m = harmonic_motion(OscillationAxis::pitch, amplitude, omega, 3, 64);
    std::vector<double> cm;
    for (const double t : m.t) {
        const MotionState s = m.at(t);
        cm.push_back(cm0 + cm_alpha * s.euler[1] + cm_q * s.omega_body[1] * c_ref / (2 * v));
    }
    OscillationSpec spec;
    spec.amplitude = amplitude;
    spec.omega = omega;
    spec.reduced_frequency = reduced_frequency(omega, c_ref, v);
    spec.n_periods = 2;
    const OscillationResult r = analyse_oscillation(m.t, cm, spec);
    // The interpolated rate carries the finite-difference error, largest at the last sample.
    EXPECT_NEAR(r.fourier.c0, cm0, 1e-10);
    EXPECT_NEAR(r.fourier.in_phase, cm_alpha, 1e-7);
    EXPECT_NEAR(r.fourier.out_of_phase, cm_q, 1e-4 * std::abs(cm_q));
    EXPECT_NEAR(r.regression.out_of_phase, cm_q, 1e-4 * std::abs(cm_q));
}

void expect_input_error(const std::vector<double>& t, const std::vector<double>& c,
                        const OscillationSpec& spec, const std::string& part) {
    try {
        (void)analyse_oscillation(t, c, spec);
        ADD_FAILURE() << "no error; expected one with '" << part << "'";
    } catch (const InputError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find(part), std::string::npos) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
}

TEST(ForcedOscillation, RejectsWindowsOfPartPeriods) {
    Signal f;
    f.spec = pitch_spec();
    const double period = 2 * pi / f.spec.omega;
    // 37.5 samples a period: one period back from the last sample falls between two samples.
    std::vector<double> t;
    for (int i = 0; i <= 150; ++i) t.push_back(period * i / 37.5);
    f.spec.n_periods = 1;
    expect_input_error(t, sample(f, t), f.spec, "whole periods");
    f.spec.n_periods = 2;
    EXPECT_NO_THROW((void)analyse_oscillation(t, sample(f, t), f.spec));  // 75 samples back
    f.spec.n_periods = 5;
    expect_input_error(t, sample(f, t), f.spec, "before the first sample");
    // Less than one period in all.
    const auto short_t = uniform_times(0.9 * period, 1, 20);
    f.spec.n_periods = 0;
    expect_input_error(short_t, sample(f, short_t), f.spec, "no whole period");
}

TEST(ForcedOscillation, RejectsBadInput) {
    Signal f;
    f.spec = pitch_spec();
    const double period = 2 * pi / f.spec.omega;
    const auto t = uniform_times(period, 1, 16);
    const auto c = sample(f, t);
    {
        auto shorter = c;
        shorter.pop_back();
        expect_input_error(t, shorter, f.spec, "samples but t has");
    }
    {
        auto back = t;
        back[5] = back[4];
        expect_input_error(back, c, f.spec, "t[5]");
    }
    {
        auto bad = c;
        bad[3] = std::nan("");
        expect_input_error(t, bad, f.spec, "C[3]");
    }
    for (const auto& [field, value] : std::vector<std::pair<std::string, double>>{
             {"amplitude", 0.0}, {"omega", -1.0}, {"reduced_frequency", 0.0}}) {
        OscillationSpec s = f.spec;
        (field == "amplitude" ? s.amplitude
         : field == "omega"   ? s.omega
                              : s.reduced_frequency) = value;
        expect_input_error(t, c, s, field);
    }
    {
        OscillationSpec s = f.spec;
        s.n_periods = -1;
        expect_input_error(t, c, s, "n_periods");
    }
    {
        // Two samples a period cannot tell sine from cosine.
        const auto coarse = uniform_times(period, 3, 2);
        expect_input_error(coarse, sample(f, coarse), f.spec, "cannot separate");
    }
}

}  // namespace
}  // namespace manta::aero
