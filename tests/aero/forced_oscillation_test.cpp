// The source-generic forced-oscillation driver (aero/forced_oscillation.hpp) on an analytic
// source that can move: a linear quasi-steady model with known derivatives, whose in-phase and
// out-of-phase parts on each axis are the combinations of docs/forced-oscillation.md (Da Ronch
// et al., Prog. Aerosp. Sci. 47, 2011, sec. 3; Greenwell, AIAA 2004-5276), checkpoints that a
// second call resumes bit for bit, and bad options and checkpoints as one-line input errors.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <stdexcept>
#include <string>

#include <unistd.h>

#include "manta/aero/forced_oscillation.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"

namespace manta::aero {
namespace {

constexpr double pi = std::numbers::pi;
constexpr double chord = 1.6, span = 9.0;

/// Derivatives of the analytic source.
constexpr double CL0 = 0.2, CL_alpha = 5.0, CL_q = 8.0;
constexpr double Cl_p = -0.45, Cl_beta = -0.08;
constexpr double Cn_beta = 0.11, Cn_r = -0.17;
constexpr double Cm_alpha = -0.7, lag_tau = 0.05;  // Cm lags alpha by a first-order filter

/// A run of the analytic source: coefficients from the motion's air-relative state at each
/// instant, and a lagged angle of attack as the state that save/restore must carry.
class LinearRun final : public UnsteadyRun {
public:
    LinearRun(Motion motion, double dt) : motion_(std::move(motion)), dt_(dt) {
        if (!(dt_ > 0.0)) throw InputError("linear source: dt must be > 0");
        n_steps_ = static_cast<int>(std::lround((motion_.t.back() - motion_.t.front()) / dt_));
        lag_ = air(motion_.t.front()).alpha;
        sample(0);
    }
    [[nodiscard]] const UnsteadySample& current() const override { return s_; }
    const UnsteadySample& step() override {
        if (finished()) throw InputError("linear source: past the motion's end");
        const int n = s_.index + 1;
        const double alpha = air(time(n)).alpha;
        lag_ += dt_ / (lag_tau + dt_) * (alpha - lag_);  // implicit Euler
        sample(n);
        return s_;
    }
    [[nodiscard]] bool finished() const override { return s_.index >= n_steps_; }
    [[nodiscard]] int n_steps() const override { return n_steps_; }
    [[nodiscard]] double dt() const override { return dt_; }
    void save(const std::filesystem::path& file) const override {
        std::string b(sizeof(int) + sizeof(double), '\0');
        std::memcpy(b.data(), &s_.index, sizeof(int));
        std::memcpy(b.data() + sizeof(int), &lag_, sizeof(double));
        core::write_file_atomic(file, b);
    }
    void restore(const std::filesystem::path& file) override {
        const std::string b = core::read_file(file);
        if (b.size() != sizeof(int) + sizeof(double))
            throw InputError("linear source: not a state of this run");
        int n = 0;
        std::memcpy(&n, b.data(), sizeof(int));
        std::memcpy(&lag_, b.data() + sizeof(int), sizeof(double));
        sample(n);
    }

private:
    struct Air {
        double alpha, beta, V, p_hat, q_hat, r_hat;
    };
    [[nodiscard]] double time(int n) const { return motion_.t.front() + n * dt_; }
    [[nodiscard]] Air air(double t) const {
        const MotionState m = motion_.at(t);
        const double v0 = *motion_.metadata.v0;
        // Air-relative velocity of the reference point in the motion frame, to body axes (3-2-1).
        const double vx = v0 + m.velocity[0], vy = m.velocity[1], vz = m.velocity[2];
        const double cf = std::cos(m.euler[0]), sf = std::sin(m.euler[0]);
        const double ct = std::cos(m.euler[1]), st = std::sin(m.euler[1]);
        const double cp = std::cos(m.euler[2]), sp = std::sin(m.euler[2]);
        const double u = ct * cp * vx + ct * sp * vy - st * vz;
        const double v =
            (sf * st * cp - cf * sp) * vx + (sf * st * sp + cf * cp) * vy + sf * ct * vz;
        const double w =
            (cf * st * cp + sf * sp) * vx + (cf * st * sp - sf * cp) * vy + cf * ct * vz;
        Air a;
        a.V = std::sqrt(u * u + v * v + w * w);
        a.alpha = std::atan2(w, u);
        a.beta = std::asin(v / a.V);
        a.p_hat = m.omega_body[0] * span / (2 * a.V);
        a.q_hat = m.omega_body[1] * chord / (2 * a.V);
        a.r_hat = m.omega_body[2] * span / (2 * a.V);
        return a;
    }
    void sample(int n) {
        const double t = time(n);
        const Air a = air(t);
        s_ = {};
        s_.index = n;
        s_.t = t;
        s_.alpha = a.alpha;
        s_.beta = a.beta;
        s_.airspeed = a.V;
        s_.wind.CL = CL0 + CL_alpha * a.alpha + CL_q * a.q_hat;
        s_.body.Cl = Cl_beta * a.beta + Cl_p * a.p_hat;
        s_.body.Cm = Cm_alpha * lag_;
        s_.body.Cn = Cn_beta * a.beta + Cn_r * a.r_hat;
    }
    Motion motion_;
    double dt_;
    int n_steps_ = 0;
    double lag_ = 0.0;
    UnsteadySample s_;
};

class LinearSource final : public AeroSource {
public:
    [[nodiscard]] std::string name() const override { return "linear"; }
    [[nodiscard]] std::string fingerprint() const override { return "linear:1"; }
    [[nodiscard]] SourceResult evaluate(const AeroQuery<double>&,
                                        const FlowConditions&) const override {
        return {};
    }
    [[nodiscard]] bool unsteady() const override { return true; }
    [[nodiscard]] std::unique_ptr<UnsteadyRun> start_unsteady(
        const Motion& motion, const UnsteadySettings& settings) const override {
        return std::make_unique<LinearRun>(motion, settings.dt);
    }
};

/// A source without an unsteady mode.
class SteadyOnlySource final : public AeroSource {
public:
    [[nodiscard]] std::string name() const override { return "steady-only"; }
    [[nodiscard]] std::string fingerprint() const override { return "steady-only"; }
    [[nodiscard]] SourceResult evaluate(const AeroQuery<double>&,
                                        const FlowConditions&) const override {
        return {};
    }
};

ForcedOscillationOptions options(OscillationAxis axis) {
    ForcedOscillationOptions o;
    o.axis = axis;
    o.amplitude = 1.5 * pi / 180.0;
    o.reduced_frequency = 0.08;
    o.speed = 60.0;
    o.n_periods = 3;
    o.steps_per_period = 32;
    o.chord = chord;
    o.span = span;
    return o;
}

std::filesystem::path scratch(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() /
                     ("manta_forced_oscillation_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const auto f = dir / name;
    std::filesystem::remove(f);
    return f;
}

TEST(ForcedOscillationDriver, MotionAndFrequency) {
    ForcedOscillationOptions o = options(OscillationAxis::pitch);
    o.alpha0 = 0.05;
    o.mach = 0.3;
    const double omega = oscillation_omega(o);
    EXPECT_DOUBLE_EQ(omega, 2 * o.speed * o.reduced_frequency / chord);
    EXPECT_DOUBLE_EQ(oscillation_omega(options(OscillationAxis::roll)),
                     2 * o.speed * o.reduced_frequency / span);
    const Motion m = oscillation_motion(o);
    ASSERT_EQ(m.t.size(), 3u * 32u + 1u);
    EXPECT_NEAR(m.t.back(), 3 * 2 * pi / omega, 1e-12);
    EXPECT_EQ(*m.metadata.v0, o.speed);
    EXPECT_EQ(*m.metadata.mach, 0.3);
    EXPECT_NEAR(m.angles[1][8], o.alpha0 + o.amplitude, 1e-15);  // a quarter period in
    // Plunge: height amplitude A V / omega, alpha0 as a constant attitude.
    o.axis = OscillationAxis::plunge;
    const Motion p = oscillation_motion(o);
    EXPECT_NEAR(p.position[2][8], o.amplitude * o.speed / omega, 1e-12);
    EXPECT_EQ(p.angles[1][5], o.alpha0);
}

// The combinations each axis measures (docs/forced-oscillation.md, "Which derivatives each
// motion gives"): pitch C_alpha and C_q (+ C_alphadot, here 0); plunge C_alpha and C_alphadot
// = 0; roll at alpha0 = 0 C_p; yaw at alpha0 = 0 -C_beta and C_r - C_betadot.
TEST(ForcedOscillationDriver, AxesGiveTheirDerivatives) {
    const LinearSource src;
    const ForcedOscillationResult pitch = forced_oscillation(src, options(OscillationAxis::pitch));
    ASSERT_EQ(pitch.history.size(), 97u);
    EXPECT_EQ(pitch.resumed_from, -1);
    EXPECT_EQ(pitch.steps_computed, 96);
    const OscillationResult& cl = pitch.coefficients[0];
    EXPECT_EQ(cl.n_periods, 2);  // the first period discarded
    EXPECT_EQ(cl.first_sample, 32u);
    // Rates come from the motion's interpolant (fourth-order node slopes): 1e-4 relative.
    EXPECT_NEAR(cl.fourier.in_phase, CL_alpha, 1e-4 * CL_alpha);
    EXPECT_NEAR(cl.fourier.out_of_phase, CL_q, 1e-3 * CL_q);
    EXPECT_NEAR(cl.regression.in_phase, CL_alpha, 1e-4 * CL_alpha);
    EXPECT_NEAR(cl.regression.out_of_phase, CL_q, 1e-3 * CL_q);
    EXPECT_NEAR(cl.mean, CL0, 1e-6);
    EXPECT_GT(cl.regression.r_squared, 1 - 1e-6);
    // Cm lags alpha (first-order filter, tau omega = phi): in phase Cm_alpha / (1 + phi^2),
    // out of phase -Cm_alpha phi / (1 + phi^2) / k (implicit Euler: to O(omega dt)).
    const double phi = lag_tau * pitch.omega;
    const double k = options(OscillationAxis::pitch).reduced_frequency;
    const OscillationResult& cm = pitch.coefficients[4];
    EXPECT_NEAR(cm.fourier.in_phase, Cm_alpha / (1 + phi * phi), 0.05 * std::abs(Cm_alpha));
    EXPECT_NEAR(cm.fourier.out_of_phase, -Cm_alpha * phi / (1 + phi * phi) / k,
                0.1 * std::abs(Cm_alpha * phi / k));

    const ForcedOscillationResult plunge =
        forced_oscillation(src, options(OscillationAxis::plunge));
    EXPECT_NEAR(plunge.coefficients[0].fourier.in_phase, CL_alpha, 1e-3 * CL_alpha);
    EXPECT_NEAR(plunge.coefficients[0].fourier.out_of_phase, 0.0, 1e-3 * CL_q);
    EXPECT_NEAR(plunge.coefficients[0].regression.in_phase, CL_alpha, 1e-3 * CL_alpha);

    const ForcedOscillationResult roll = forced_oscillation(src, options(OscillationAxis::roll));
    EXPECT_NEAR(roll.coefficients[3].fourier.out_of_phase, Cl_p, 1e-3 * std::abs(Cl_p));
    // beta = phi sin(alpha0) = 0: what is left is the rates' interpolation error.
    EXPECT_NEAR(roll.coefficients[3].fourier.in_phase, 0.0, 1e-6);

    const ForcedOscillationResult yaw = forced_oscillation(src, options(OscillationAxis::yaw));
    EXPECT_NEAR(yaw.coefficients[5].fourier.in_phase, -Cn_beta, 1e-3 * Cn_beta);
    EXPECT_NEAR(yaw.coefficients[5].fourier.out_of_phase, Cn_r, 1e-3 * std::abs(Cn_r));
    EXPECT_NEAR(yaw.coefficients[5].regression.out_of_phase, Cn_r, 1e-3 * std::abs(Cn_r));
}

// The analysis of a synthetic history, built sample by sample: the known derivatives back to
// rounding, the first period's transient left out.
TEST(ForcedOscillationDriver, AnalysisOfASyntheticHistory) {
    ForcedOscillationOptions o = options(OscillationAxis::pitch);
    o.alpha0 = 0.04;
    const double omega = oscillation_omega(o);
    const double period = 2 * pi / omega;
    const double a = -1.1, b = -9.0;  // Cm_alpha, Cm_q + Cm_alphadot
    std::vector<UnsteadySample> h;
    const int n = o.n_periods * o.steps_per_period;
    for (int i = 0; i <= n; ++i) {
        UnsteadySample s;
        s.index = i;
        s.t = period * i / o.steps_per_period;
        const double arg = omega * s.t;
        const double transient = s.t < period ? 0.5 * (period - s.t) : 0.0;
        s.body.Cm = 0.03 + a * o.amplitude * std::sin(arg) +
                    b * o.amplitude * o.reduced_frequency * std::cos(arg) + transient;
        s.wind.CL = 0.4;
        h.push_back(s);
    }
    const auto r = analyse_forced_oscillation(h, o);
    EXPECT_NEAR(r[4].fourier.in_phase, a, 1e-11);
    EXPECT_NEAR(r[4].fourier.out_of_phase, b, 1e-9);
    EXPECT_NEAR(r[4].regression.in_phase, a, 1e-11);
    EXPECT_NEAR(r[4].regression.out_of_phase, b, 1e-9);
    EXPECT_NEAR(r[4].mean, 0.03, 1e-14);
    EXPECT_NEAR(r[0].fourier.in_phase, 0.0, 1e-12);  // constant CL
    EXPECT_NEAR(r[0].mean, 0.4, 1e-15);
    // A history shorter than the n_periods - 1 periods analysed is refused.
    h.resize(static_cast<std::size_t>(o.steps_per_period * 3 / 2));
    EXPECT_THROW((void)analyse_forced_oscillation(h, o), InputError);
}

struct Interrupted : std::runtime_error {
    Interrupted() : std::runtime_error("interrupted") {}
};

// A run stopped after a checkpoint (an exception from the progress callback, as a kill after
// the write) and started again resumes from the checkpoint and gives the uninterrupted history
// and derivatives bit for bit; a finished checkpoint answers without stepping.
TEST(ForcedOscillationDriver, CheckpointResumesBitForBit) {
    const LinearSource src;
    const ForcedOscillationResult whole = forced_oscillation(src, options(OscillationAxis::pitch));

    ForcedOscillationOptions o = options(OscillationAxis::pitch);
    o.checkpoint = scratch("pitch.ckpt");
    o.checkpoint_seconds = 0.0;  // every step
    EXPECT_THROW((void)forced_oscillation(src, o,
                                          [](const ForcedOscillationProgress& p) {
                                              EXPECT_TRUE(p.checkpoint_written);
                                              if (p.step == 40) throw Interrupted();
                                          }),
                 Interrupted);
    ASSERT_TRUE(std::filesystem::exists(o.checkpoint));
    int calls = 0;
    const ForcedOscillationResult resumed =
        forced_oscillation(src, o, [&](const ForcedOscillationProgress& p) {
            ++calls;
            EXPECT_EQ(p.resumed_from, 40);
            EXPECT_EQ(p.n_steps, 96);
            ASSERT_TRUE(p.seconds_left.has_value());
            EXPECT_GE(*p.seconds_left, 0.0);
        });
    EXPECT_EQ(resumed.resumed_from, 40);
    EXPECT_EQ(resumed.steps_computed, 56);
    EXPECT_EQ(calls, 56);
    ASSERT_EQ(resumed.history.size(), whole.history.size());
    for (std::size_t i = 0; i < whole.history.size(); ++i) {
        EXPECT_EQ(resumed.history[i].t, whole.history[i].t);
        EXPECT_EQ(resumed.history[i].wind.CL, whole.history[i].wind.CL);
        EXPECT_EQ(resumed.history[i].body.Cm, whole.history[i].body.Cm) << i;
    }
    for (std::size_t c = 0; c < 6; ++c) {
        EXPECT_EQ(resumed.coefficients[c].fourier.in_phase, whole.coefficients[c].fourier.in_phase);
        EXPECT_EQ(resumed.coefficients[c].regression.out_of_phase,
                  whole.coefficients[c].regression.out_of_phase);
    }
    // Finished: the checkpoint holds the whole run.
    const ForcedOscillationResult again = forced_oscillation(src, o);
    EXPECT_EQ(again.resumed_from, 96);
    EXPECT_EQ(again.steps_computed, 0);
    EXPECT_EQ(again.coefficients[4].fourier.out_of_phase,
              whole.coefficients[4].fourier.out_of_phase);
    // No temporary left beside it.
    for (const auto& e : std::filesystem::directory_iterator(o.checkpoint.parent_path()))
        EXPECT_EQ(e.path().filename().string().find(".state.tmp"), std::string::npos);
}

TEST(ForcedOscillationDriver, CheckpointOfAnotherRunIsRefused) {
    const LinearSource src;
    ForcedOscillationOptions o = options(OscillationAxis::pitch);
    o.checkpoint = scratch("other.ckpt");
    (void)forced_oscillation(src, o);
    o.reduced_frequency = 0.1;
    try {
        (void)forced_oscillation(src, o);
        ADD_FAILURE() << "expected an InputError";
    } catch (const InputError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("checkpoint of another oscillation"), std::string::npos) << m;
        EXPECT_NE(m.find(o.checkpoint.string()), std::string::npos) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
    // Not a checkpoint, and a truncated one.
    core::write_file_atomic(o.checkpoint, "t,CL\n0,1\n");
    EXPECT_THROW((void)forced_oscillation(src, o), InputError);
    o.reduced_frequency = 0.08;
    const auto f = scratch("truncated.ckpt");
    o.checkpoint = f;
    (void)forced_oscillation(src, o);
    const std::string whole = core::read_file(f);
    core::write_file_atomic(f, whole.substr(0, whole.size() / 2));
    try {
        (void)forced_oscillation(src, o);
        ADD_FAILURE() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
    }
}

TEST(ForcedOscillationDriver, BadOptionsAreOneLineInputErrors) {
    const LinearSource src;
    const auto refused = [&](ForcedOscillationOptions o, const std::string& expect) {
        SCOPED_TRACE(expect);
        try {
            (void)forced_oscillation(src, o);
            ADD_FAILURE() << "expected an InputError";
        } catch (const InputError& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find(expect), std::string::npos) << m;
            EXPECT_EQ(m.find('\n'), std::string::npos) << m;
        }
    };
    ForcedOscillationOptions o = options(OscillationAxis::pitch);
    o.reduced_frequency = 0.0;
    refused(o, "reduced frequency = 0");
    o = options(OscillationAxis::pitch);
    o.reduced_frequency = -0.1;
    refused(o, "reduced frequency = -0.1");
    o = options(OscillationAxis::pitch);
    o.amplitude = std::nan("");
    refused(o, "amplitude = nan");
    o = options(OscillationAxis::pitch);
    o.n_periods = 1;
    refused(o, "1 periods; expected >= 2");
    o = options(OscillationAxis::pitch);
    o.steps_per_period = 4;
    refused(o, "4 steps per period; expected >= 8");
    o = options(OscillationAxis::pitch);
    o.chord = 0.0;
    refused(o, "reference chord");
    o = options(OscillationAxis::roll);
    o.span = -1.0;
    refused(o, "reference span");
    o = options(OscillationAxis::pitch);
    o.speed = 0.0;
    refused(o, "speed = 0");
    o = options(OscillationAxis::pitch);
    o.mach = -0.2;
    refused(o, "Mach number -0.2");
    o = options(OscillationAxis::pitch);
    o.checkpoint_seconds = -1.0;
    refused(o, "checkpoint interval");
    // A source that cannot move says so, naming itself.
    try {
        (void)forced_oscillation(SteadyOnlySource{}, options(OscillationAxis::pitch));
        ADD_FAILURE() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("steady-only"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace manta::aero
