/// @file simulate.cpp
/// Control inputs, saturation, and the drivers of `simulate` and `simulate_ensemble` (RK4 in
/// lock-step over one or more cases, Dormand-Prince 5(4) for one); see simulate.hpp.

#include "manta/flightdyn/simulate.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <boost/numeric/odeint.hpp>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <optional>

#include "manta/core/config.hpp"
#include "manta/core/error.hpp"
#include "manta/core/units.hpp"
#include "manta/core/utf8.hpp"
#include "manta/core/version.hpp"

namespace manta::flightdyn {

// ------------------------------------------------------------------------------- names

std::string_view to_string(StateForm v) {
    return v == StateForm::euler ? "euler" : "quaternion";
}
std::string_view to_string(Integrator v) {
    return v == Integrator::rk4 ? "rk4" : "dopri5";
}
std::string_view to_string(EndReason v) {
    switch (v) {
        case EndReason::completed:
            return "completed";
        case EndReason::ground:
            return "ground";
        case EndReason::left_atmosphere:
            return "left_atmosphere";
        case EndReason::numerical_error:
            return "numerical_error";
    }
    return "?";
}
std::string_view to_string(Channel c) {
    static constexpr std::array<std::string_view, n_channels> names = {"elevator", "aileron",
                                                                       "rudder", "throttle"};
    return names[static_cast<std::size_t>(c)];
}

namespace {

[[noreturn]] void bad_choice(std::string_view what, std::string_view text,
                             const std::vector<std::string>& choices) {
    const std::string guess = core::closest_match(text, choices);
    throw InputError(
        fmt::format("{} '{}' is not known{}; valid choices: {}", what, text,
                    guess.empty() ? std::string() : fmt::format(" (did you mean '{}'?)", guess),
                    fmt::join(choices, ", ")));
}

}  // namespace

StateForm parse_state_form(std::string_view text) {
    if (text == "euler") return StateForm::euler;
    if (text == "quaternion") return StateForm::quaternion;
    bad_choice("state form", text, {"euler", "quaternion"});
}

Integrator parse_integrator(std::string_view text) {
    if (text == "rk4") return Integrator::rk4;
    if (text == "dopri5") return Integrator::dopri5;
    bad_choice("integrator", text, {"rk4", "dopri5"});
}

// ------------------------------------------------------------------------------- inputs

namespace {

double& channel_ref(Controls<double>& u, int c) {
    switch (c) {
        case 0:
            return u.elevator;
        case 1:
            return u.aileron;
        case 2:
            return u.rudder;
        default:
            return u.throttle;
    }
}

const std::array<double, 2>& channel_limits(const ControlLimits& l, int c) {
    switch (c) {
        case 0:
            return l.elevator;
        case 1:
            return l.aileron;
        case 2:
            return l.rudder;
        default:
            return l.throttle;
    }
}

/// 1-based line number of the CSV header (first line neither blank nor a '#' comment).
int header_line(std::string_view text) {
    int line = 0;
    std::size_t pos = 0;
    while (pos <= text.size()) {
        const std::size_t nl = text.find('\n', pos);
        std::string_view s =
            text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
        pos = nl == std::string_view::npos ? text.size() + 1 : nl + 1;
        ++line;
        const auto first = s.find_first_not_of(" \t\r");
        if (first == std::string_view::npos || s[first] == '#') continue;
        return line;
    }
    return 1;
}

}  // namespace

InputHistory::InputHistory(const Controls<double>& initial) : initial_(initial) {}

InputHistory InputHistory::parse(std::string_view csv_text, const std::string& source,
                                 const Controls<double>& initial) {
    core::require_utf8_text(csv_text, source);
    const core::CsvTable table = core::parse_csv(csv_text, source);
    const int hl = header_line(csv_text);
    // Valid column names: per channel the radian and the degree form (throttle has no degrees).
    static const std::vector<std::string> valid = {"t",           "elevator",  "aileron",
                                                   "rudder",      "throttle",  "elevator_deg",
                                                   "aileron_deg", "rudder_deg"};
    InputHistory h(initial);
    h.source_ = source;
    std::array<int, n_channels> col{-1, -1, -1, -1};
    std::array<bool, n_channels> in_deg{false, false, false, false};
    int t_col = -1;
    for (std::size_t i = 0; i < table.columns.size(); ++i) {
        const std::string& name = table.columns[i];
        const int field = static_cast<int>(i) + 1;
        if (name == "t") {
            t_col = static_cast<int>(i);
            continue;
        }
        int c = -1;
        bool deg = false;
        for (int k = 0; k < n_channels; ++k) {
            const std::string base(to_string(static_cast<Channel>(k)));
            if (name == base) c = k;
            if (k != 3 && name == base + "_deg") {
                c = k;
                deg = true;
            }
        }
        if (c < 0) {
            const std::string guess = core::closest_match(name, valid);
            throw InputError(fmt::format(
                "{}:{}:{}: unknown column '{}'{}; valid columns: {}", source, hl, field, name,
                guess.empty() ? std::string() : fmt::format(" (did you mean '{}'?)", guess),
                fmt::join(valid, ", ")));
        }
        if (col[c] >= 0) {
            throw InputError(fmt::format(
                "{}:{}:{}: column '{}' gives the {} a second time (column '{}' already does); use "
                "either '{}' [rad] or "
                "'{}_deg' [deg], not both",
                source, hl, field, name, to_string(static_cast<Channel>(c)),
                table.columns[static_cast<std::size_t>(col[c])], to_string(static_cast<Channel>(c)),
                to_string(static_cast<Channel>(c))));
        }
        col[c] = static_cast<int>(i);
        in_deg[c] = deg;
    }
    if (t_col < 0) {
        throw InputError(fmt::format("{}:{}: missing column 't' (time [s]); columns present: {}",
                                     source, hl, fmt::join(table.columns, ", ")));
    }
    if (table.rows.empty()) {
        throw InputError(fmt::format(
            "{}: no data rows after the header (line {}); expected at least one row", source, hl));
    }
    const std::size_t n = table.rows.size();
    h.t_.resize(n);
    h.lines_ = table.row_lines;
    for (std::size_t r = 0; r < n; ++r) {
        const double t = table.rows[r][static_cast<std::size_t>(t_col)];
        if (r > 0 && !(t > h.t_[r - 1])) {
            throw InputError(fmt::format(
                "{}:{}:{}: t = {} {} the previous row's t = {} (line {}); times must increase "
                "strictly",
                source, table.row_lines[r], t_col + 1, core::format_exact(t),
                t == h.t_[r - 1] ? "duplicates" : "is less than", core::format_exact(h.t_[r - 1]),
                table.row_lines[r - 1]));
        }
        h.t_[r] = t;
    }
    for (int c = 0; c < n_channels; ++c) {
        if (col[c] < 0) continue;
        h.present_[c] = true;
        auto& v = h.values_[c];
        v.resize(n);
        const double scale = in_deg[c] ? core::deg_to_rad : 1.0;
        for (std::size_t r = 0; r < n; ++r) {
            const double raw = table.rows[r][static_cast<std::size_t>(col[c])];
            v[r] = raw * scale;
            // A hinged surface deflects less than 90 deg (issue 16): a larger value is a unit
            // slip, not a command to saturate silently.
            if (c != 3 && std::abs(v[r]) > std::numbers::pi / 2.0) {
                throw InputError(fmt::format(
                    "{}:{}:{}: column '{}' value {} is outside the plausible range of a control "
                    "deflection, {}{}",
                    source, table.row_lines[r], col[c] + 1,
                    table.columns[static_cast<std::size_t>(col[c])], core::format_exact(raw),
                    in_deg[c] ? "[-90, 90] deg" : "[-1.5708, 1.5708] rad",
                    !in_deg[c] && std::abs(raw) <= 360.0
                        ? fmt::format(" (degrees typed as radians? write the column as '{}_deg')",
                                      to_string(static_cast<Channel>(c)))
                        : std::string()));
            }
        }
    }
    return h;
}

InputHistory InputHistory::read(const std::filesystem::path& file,
                                const Controls<double>& initial) {
    return parse(core::read_file(file), file.string(), initial);
}

Controls<double> InputHistory::at(double t) const {
    Controls<double> u = initial_;
    if (t_.empty()) return u;
    const auto it = std::upper_bound(t_.begin(), t_.end(), t);
    const std::size_t i = static_cast<std::size_t>(it - t_.begin());
    for (int c = 0; c < n_channels; ++c) {
        if (!present_[c]) continue;
        const auto& v = values_[c];
        double value;
        if (i == 0) {
            value = v.front();
        } else if (i == t_.size()) {
            value = v.back();
        } else {
            const double w = (t - t_[i - 1]) / (t_[i] - t_[i - 1]);
            value = v[i - 1] + w * (v[i] - v[i - 1]);
        }
        channel_ref(u, c) = value;
    }
    return u;
}

SaturatedControls saturate(const Controls<double>& command, const ControlLimits& limits) {
    SaturatedControls s;
    s.controls = command;
    for (int c = 0; c < n_channels; ++c) {
        const auto& lim = channel_limits(limits, c);
        double& v = channel_ref(s.controls, c);
        if (v < lim[0]) {
            v = lim[0];
            s.saturated[c] = true;
        } else if (v > lim[1]) {
            v = lim[1];
            s.saturated[c] = true;
        }
    }
    return s;
}

std::int64_t SaturationReport::total() const {
    std::int64_t n = 0;
    for (int c = 0; c < n_channels; ++c) n += input_rows[c] + output_samples[c];
    return n;
}

std::string SaturationReport::summary(const ControlLimits& limits) const {
    std::string out;
    for (int c = 0; c < n_channels; ++c) {
        if (input_rows[c] == 0 && output_samples[c] == 0) continue;
        const auto& lim = channel_limits(limits, c);
        const bool angle = c != 3;
        const double k = angle ? core::rad_to_deg : 1.0;
        const char* unit = angle ? " deg" : "";
        if (!out.empty()) out += '\n';
        out += fmt::format("{}: {} input rows beyond [{:g}, {:g}]{}",
                           to_string(static_cast<Channel>(c)), input_rows[c], lim[0] * k,
                           lim[1] * k, unit);
        if (input_rows[c] > 0)
            out += fmt::format(", first at t = {:g} s ({:g}{})", first_time[c], first_value[c] * k,
                               unit);
        out += fmt::format("; {} output samples clipped", output_samples[c]);
    }
    return out;
}

// ------------------------------------------------------------------------------- options

void SimulationOptions::validate() const {
    auto positive = [](double v, const char* name, const char* unit) {
        if (!(v > 0.0 && std::isfinite(v)))
            throw InputError(fmt::format(
                "simulation option {} = {} {}; expected a finite number > 0", name, v, unit));
    };
    positive(duration, "duration", "s");
    positive(dt, "dt", "s");
    if (!(output_interval >= 0.0 && std::isfinite(output_interval)))
        throw InputError(fmt::format(
            "simulation option output_interval = {} s; expected a finite number >= 0 (0: every "
            "step)",
            output_interval));
    if (!(max_step >= 0.0 && std::isfinite(max_step)))
        throw InputError(fmt::format(
            "simulation option max_step = {} s; expected a finite number >= 0 (0: the output "
            "interval)",
            max_step));
    if (integrator == Integrator::dopri5) {
        positive(rtol, "rtol", "");
        positive(atol, "atol", "");
    }
    if (dt > duration)
        throw InputError(fmt::format("simulation option dt = {} s is longer than the duration {} s",
                                     dt, duration));
    // The step and row counts are integers: a duration of 1e308 s would overflow them.
    constexpr double max_steps = 1e12;
    if (duration / dt > max_steps)
        throw InputError(fmt::format(
            "simulation options duration = {} s and dt = {} s make {:.3g} steps; expected at "
            "most {:g} (a shorter duration or a longer step)",
            duration, dt, duration / dt, max_steps));
    if (output_interval > 0.0 && duration / output_interval > max_steps)
        throw InputError(fmt::format(
            "simulation options duration = {} s and output_interval = {} s make {:.3g} rows; "
            "expected at most {:g}",
            duration, output_interval, duration / output_interval, max_steps));
    if (!(progress_interval >= 0.0))
        throw InputError(fmt::format("simulation option progress_interval = {} s; expected >= 0",
                                     progress_interval));
}

const std::vector<std::string>& trajectory_columns() {
    static const std::vector<std::string> c = {
        "t",        "x",  "y",  "z",  "phi",      "theta",   "psi",    "V",        "alpha",
        "beta",     "p",  "q",  "r",  "elevator", "aileron", "rudder", "throttle", "mach",
        "altitude", "nz", "CL", "CD", "CY",       "Cl",      "Cm",     "Cn"};
    return c;
}

// ------------------------------------------------------------------------------- driver
//
// Three layers, shared by `simulate` and `simulate_ensemble`:
//  - Track: the book-keeping of one trajectory (output rows, saturation counts, the last finite
//    state, NaN check, end conditions with the ground crossing, metadata);
//  - Lockstep: fixed-step RK4 of one or more tracks on one time grid, each stage one batched
//    right-hand-side call (`simulate`'s RK4 is a lock-step run of one track);
//  - run_dopri5: the adaptive integrator for one track (Boost.Odeint dense output).

namespace {

namespace odeint = boost::numeric::odeint;
using Clock = std::chrono::steady_clock;

/// The two state forms behind one interface for the drivers.
template <StateForm F>
struct Form;

template <>
struct Form<StateForm::euler> {
    static constexpr std::size_t n = euler::size;
    using Vec = EulerState<double>;
    static constexpr int z = euler::z;
    static Vec from_euler(const EulerState<double>& s) { return s; }
    static EulerState<double> to_euler(const Vec& s) { return s; }
    static Vec rhs(const FlightModel& m, const Vec& s, const Controls<double>& u,
                   Loads<double>* L) {
        return euler_rhs(m, s, u, L);
    }
    static void batch(const FlightModel& m, std::span<const Vec> s,
                      std::span<const Controls<double>> u, std::span<Vec> d) {
        euler_rhs_batch(m, s, u, d);
    }
    static constexpr const char* names[n] = {"x", "y",     "z",    "phi", "theta", "psi",
                                             "V", "alpha", "beta", "p",   "q",     "r"};
};

template <>
struct Form<StateForm::quaternion> {
    static constexpr std::size_t n = quat::size;
    using Vec = QuatState<double>;
    static constexpr int z = quat::z;
    static Vec from_euler(const EulerState<double>& s) { return to_quaternion_state(s); }
    static EulerState<double> to_euler(const Vec& s) { return to_euler_state(s); }
    static Vec rhs(const FlightModel& m, const Vec& s, const Controls<double>& u,
                   Loads<double>* L) {
        return quaternion_rhs(m, s, u, L);
    }
    static void batch(const FlightModel& m, std::span<const Vec> s,
                      std::span<const Controls<double>> u, std::span<Vec> d) {
        quaternion_rhs_batch(m, s, u, d);
    }
    static constexpr const char* names[n] = {"x", "y", "z", "q0", "q1", "q2", "q3",
                                             "u", "v", "w", "p",  "q",  "r"};
};

/// Thrown by the right-hand side when a stage leaves the atmosphere model; caught by the driver.
struct LeftAtmosphere {
    double t;
    double altitude;
};

/// Geometric altitudes [m] the US 1976 model covers.
struct AltitudeRange {
    double low = geometric_from_geopotential(us1976_constants::h_bottom);
    double high = geometric_from_geopotential(us1976_constants::h_top);
    [[nodiscard]] bool contains(double h) const { return h >= low && h <= high; }
};

/// '#' lines of a trajectory file.
std::vector<std::string> make_metadata(const FlightModel& model, const InputHistory& inputs,
                                       const SimulationOptions& options, const std::string& end) {
    std::vector<std::string> md;
    md.push_back(
        "manta trajectory (docs/flight-dynamics.md#trajectory-csv); SI units, angles in rad");
    md.push_back(fmt::format("aircraft: {}",
                             options.aircraft_name.empty() ? model.name : options.aircraft_name));
    md.push_back(fmt::format("mass case: {}",
                             options.mass_case.empty() ? model.mass.name : options.mass_case));
    if (options.integrator == Integrator::rk4) {
        md.push_back("integrator: rk4 (classical Runge-Kutta, fixed step)");
        md.push_back(fmt::format("step: {} s", core::format_exact(options.dt)));
    } else {
        md.push_back(
            fmt::format("integrator: dopri5 (Dormand-Prince 5(4), adaptive; rtol {}, atol {})",
                        core::format_exact(options.rtol), core::format_exact(options.atol)));
        md.push_back(fmt::format(
            "step: initial {} s, max {} s", core::format_exact(options.dt),
            core::format_exact(
                options.max_step > 0
                    ? options.max_step
                    : (options.output_interval > 0 ? options.output_interval : options.dt))));
    }
    md.push_back(fmt::format("state form: {}", to_string(options.form)));
    md.push_back(fmt::format("inputs: {}", inputs.source().empty()
                                               ? std::string("initial controls held")
                                               : inputs.source()));
    md.push_back(fmt::format("end: {}", end));
    md.push_back(fmt::format("version: manta {}", core::version()));
    return md;
}

/// InputError, starting with `who`, when `initial` cannot start a run with `options`.
void check_initial(const EulerState<double>& initial, const SimulationOptions& options,
                   const std::string& who) {
    if (!initial.allFinite())
        throw InputError(fmt::format("{}: the initial state is not finite", who));
    const double h0 = -initial[euler::z];
    const AltitudeRange range;
    if (!range.contains(h0))
        throw InputError(fmt::format(
            "{}: initial altitude {} m is outside the US Standard Atmosphere 1976 range "
            "[{:.0f}, {:.0f}] m",
            who, h0, range.low, range.high));
    if (!std::isnan(options.ground_altitude) && h0 <= options.ground_altitude)
        throw InputError(
            fmt::format("{}: initial altitude {} m is at or below the ground altitude {} m", who,
                        h0, options.ground_altitude));
    if (options.form == StateForm::euler) {
        if (!(initial[euler::V] > 0.0))
            throw InputError(fmt::format(
                "{}: the Euler-angle form needs V > 0 (got {} m/s); use the quaternion form", who,
                initial[euler::V]));
        if (std::abs(std::cos(initial[euler::theta])) < 1e-9)
            throw InputError(fmt::format(
                "{}: the Euler-angle form is singular at theta = +-90 deg; use the quaternion "
                "form",
                who));
    }
}

/// Output interval [s]: options.output_interval (0: dt), for rk4 rounded to a multiple of dt.
double output_interval(const SimulationOptions& opt) {
    const double want = opt.output_interval > 0 ? opt.output_interval : opt.dt;
    if (opt.integrator == Integrator::rk4) return std::max(1.0, std::round(want / opt.dt)) * opt.dt;
    return want;
}

/// Position of an entry's (table, axis) in the database's counter order (tables in file order,
/// then their axes), the order AeroDatabase::out_of_range() lists them in.
std::size_t counter_rank(const aero::AeroDatabase& db, const aero::OutOfRangeEntry& e) {
    std::size_t rank = 0;
    for (const aero::Table& t : db.tables()) {
        for (const aero::GridAxis& a : t.axes) {
            if (t.name == e.table && a.axis == e.axis) return rank;
            ++rank;
        }
    }
    return rank;
}

/// Add the counts of `add` to `into`: counts summed, extremes kept, entries in the database's
/// order (so a report merged from pieces reads as one from the database).
void merge_counts(aero::OutOfRangeReport& into, const aero::OutOfRangeReport& add,
                  const aero::AeroDatabase& db) {
    into.evaluations += add.evaluations;
    for (const aero::OutOfRangeEntry& e : add.entries) {
        const auto same = [&](const aero::OutOfRangeEntry& x) {
            return x.table == e.table && x.axis == e.axis;
        };
        const auto it = std::find_if(into.entries.begin(), into.entries.end(), same);
        if (it == into.entries.end()) {
            const std::size_t rank = counter_rank(db, e);
            const auto pos = std::find_if(
                into.entries.begin(), into.entries.end(),
                [&](const aero::OutOfRangeEntry& x) { return counter_rank(db, x) > rank; });
            into.entries.insert(pos, e);
            continue;
        }
        if (e.below > 0) it->lowest = it->below > 0 ? std::min(it->lowest, e.lowest) : e.lowest;
        if (e.above > 0) it->highest = it->above > 0 ? std::max(it->highest, e.highest) : e.highest;
        it->below += e.below;
        it->above += e.above;
    }
}

/// Progress of a run of `n_cases` cases of `options.duration` each, handed to options.progress
/// at most every progress_interval wall seconds.
class ProgressMeter {
public:
    ProgressMeter(const SimulationOptions& opt, std::size_t n_cases)
        : opt_(opt), n_cases_(n_cases), start_(Clock::now()), last_(start_) {}

