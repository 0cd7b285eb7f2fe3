/// @file forced_oscillation.cpp
/// Forced harmonic oscillation on any aero source that can move: motion, run with checkpoints,
/// analysis (docs/forced-oscillation.md).

#include "manta/aero/forced_oscillation.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <string_view>
#include <system_error>

#include <unistd.h>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"

namespace manta::aero {

namespace {

constexpr std::string_view who = "forced oscillation";
constexpr std::string_view magic = "MANTA forced-oscillation checkpoint 1\n";

bool lateral(OscillationAxis axis) {
    return axis == OscillationAxis::roll || axis == OscillationAxis::yaw;
}

/// Everything that defines the run: a checkpoint of another run is refused.
std::string run_fingerprint(const AeroSource& source, const ForcedOscillationOptions& o) {
    const auto x = [](double v) { return core::format_exact(v); };
    return fmt::format(
        "source {} | axis {} amplitude {} k {} alpha0 {} speed {} mach {} periods {} steps {} "
        "chord {} span {} Re/l {}",
        source.fingerprint(), to_string(o.axis), x(o.amplitude), x(o.reduced_frequency),
        x(o.alpha0), x(o.speed), o.mach ? x(*o.mach) : std::string("source"), o.n_periods,
        o.steps_per_period, x(o.chord), x(o.span), x(o.conditions.reynolds_per_metre));
}

// Checkpoint layout (native byte order, like the sources' own states): the magic line, the
// fingerprint's length and text, the number of samples and per sample its index and 13 doubles
// (t, CX CY CZ Cl Cm Cn, CL CD CY, alpha, beta, airspeed), then the run state's length and bytes
// (UnsteadyRun::save's file).

template <class T>
void put(std::string& out, T v) {
    out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

struct Reader {
    std::string_view data;
    std::size_t pos = 0;
    const std::filesystem::path& file;
    void need(std::size_t n) const {
        if (data.size() - pos < n)
            throw InputError(fmt::format(
                "{}: truncated forced-oscillation checkpoint ({} bytes, {} more needed at byte "
                "{}); expected a whole checkpoint, or delete the file to start afresh",
                file.string(), data.size(), n - (data.size() - pos), pos));
    }
    template <class T>
    T get() {
        need(sizeof(T));
        T v;
        std::memcpy(&v, data.data() + pos, sizeof v);
        pos += sizeof v;
        return v;
    }
    std::string_view bytes(std::size_t n) {
        need(n);
        const std::string_view s = data.substr(pos, n);
        pos += n;
        return s;
    }
};

std::filesystem::path state_temporary(const std::filesystem::path& checkpoint) {
    return std::filesystem::path(checkpoint.string() + fmt::format(".state.tmp{}", ::getpid()));
}

void write_checkpoint(const std::filesystem::path& file, const std::string& fingerprint,
                      const std::vector<UnsteadySample>& history, const UnsteadyRun& run) {
    const std::filesystem::path tmp = state_temporary(file);
    run.save(tmp);
    std::string state;
    try {
        state = core::read_file(tmp);
    } catch (...) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        throw;
    }
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    std::string out(magic);
    put<std::uint64_t>(out, fingerprint.size());
    out += fingerprint;
    put<std::uint64_t>(out, history.size());
    for (const UnsteadySample& s : history) {
        put<std::int32_t>(out, s.index);
        for (const double v :
             {s.t, s.body.CX, s.body.CY, s.body.CZ, s.body.Cl, s.body.Cm, s.body.Cn, s.wind.CL,
              s.wind.CD, s.wind.CY, s.alpha, s.beta, s.airspeed})
            put<double>(out, v);
    }
    put<std::uint64_t>(out, state.size());
    out += state;
    core::write_file_atomic(file, out);
}

/// Restore `run` and the history from `file`; returns the step resumed from.
int read_checkpoint(const std::filesystem::path& file, const std::string& fingerprint,
                    std::vector<UnsteadySample>& history, UnsteadyRun& run) {
    const std::string data = core::read_file(file);
    Reader r{data, 0, file};
    if (data.compare(0, magic.size(), magic) != 0)
        throw InputError(fmt::format(
            "{}: not a forced-oscillation checkpoint (its first line is not '{}'); expected a "
            "file written by --checkpoint, or delete it",
            file.string(), magic.substr(0, magic.size() - 1)));
    r.pos = magic.size();
    const auto n_fp = r.get<std::uint64_t>();
    const std::string_view other = r.bytes(n_fp);
    if (other != fingerprint)
        throw InputError(fmt::format(
            "{}: checkpoint of another oscillation ({}); this run is ({}); expected the same "
            "source and options, or delete the file to start afresh",
            file.string(), other, fingerprint));
    const auto n = r.get<std::uint64_t>();
    constexpr std::size_t sample_bytes = sizeof(std::int32_t) + 13 * sizeof(double);
    r.need(n > data.size() ? data.size() + 1 : n * sample_bytes);
    std::vector<UnsteadySample> h(n);
    for (UnsteadySample& s : h) {
        s.index = r.get<std::int32_t>();
        for (double* v :
             {&s.t, &s.body.CX, &s.body.CY, &s.body.CZ, &s.body.Cl, &s.body.Cm, &s.body.Cn,
              &s.wind.CL, &s.wind.CD, &s.wind.CY, &s.alpha, &s.beta, &s.airspeed})
            *v = r.get<double>();
    }
    const auto n_state = r.get<std::uint64_t>();
    const std::string_view state = r.bytes(n_state);
    const std::filesystem::path tmp = state_temporary(file);
    core::write_file_atomic(tmp, state);
    try {
        run.restore(tmp);
    } catch (...) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        throw;
    }
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    const int step = run.current().index;
    if (h.size() != static_cast<std::size_t>(step) + 1 || h.back().index != step)
        throw InputError(fmt::format(
            "{}: checkpoint with {} samples and a run state at step {}; expected step + 1 "
            "samples (a damaged checkpoint: delete it to start afresh)",
            file.string(), h.size(), step));
    history = std::move(h);
    return step;
}

}  // namespace