    /// `done`: case-seconds simulated (a case that ended counts in full); `ended`: cases ended.
    /// The clock is read every 32 calls only; `final` always reports.
    void update(double done, std::size_t ended, bool final = false) {
        if (!opt_.progress) return;
        if (!final && (++calls_ & 31U) != 0) return;
        const auto now = Clock::now();
        if (!final && std::chrono::duration<double>(now - last_).count() < opt_.progress_interval)
            return;
        last_ = now;
        SimulationProgress p;
        p.t = done;
        p.duration = opt_.duration * static_cast<double>(n_cases_);
        p.wall_elapsed = std::chrono::duration<double>(now - start_).count();
        p.wall_remaining =
            done > 0 ? p.wall_elapsed * std::max(0.0, p.duration - done) / done : 0.0;
        p.n_cases = n_cases_;
        p.cases_ended = ended;
        opt_.progress(p);
    }
    /// Wall time since construction [s].
    [[nodiscard]] double elapsed() const {
        return std::chrono::duration<double>(Clock::now() - start_).count();
    }

private:
    const SimulationOptions& opt_;
    std::size_t n_cases_;
    Clock::time_point start_, last_;
    std::uint32_t calls_ = 0;
};

/// The book-keeping of one trajectory: output rows, saturation counts, the last finite state,
/// the end conditions. Never throws for the run's own failures: a NaN/Inf records
/// EndReason::numerical_error (`simulate` turns it into on_abort + NumericalError).
template <StateForm F>
class Track {
public:
    using FT = Form<F>;
    static constexpr std::size_t N = FT::n;
    using State = std::array<double, N>;
    using Vec = typename FT::Vec;

    /// `own_counts`: the aero database's counters are attributed to this track around each
    /// piece of work (ensembles; the caller attributes the batched stages with add_counts);
    /// false: the caller resets them before the run and the result takes their totals.
    Track(const FlightModel& model, const InputHistory& inputs, const SimulationOptions& opt,
          bool own_counts)
        : m_(model), in_(inputs), opt_(opt), own_counts_(own_counts && model.aero != nullptr) {}

    /// Begin at `initial` (Euler form): columns, input rows beyond the limits; the state in the
    /// integrated form.
    State start(const EulerState<double>& initial) {
        result_.columns = trajectory_columns();
        const State x0 = to_array(FT::from_euler(initial));
        last_good_ = x0;
        for (int c = 0; c < n_channels; ++c) {
            if (!in_.has(static_cast<Channel>(c))) continue;
            const auto& lim = channel_limits(m_.limits, c);
            const auto& v = in_.samples(static_cast<Channel>(c));
            for (std::size_t r = 0; r < v.size(); ++r) {
                if (v[r] >= lim[0] && v[r] <= lim[1]) continue;
                if (result_.saturation.input_rows[c]++ == 0) {
                    result_.saturation.first_time[c] = in_.times()[r];
                    result_.saturation.first_value[c] = v[r];
                }
            }
        }
        return x0;
    }