void check_options(const ForcedOscillationOptions& o) {
    const auto positive = [](double v, std::string_view name, std::string_view unit) {
        if (!(v > 0.0) || !std::isfinite(v))
            throw InputError(
                fmt::format("{}: {} = {}{}; expected a finite number > 0", who, name, v, unit));
    };
    positive(o.amplitude, "amplitude", " rad");
    positive(o.reduced_frequency, "reduced frequency", "");
    positive(o.speed, "speed", " m/s");
    if (lateral(o.axis))
        positive(o.span, "reference span (roll and yaw)", " m");
    else
        positive(o.chord, "reference chord (pitch and plunge)", " m");
    if (!std::isfinite(o.alpha0))
        throw InputError(
            fmt::format("{}: alpha0 = {} rad; expected a finite number", who, o.alpha0));
    if (o.mach && !(*o.mach >= 0.0 && std::isfinite(*o.mach)))
        throw InputError(
            fmt::format("{}: Mach number {}; expected a finite number >= 0", who, *o.mach));
    if (o.n_periods < 2)
        throw InputError(fmt::format(
            "{}: {} periods; expected >= 2 (the first is discarded as the start transient)", who,
            o.n_periods));
    if (o.steps_per_period < 8)
        throw InputError(
            fmt::format("{}: {} steps per period; expected >= 8", who, o.steps_per_period));
    if (!(o.checkpoint_seconds >= 0.0))
        throw InputError(
            fmt::format("{}: checkpoint interval {} s; expected >= 0", who, o.checkpoint_seconds));
}

double oscillation_omega(const ForcedOscillationOptions& o) {
    check_options(o);
    const double lref = lateral(o.axis) ? o.span : o.chord;
    return 2.0 * o.speed * o.reduced_frequency / lref;
}

Motion oscillation_motion(const ForcedOscillationOptions& o) {
    const double omega = oscillation_omega(o);
    const double mean = o.axis == OscillationAxis::pitch ? o.alpha0 : 0.0;
    // Plunge: the angle-of-attack amplitude A needs a height amplitude h = A V / omega, and the
    // angle of attack leads the height by a quarter period.
    const bool plunge = o.axis == OscillationAxis::plunge;
    const double motion_amplitude = plunge ? o.amplitude * o.speed / omega : o.amplitude;
    Motion motion =
        harmonic_motion(o.axis, motion_amplitude, omega, o.n_periods, o.steps_per_period, mean);
    if (o.axis != OscillationAxis::pitch && o.alpha0 != 0.0)
        for (double& th : motion.angles[1]) th = o.alpha0;
    motion.metadata.v0 = o.speed;
    motion.metadata.mach = o.mach;
    return motion;
}