    static State to_array(const Vec& v) {
        State a;
        Eigen::Map<Vec>(a.data()) = v;
        return a;
    }
    static Vec to_vec(const State& a) { return Eigen::Map<const Vec>(a.data()); }
    [[nodiscard]] static double altitude(const State& x) { return -x[FT::z]; }
    [[nodiscard]] bool below_ground(const State& x) const {
        return !std::isnan(opt_.ground_altitude) && altitude(x) <= opt_.ground_altitude;
    }
    [[nodiscard]] bool in_atmosphere(const State& x) const { return range_.contains(altitude(x)); }

    /// Applied (saturated) controls at time t [s].
    [[nodiscard]] Controls<double> controls(double t) const {
        return saturate(in_.at(t), m_.limits).controls;
    }
    /// One right-hand side, counted; LeftAtmosphere when x is outside the atmosphere model.
    void rhs(const State& x, State& dxdt, double t) {
        const double h = altitude(x);
        if (!range_.contains(h)) throw LeftAtmosphere{t, h};
        ++n_rhs_;
        dxdt = to_array(FT::rhs(m_, to_vec(x), controls(t), nullptr));
    }
    /// Count right-hand sides evaluated for this track elsewhere (a batched stage).
    void count_rhs() { ++n_rhs_; }
    /// Attribute out-of-table counts measured elsewhere to this track.
    void add_counts(const aero::OutOfRangeReport& r) { merge_counts(counts_, r, *m_.aero); }
    /// Run `fn` with the database's counters attributed to this track (own_counts only).
    template <class Fn>
    void counted(Fn&& fn) {
        if (!own_counts_) {
            fn();
            return;
        }
        m_.aero->reset_out_of_range();
        try {
            fn();
        } catch (...) {
            add_counts(m_.aero->out_of_range());
            throw;
        }
        add_counts(m_.aero->out_of_range());
    }

    /// Append an output row for state x at time t.
    void emit(const State& x, double t) {
        const SaturatedControls sc = saturate(in_.at(t), m_.limits);
        for (int c = 0; c < n_channels; ++c)
            if (sc.saturated[c]) ++result_.saturation.output_samples[c];
        Loads<double> L;
        const Vec s = to_vec(x);
        counted([&] { (void)FT::rhs(m_, s, sc.controls, &L); });
        EulerState<double> e = FT::to_euler(s);
        // Keep phi and psi continuous between rows (the quaternion form returns them wrapped).
        if (result_.n_rows > 0) {
            e[euler::phi] = unwrap(e[euler::phi], prev_phi_);
            e[euler::psi] = unwrap(e[euler::psi], prev_psi_);
        }
        prev_phi_ = e[euler::phi];
        prev_psi_ = e[euler::psi];
        const FlightOutputs o = outputs(m_, L, e);
        const Controls<double>& u = sc.controls;
        const std::array<double, 26> row{t,
                                         e[euler::x],
                                         e[euler::y],
                                         e[euler::z],
                                         e[euler::phi],
                                         e[euler::theta],
                                         e[euler::psi],
                                         e[euler::V],
                                         e[euler::alpha],
                                         e[euler::beta],
                                         e[euler::p],
                                         e[euler::q],
                                         e[euler::r],
                                         u.elevator,
                                         u.aileron,
                                         u.rudder,
                                         u.throttle,
                                         o.mach,
                                         o.altitude,
                                         o.nz,
                                         o.CL,
                                         o.CD,
                                         o.CY,
                                         o.Cl,
                                         o.Cm,
                                         o.Cn};
        static_assert(row.size() == 26, "trajectory_columns() has 26 columns");
        if (opt_.row_sink)
            opt_.row_sink(row);
        else
            result_.rows.emplace_back(row.begin(), row.end());
        ++result_.n_rows;
        result_.final_state = e;
        result_.final_controls = u;
        result_.final_time = t;
    }

    /// An accepted step ending at (x, t).
    void accept(const State& x, double t) {
        ++result_.steps;
        last_good_ = x;
        last_good_t_ = t;
    }

    /// True if x is finite; otherwise the run fails here (numerical_error, naming the time and
    /// the last finite state) and false.
    bool check_finite(const State& x, double t) {
        bool ok = true;
        for (double v : x) ok = ok && std::isfinite(v);
        if (ok) return true;
        std::string hint;
        if constexpr (F == StateForm::euler) {
            if (std::abs(std::cos(last_good_[euler::theta])) < 1e-3)
                hint =
                    "; the Euler-angle form is singular at theta = +-90 deg: use the quaternion "
                    "form";
            else if (std::abs(last_good_[euler::V]) < 1e-3)
                hint = "; the Euler-angle form is singular at V = 0: use the quaternion form";
        }
        fail(fmt::format("simulate: the state became non-finite (NaN/Inf) at t = {:.6g} s after "
                         "{} steps: {}; last finite state at t = {:.6g} s: {}{}",
                         t, result_.steps, describe(x), last_good_t_, describe(last_good_), hint),
             fmt::format("non-finite state at t = {:g} s", t));
        return false;
    }
    /// The run failed: `message` is the NumericalError text, `what` its short form for the
    /// trajectory's `# end:` line.
    void fail(std::string message, std::string what) {
        end(EndReason::numerical_error, std::move(message));
        abort_what_ = std::move(what);
    }
    void end(EndReason reason, std::string message) {
        result_.end_reason = reason;
        result_.end_message = std::move(message);
    }
    /// The step from (x, t0) left the atmosphere model: the run ends at x, the last state inside.
    void left_during_step(const LeftAtmosphere& e, const State& x, double t0) {
        end(EndReason::left_atmosphere,
            fmt::format("altitude {:.1f} m left the US Standard Atmosphere 1976 range [{:.0f}, "
                        "{:.0f}] m near t = {:.4g} s; stopped at the last state inside, t = "
                        "{:.6g} s",
                        e.altitude, range_.low, range_.high, e.t, last_good_t_));
        if (result_.final_time != t0) emit(x, t0);
    }

    /// After a fixed step from (x, t0) to (x1, t1): the NaN check, the atmosphere, the ground
    /// (the crossing located by regula falsi, Illinois variant, on the step length; `step(h, out)`
    /// redoes the step from (x, t0) with length h), then the step is accepted and, if `row`, a
    /// row written. False when the run ended here.
    template <class Step>
    bool finish_step(const State& x, double t0, const State& x1, double t1, bool row, Step&& step) {
        if (!check_finite(x1, t1)) return false;
        if (!range_.contains(altitude(x1))) {
            left_during_step({t1, altitude(x1)}, x, t0);
            return false;
        }
        if (below_ground(x1)) {
            const double g0 = opt_.ground_altitude;
            double a = 0.0, fa = altitude(x) - g0, b = t1 - t0, fb = altitude(x1) - g0;
            State xc = x1;
            double tc = b;
            try {
                counted([&] {
                    for (int it = 0; it < 60 && fb != 0.0; ++it) {
                        tc = b - fb * (b - a) / (fb - fa);
                        step(tc, xc);
                        const double fc = altitude(xc) - g0;
                        if (std::abs(fc) < 1e-9 || std::abs(b - a) < 1e-12) break;
                        if (fc * fb < 0) {
                            a = b;
                            fa = fb;
                        } else {
                            fa *= 0.5;
                        }
                        b = tc;
                        fb = fc;
                    }
                });
            } catch (const LeftAtmosphere& e) {
                left_during_step(e, x, t0);
                return false;
            }
            accept(xc, t0 + tc);
            emit(xc, t0 + tc);
            end(EndReason::ground,
                fmt::format("reached the ground (altitude {:g} m) at t = {:.6g} s", g0, t0 + tc));
            return false;
        }
        accept(x1, t1);
        if (row) emit(x1, t1);
        return true;
    }

    /// The state vector as "x = .., y = .., ..." for messages.
    [[nodiscard]] std::string describe(const State& x) const {
        std::string s;
        for (std::size_t i = 0; i < N; ++i)
            s += fmt::format("{}{} = {:.10g}", i ? ", " : "", FT::names[i], x[i]);
        return s;
    }

    [[nodiscard]] const State& last_good() const { return last_good_; }
    [[nodiscard]] double last_good_time() const { return last_good_t_; }
    [[nodiscard]] double final_time() const { return result_.final_time; }
    [[nodiscard]] bool failed() const { return result_.end_reason == EndReason::numerical_error; }

    /// The result: right-hand-side count, wall time, out-of-table counts, metadata.
    SimulationResult finish(double wall_seconds) {
        result_.rhs_evaluations = n_rhs_;
        result_.wall_seconds = wall_seconds;
        if (m_.aero) result_.out_of_range = own_counts_ ? counts_ : m_.aero->out_of_range();
        const std::string end_line =
            failed() ? fmt::format("aborted ({})", abort_what_)
                     : fmt::format("{} ({})", to_string(result_.end_reason), result_.end_message);
        result_.metadata = make_metadata(m_, in_, opt_, end_line);
        return std::move(result_);
    }

private:
    static double unwrap(double a, double prev) {
        constexpr double two_pi = 2.0 * core::pi;
        return a - two_pi * std::round((a - prev) / two_pi);
    }