std::array<OscillationResult, 6> analyse_forced_oscillation(
    const std::vector<UnsteadySample>& history, const ForcedOscillationOptions& o) {
    const double omega = oscillation_omega(o);
    OscillationSpec spec;
    spec.x0 = o.axis == OscillationAxis::pitch ? o.alpha0 : 0.0;
    spec.amplitude = o.amplitude;
    spec.omega = omega;
    spec.reduced_frequency = o.reduced_frequency;
    spec.n_periods = o.n_periods - 1;
    if (o.axis == OscillationAxis::plunge) {
        spec.x0 = o.alpha0;
        spec.phase = 0.5 * std::numbers::pi;
    }
    const std::size_t n = history.size();
    std::vector<double> t(n);
    std::array<std::vector<double>, 6> c;
    for (auto& v : c) v.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const UnsteadySample& s = history[i];
        t[i] = s.t;
        c[0][i] = s.wind.CL;
        c[1][i] = s.wind.CD;
        c[2][i] = s.wind.CY;
        c[3][i] = s.body.Cl;
        c[4][i] = s.body.Cm;
        c[5][i] = s.body.Cn;
    }
    std::array<OscillationResult, 6> r;
    for (std::size_t k = 0; k < 6; ++k) r[k] = analyse_oscillation(t, c[k], spec);
    return r;
}

ForcedOscillationResult forced_oscillation(const AeroSource& source,
                                           const ForcedOscillationOptions& o,
                                           const ForcedOscillationCallback& progress) {
    using clock = std::chrono::steady_clock;
    const auto wall0 = clock::now();
    const auto elapsed = [&] {
        return std::chrono::duration<double>(clock::now() - wall0).count();
    };
    const Motion motion = oscillation_motion(o);
    const double omega = oscillation_omega(o);
    const double period = 2.0 * std::numbers::pi / omega;
    UnsteadySettings settings;
    settings.dt = period / o.steps_per_period;
    settings.conditions = o.conditions;
    // A source that cannot move throws here, before anything is written.
    const std::unique_ptr<UnsteadyRun> run = source.start_unsteady(motion, settings);

    ForcedOscillationResult r;
    r.options = o;
    r.omega = omega;
    const std::string fp = o.checkpoint.empty() ? std::string() : run_fingerprint(source, o);
    if (!o.checkpoint.empty() && std::filesystem::exists(o.checkpoint))
        r.resumed_from = read_checkpoint(o.checkpoint, fp, r.history, *run);
    else
        r.history.push_back(run->current());
    r.history.reserve(static_cast<std::size_t>(run->n_steps()) + 1);
    auto last_checkpoint = clock::now();
    const auto checkpoint = [&] {
        write_checkpoint(o.checkpoint, fp, r.history, *run);
        last_checkpoint = clock::now();
    };
    // The start can be a long steady solution: kept at once.
    if (!o.checkpoint.empty() && r.resumed_from < 0) checkpoint();

    const int first = run->current().index;
    const double end_time = motion.t.back();
    while (!run->finished()) {
        r.history.push_back(run->step());
        ++r.steps_computed;
        const bool done = run->finished();
        bool written = false;
        if (!o.checkpoint.empty() &&
            (done || std::chrono::duration<double>(clock::now() - last_checkpoint).count() >=
                         o.checkpoint_seconds)) {
            checkpoint();
            written = true;
        }
        if (progress) {
            ForcedOscillationProgress p;
            p.step = run->current().index;
            p.n_steps = run->n_steps();
            p.t = run->current().t;
            p.end_time = end_time;
            p.sample = &run->current();
            p.resumed_from = r.resumed_from;
            p.wall_s = elapsed();
            const int here = p.step - first;
            if (here > 0) p.seconds_left = p.wall_s / here * (p.n_steps - p.step);
            p.checkpoint_written = written;
            progress(p);
        }
    }
    r.coefficients = analyse_forced_oscillation(r.history, o);
    r.wall_s = elapsed();
    return r;
}

}  // namespace manta::aero