    const FlightModel& m_;
    const InputHistory& in_;
    const SimulationOptions& opt_;
    bool own_counts_;
    AltitudeRange range_;
    SimulationResult result_;
    aero::OutOfRangeReport counts_;
    std::string abort_what_;
    State last_good_{};
    double last_good_t_ = 0.0;
    double prev_phi_ = 0.0, prev_psi_ = 0.0;
    std::int64_t n_rhs_ = 0;
};

/// x + a_dt k: an RK4 stage state, as Boost.Odeint's runge_kutta4 forms it (its zero tableau
/// entries add exact zeros).
template <std::size_t N>
void rk4_stage(const std::array<double, N>& x, double a_dt, const std::array<double, N>& k,
               std::array<double, N>& out) {
    for (std::size_t i = 0; i < N; ++i) out[i] = x[i] + a_dt * k[i];
}

/// The RK4 update x + dt (k1/6 + k2/3 + k3/3 + k4/6), with Boost.Odeint's runge_kutta4
/// coefficients and order of operations.
template <std::size_t N>
void rk4_update(const std::array<double, N>& x, double dt, const std::array<double, N>& k1,
                const std::array<double, N>& k2, const std::array<double, N>& k3,
                const std::array<double, N>& k4, std::array<double, N>& out) {
    const double b1 = (1.0 / 6.0) * dt, b2 = (1.0 / 3.0) * dt;
    for (std::size_t i = 0; i < N; ++i)
        out[i] = x[i] + b1 * k1[i] + b2 * k2[i] + b2 * k3[i] + b1 * k4[i];
}

/// Classical RK4 (Butcher tableau c = 0, 1/2, 1/2, 1; a = 1/2; 0, 1/2; 0, 0, 1;
/// b = 1/6, 1/3, 1/3, 1/6) of one or more tracks advancing together: the same steps of dt
/// from 0 (the last shortened to land on the duration) and the same output grid for all, each
/// stage evaluating the running tracks' derivatives in one batched call. A track that ends drops
/// out; the others go on.
template <StateForm F>
class Lockstep {
public:
    using Tr = Track<F>;
    using State = typename Tr::State;
    using Vec = typename Tr::Vec;

    /// `attribute`: attribute the aero database's counters to the tracks per stage (the tracks
    /// were made with own_counts).
    Lockstep(const FlightModel& model, const SimulationOptions& opt, std::span<Tr> tracks,
             ProgressMeter& meter, bool attribute)
        : m_(model),
          opt_(opt),
          tracks_(tracks),
          meter_(meter),
          attribute_(attribute && model.aero != nullptr),
          solo_(tracks.size(), 0),
          wall_end_(tracks.size(), 0.0) {}

    /// Integrate track i from x0[i]; each track's end is recorded in it.
    void run(const std::vector<State>& x0) {
        const std::size_t n = tracks_.size();
        const double dt = opt_.dt, T = opt_.duration;
        const auto every = static_cast<std::int64_t>(std::llround(output_interval(opt_) / dt));
        // Steps of dt from 0; the last one shortened to land on T exactly.
        const auto n_steps = static_cast<std::int64_t>(std::ceil(T / dt - 1e-9));
        std::vector<State> x = x0, xt(n), x1(n), k1(n), k2(n), k3(n), k4(n);
        std::vector<std::size_t> active(n);  // running tracks; during a step, those still in it
        std::vector<std::pair<std::size_t, LeftAtmosphere>> left;
        for (std::size_t i = 0; i < n; ++i) {
            active[i] = i;
            tracks_[i].emit(x[i], 0.0);
        }
        std::size_t n_ended = 0;
        for (std::int64_t s = 0; s < n_steps && !active.empty(); ++s) {
            const double t0 = static_cast<double>(s) * dt;
            const double t1 = s + 1 == n_steps ? T : static_cast<double>(s + 1) * dt;
            const double h = t1 - t0;
            left.clear();
            evaluate(t0, active, x, k1, left);
            for (const std::size_t i : active) rk4_stage(x[i], 0.5 * h, k1[i], xt[i]);
            evaluate(t0 + 0.5 * h, active, xt, k2, left);
            for (const std::size_t i : active) rk4_stage(x[i], 0.5 * h, k2[i], xt[i]);
            evaluate(t0 + 0.5 * h, active, xt, k3, left);
            for (const std::size_t i : active) rk4_stage(x[i], h, k3[i], xt[i]);
            evaluate(t0 + h, active, xt, k4, left);
            for (const std::size_t i : active)
                rk4_update(x[i], h, k1[i], k2[i], k3[i], k4[i], x1[i]);

            const bool row = (s + 1) % every == 0 || s + 1 == n_steps;
            for (const auto& [i, e] : left) {
                tracks_[i].left_during_step(e, x[i], t0);
                ended(i, n_ended);
            }
            std::size_t kept = 0;
            for (const std::size_t i : active) {
                const auto step = [&](double hc, State& out) { step_one(i, x[i], t0, hc, out); };
                if (tracks_[i].finish_step(x[i], t0, x1[i], t1, row, step)) {
                    x[i] = x1[i];
                    active[kept++] = i;
                } else {
                    ended(i, n_ended);
                }
            }
            if (kept != active.size()) active.resize(kept);
            meter_.update(
                static_cast<double>(n_ended) * T + static_cast<double>(active.size()) * t1,
                n_ended);
        }
        for (const std::size_t i : active) {
            tracks_[i].end(EndReason::completed, fmt::format("completed {:g} s", T));
            ended(i, n_ended);
        }
    }

    /// Wall time [s] at which track i ended.
    [[nodiscard]] double wall_end(std::size_t i) const { return wall_end_[i]; }

private:
    void ended(std::size_t i, std::size_t& n_ended) {
        wall_end_[i] = meter_.elapsed();
        ++n_ended;
    }

    /// One RK4 step of track i alone from (x, t0) with length h (the ground crossing), with the
    /// arithmetic of the lock-step stages.
    void step_one(std::size_t i, const State& x, double t0, double h, State& out) {
        Tr& tr = tracks_[i];
        State a, b, c, d, xt;
        tr.rhs(x, a, t0);
        rk4_stage(x, 0.5 * h, a, xt);
        tr.rhs(xt, b, t0 + 0.5 * h);
        rk4_stage(x, 0.5 * h, b, xt);
        tr.rhs(xt, c, t0 + 0.5 * h);
        rk4_stage(x, h, c, xt);
        tr.rhs(xt, d, t0 + h);
        rk4_update(x, h, a, b, c, d, out);
    }

    /// Derivatives at time t of the tracks `ids` at states xs[i], into ks[i]. A track whose
    /// stage state is outside the atmosphere model leaves `ids` and is listed in `left`.
    void evaluate(double t, std::vector<std::size_t>& ids, const std::vector<State>& xs,
                  std::vector<State>& ks,
                  std::vector<std::pair<std::size_t, LeftAtmosphere>>& left) {
        std::size_t kept = 0;
        for (const std::size_t i : ids) {
            if (tracks_[i].in_atmosphere(xs[i])) {
                tracks_[i].count_rhs();
                ids[kept++] = i;
            } else {
                left.emplace_back(i, LeftAtmosphere{t, Tr::altitude(xs[i])});
            }
        }
        if (kept != ids.size()) ids.resize(kept);
        if (!attribute_) {
            batch(t, ids, xs, ks);
            return;
        }
        // Out-of-table counts per track: one batched call while no query leaves the tables,
        // then each evaluation counts once; a track whose last evaluation left them goes alone
        // until one does not.
        together_.clear();
        for (const std::size_t i : ids) {
            if (solo_[i])
                alone(t, i, xs, ks);
            else
                together_.push_back(i);
        }
        if (together_.empty()) return;
        m_.aero->reset_out_of_range();
        batch(t, together_, xs, ks);
        const aero::OutOfRangeReport r = m_.aero->out_of_range();
        if (r.entries.empty() && r.evaluations == together_.size()) {
            aero::OutOfRangeReport one;
            one.evaluations = 1;
            for (const std::size_t i : together_) tracks_[i].add_counts(one);
            return;
        }
        // Whose query was it? Evaluate these again one at a time (equal to rounding).
        for (const std::size_t i : together_) alone(t, i, xs, ks);
    }

    /// The batched right-hand side of tracks `ids` (one track: the one-state right-hand side,
    /// equal to the batch's to rounding, without the batch's set-up).
    void batch(double t, std::span<const std::size_t> ids, const std::vector<State>& xs,
               std::vector<State>& ks) {
        const std::size_t k = ids.size();
        if (k == 1) {
            const std::size_t i = ids[0];
            ks[i] =
                Tr::to_array(Form<F>::rhs(m_, Tr::to_vec(xs[i]), tracks_[i].controls(t), nullptr));
            return;
        }
        s_.resize(k);
        u_.resize(k);
        d_.resize(k);
        for (std::size_t j = 0; j < k; ++j) {
            s_[j] = Tr::to_vec(xs[ids[j]]);
            u_[j] = tracks_[ids[j]].controls(t);
        }
        Form<F>::batch(m_, s_, u_, d_);
        for (std::size_t j = 0; j < k; ++j) ks[ids[j]] = Tr::to_array(d_[j]);
    }

    /// The right-hand side of track i alone, its counts attributed to it.
    void alone(double t, std::size_t i, const std::vector<State>& xs, std::vector<State>& ks) {
        Tr& tr = tracks_[i];
        m_.aero->reset_out_of_range();
        ks[i] = Tr::to_array(Form<F>::rhs(m_, Tr::to_vec(xs[i]), tr.controls(t), nullptr));
        const aero::OutOfRangeReport r = m_.aero->out_of_range();
        solo_[i] = r.entries.empty() ? 0 : 1;
        tr.add_counts(r);
    }

    const FlightModel& m_;
    const SimulationOptions& opt_;
    std::span<Tr> tracks_;
    ProgressMeter& meter_;
    bool attribute_;
    std::vector<char> solo_;
    std::vector<double> wall_end_;
    std::vector<std::size_t> together_;
    std::vector<Vec> s_, d_;
    std::vector<Controls<double>> u_;
};

/// Dormand-Prince 5(4) with dense output for one track: output rows interpolated on the fixed
/// grid, the ground crossing by bisection on the interpolant.
template <StateForm F>
void run_dopri5(Track<F>& tr, const typename Track<F>::State& x0, const SimulationOptions& opt,
                ProgressMeter& meter) {
    using State = typename Track<F>::State;
    using Stepper = odeint::runge_kutta_dopri5<State>;
    const double dt_out = output_interval(opt);
    const double max_dt = opt.max_step > 0 ? opt.max_step : dt_out;
    auto stepper = odeint::make_dense_output(opt.atol, opt.rtol, max_dt, Stepper());
    const auto sys = [&tr](const State& x, State& dxdt, double t) { tr.rhs(x, dxdt, t); };
    const double T = opt.duration;
    stepper.initialize(x0, 0.0, std::min(opt.dt, max_dt));
    tr.emit(x0, 0.0);
    std::int64_t j = 1;  // next output index
    auto out_time = [&](std::int64_t k) { return std::min(T, static_cast<double>(k) * dt_out); };
    const auto n_out = static_cast<std::int64_t>(std::ceil(T / dt_out - 1e-9));
    State xo;
    while (j <= n_out) {
        const double t_prev = stepper.current_time();
        try {
            stepper.do_step(sys);
        } catch (const LeftAtmosphere& e) {
            tr.left_during_step(e, tr.last_good(), tr.last_good_time());
            return;
        } catch (const odeint::odeint_error& e) {
            tr.fail(fmt::format("simulate: dopri5 failed at t = {:.6g} s ({}); state: {}", t_prev,
                                e.what(), tr.describe(tr.last_good())),
                    fmt::format("dopri5 failed at t = {:g} s", t_prev));
            return;
        }
        const double t1 = stepper.current_time();
        const State& x1 = stepper.current_state();
        if (!tr.check_finite(x1, t1)) return;
        if (!tr.in_atmosphere(x1)) {
            tr.left_during_step({t1, Track<F>::altitude(x1)}, tr.last_good(), tr.last_good_time());
            return;
        }
        if (tr.below_ground(x1)) {
            // Bisection on the dense-output interpolant for the ground crossing.
            double a = t_prev, b = t1;
            for (int it = 0; it < 80 && b - a > 1e-10; ++it) {
                const double c = 0.5 * (a + b);
                stepper.calc_state(c, xo);
                (tr.below_ground(xo) ? b : a) = c;
            }
            while (j <= n_out && out_time(j) < a) {
                stepper.calc_state(out_time(j), xo);
                tr.emit(xo, out_time(j));
                ++j;
            }
            stepper.calc_state(b, xo);
            tr.accept(xo, b);
            tr.emit(xo, b);
            tr.end(EndReason::ground,
                   fmt::format("reached the ground (altitude {:g} m) at t = {:.6g} s",
                               opt.ground_altitude, b));
            return;
        }
        tr.accept(x1, t1);
        meter.update(t1, 0);
        while (j <= n_out && out_time(j) <= t1) {
            stepper.calc_state(out_time(j), xo);
            tr.emit(xo, out_time(j));
            ++j;
        }
    }
    tr.end(EndReason::completed, fmt::format("completed {:g} s", T));
}

/// `simulate` in form F: a track, RK4 as a lock-step run of one, or dopri5.
template <StateForm F>
SimulationResult run_single(const FlightModel& model, const EulerState<double>& initial,
                            const InputHistory& inputs, const SimulationOptions& options) {
    ProgressMeter meter(options, 1);
    if (model.aero) model.aero->reset_out_of_range();
    std::vector<Track<F>> tracks;
    tracks.emplace_back(model, inputs, options, false);
    Track<F>& tr = tracks.front();
    const auto x0 = tr.start(initial);
    if (options.integrator == Integrator::rk4)
        Lockstep<F>(model, options, tracks, meter, false).run({x0});
    else
        run_dopri5(tr, x0, options, meter);
    const double wall = meter.elapsed();
    if (!tr.failed()) meter.update(tr.final_time(), 1, true);
    SimulationResult r = tr.finish(wall);
    if (r.end_reason == EndReason::numerical_error) {
        if (options.on_abort) options.on_abort(r);
        throw NumericalError(r.end_message);
    }
    return r;
}

/// `simulate_ensemble` with RK4 in form F: every case in lock-step.
template <StateForm F>
std::vector<SimulationResult> run_lockstep(const FlightModel& model,
                                           std::span<const EnsembleCase> cases,
                                           const SimulationOptions& options) {
    const std::size_t n = cases.size();
    ProgressMeter meter(options, n);
    const bool attribute = n > 1;
    if (model.aero) model.aero->reset_out_of_range();
    std::vector<Track<F>> tracks;
    tracks.reserve(n);
    std::vector<typename Track<F>::State> x0;
    x0.reserve(n);
    for (const EnsembleCase& c : cases) {
        tracks.emplace_back(model, c.inputs, options, attribute);
        x0.push_back(tracks.back().start(c.initial));
    }
    Lockstep<F> lockstep(model, options, tracks, meter, attribute);
    lockstep.run(x0);
    std::vector<SimulationResult> out;
    out.reserve(n);
    for (std::size_t i = 0; i < n; ++i) out.push_back(tracks[i].finish(lockstep.wall_end(i)));
    meter.update(options.duration * static_cast<double>(n), n, true);
    return out;
}

/// `simulate_ensemble` with dopri5: the cases one after another with `simulate`.
std::vector<SimulationResult> run_one_by_one(const FlightModel& model,
                                             std::span<const EnsembleCase> cases,
                                             const SimulationOptions& options) {
    const std::size_t n = cases.size();
    const double total = options.duration * static_cast<double>(n);
    const auto start = Clock::now();
    auto report = [&](double done, std::size_t ended) {
        SimulationProgress q;
        q.t = done;
        q.duration = total;
        q.wall_elapsed = std::chrono::duration<double>(Clock::now() - start).count();
        q.wall_remaining = done > 0 ? q.wall_elapsed * std::max(0.0, total - done) / done : 0.0;
        q.n_cases = n;
        q.cases_ended = ended;
        options.progress(q);
    };
    std::vector<SimulationResult> out;
    out.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        SimulationOptions o = options;
        std::optional<SimulationResult> partial;
        o.on_abort = [&partial](const SimulationResult& r) { partial = r; };
        if (options.progress) {
            const double before = options.duration * static_cast<double>(i);
            o.progress = [&report, before, i](const SimulationProgress& p) {
                report(before + p.t, i);
            };
        }
        try {
            out.push_back(simulate(model, cases[i].initial, cases[i].inputs, o));
        } catch (const NumericalError&) {
            if (!partial) throw;
            out.push_back(std::move(*partial));
        }
    }
    if (options.progress) report(total, n);
    return out;
}

}  // namespace

SimulationResult simulate(const FlightModel& model_in, const EulerState<double>& initial,
                          const InputHistory& inputs, const SimulationOptions& options) {
    options.validate();
    // A copy with the derived flags set from the tables (finalize also validates): a model whose
    // builder forgot finalize() would otherwise drop the alpha-dot/beta-dot terms silently.
    FlightModel model = model_in;
    finalize(model);
    check_initial(initial, options, "simulate");
    if (options.form == StateForm::euler)
        return run_single<StateForm::euler>(model, initial, inputs, options);
    return run_single<StateForm::quaternion>(model, initial, inputs, options);
}

std::vector<SimulationResult> simulate_ensemble(const FlightModel& model_in,
                                                std::span<const EnsembleCase> cases,
                                                const SimulationOptions& options_in) {
    options_in.validate();
    SimulationOptions options = options_in;
    options.row_sink = nullptr;  // the cases keep their rows
    FlightModel model = model_in;
    finalize(model);
    for (const EnsembleCase& c : cases)
        check_initial(c.initial, options, fmt::format("simulate_ensemble: case '{}'", c.name));
    if (cases.empty()) return {};
    if (options.integrator == Integrator::dopri5) return run_one_by_one(model, cases, options);
    if (options.form == StateForm::euler)
        return run_lockstep<StateForm::euler>(model, cases, options);
    return run_lockstep<StateForm::quaternion>(model, cases, options);
}

void write_trajectory(const std::filesystem::path& file, const SimulationResult& result) {
    core::write_file_atomic(file, core::to_csv(result.columns, result.rows, result.metadata));
}

// ------------------------------------------------------------------------------- streaming

TrajectoryWriter::TrajectoryWriter(const std::filesystem::path& file) : file_(file) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (file.has_parent_path()) fs::create_directories(file.parent_path(), ec);
    // A named temporary removed at once: the rows live in an open, nameless file.
    const std::string spool =
        fmt::format("{}.rows.tmp{}", file.string(), static_cast<long>(::getpid()));
    spool_ = ::open(spool.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (spool_ < 0)
        throw IoError(fmt::format("{}: cannot write the trajectory (spool file {}): {}",
                                  file.string(), spool, std::strerror(errno)));
    ::unlink(spool.c_str());
    buffer_.reserve(std::size_t{1} << 20);
}

TrajectoryWriter::~TrajectoryWriter() {
    if (spool_ >= 0) ::close(spool_);
}

void TrajectoryWriter::row(std::span<const double> values) {
    for (std::size_t i = 0; i < values.size(); ++i) {
        if (i) buffer_ += ',';
        buffer_ += core::format_exact(values[i]);
    }
    buffer_ += '\n';
    ++rows_;
    if (buffer_.size() >= (std::size_t{1} << 20)) flush_buffer();
}

std::function<void(std::span<const double>)> TrajectoryWriter::sink() {
    return [this](std::span<const double> values) { row(values); };
}

void TrajectoryWriter::flush_buffer() {
    const char* p = buffer_.data();
    std::size_t left = buffer_.size();
    while (left > 0) {
        const ssize_t n = ::write(spool_, p, left);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0)
            throw IoError(fmt::format("{}: cannot write the trajectory rows: {}", file_.string(),
                                      std::strerror(errno)));
        p += n;
        left -= static_cast<std::size_t>(n);
    }
    buffer_.clear();
}

void TrajectoryWriter::finish(const SimulationResult& result) {
    flush_buffer();
    core::AtomicFileWriter out(file_);
    // The text of core::to_csv: comments, header, then the rows.
    out.write(core::to_csv(result.columns, {}, result.metadata));
    if (::lseek(spool_, 0, SEEK_SET) < 0)
        throw IoError(fmt::format("{}: cannot read the trajectory rows back: {}", file_.string(),
                                  std::strerror(errno)));
    std::string chunk(std::size_t{1} << 20, '\0');
    for (;;) {
        const ssize_t n = ::read(spool_, chunk.data(), chunk.size());
        if (n < 0 && errno == EINTR) continue;
        if (n < 0)
            throw IoError(fmt::format("{}: cannot read the trajectory rows back: {}",
                                      file_.string(), std::strerror(errno)));
        if (n == 0) break;
        out.write(std::string_view(chunk.data(), static_cast<std::size_t>(n)));
    }
    out.commit();  // the spool is read to its end: rows appended later follow these
}

}  // namespace manta::flightdyn
