#include "manta/flightdyn/simulate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <boost/numeric/odeint.hpp>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "manta/core/config.hpp"
#include "manta/core/error.hpp"
#include "manta/core/units.hpp"
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
        for (std::size_t r = 0; r < n; ++r)
            v[r] = table.rows[r][static_cast<std::size_t>(col[c])] * scale;
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

// ------------------------------------------------------------------------------- attitude

Eigen::Matrix3d dcm_earth_from_body(double phi, double theta, double psi) {
    const double sf = std::sin(phi), cf = std::cos(phi);
    const double st = std::sin(theta), ct = std::cos(theta);
    const double sp = std::sin(psi), cp = std::cos(psi);
    Eigen::Matrix3d c;
    c << ct * cp, sf * st * cp - cf * sp, cf * st * cp + sf * sp,  //
        ct * sp, sf * st * sp + cf * cp, cf * st * sp - sf * cp,   //
        -st, sf * ct, cf * ct;
    return c;
}

Eigen::Matrix3d dcm_earth_from_body(const Eigen::Vector4d& qin) {
    const Eigen::Vector4d q = qin / qin.norm();
    const double q0 = q[0], q1 = q[1], q2 = q[2], q3 = q[3];
    Eigen::Matrix3d c;
    c << q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3, 2 * (q1 * q2 - q0 * q3),
        2 * (q1 * q3 + q0 * q2),                                                                  //
        2 * (q1 * q2 + q0 * q3), q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3, 2 * (q2 * q3 - q0 * q1),  //
        2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3;
    return c;
}

// ------------------------------------------------------------------------------- driver

namespace {

namespace odeint = boost::numeric::odeint;
using Clock = std::chrono::steady_clock;

/// The two state forms behind one interface for the driver.
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

template <StateForm F>
class Driver {
public:
    using FT = Form<F>;
    static constexpr std::size_t N = FT::n;
    using State = std::array<double, N>;

    Driver(const FlightModel& model, const InputHistory& inputs, const SimulationOptions& opt)
        : m_(model), in_(inputs), opt_(opt) {}

    SimulationResult run(const EulerState<double>& initial);

private:
    /// Right-hand side in Odeint's signature.
    struct System {
        Driver* d;
        void operator()(const State& x, State& dxdt, double t) const {
            const double h = -x[FT::z];
            if (!d->range_.contains(h)) throw LeftAtmosphere{t, h};
            ++d->n_rhs_;
            const Controls<double> u = saturate(d->in_.at(t), d->m_.limits).controls;
            const typename FT::Vec s = Eigen::Map<const typename FT::Vec>(x.data());
            const typename FT::Vec ds = FT::rhs(d->m_, s, u, nullptr);
            Eigen::Map<typename FT::Vec>(dxdt.data()) = ds;
        }
    };

    static State to_array(const typename FT::Vec& v) {
        State a;
        Eigen::Map<typename FT::Vec>(a.data()) = v;
        return a;
    }
    static typename FT::Vec to_vec(const State& a) {
        return Eigen::Map<const typename FT::Vec>(a.data());
    }
    [[nodiscard]] double altitude(const State& x) const { return -x[FT::z]; }
    [[nodiscard]] bool below_ground(const State& x) const {
        return !std::isnan(opt_.ground_altitude) && altitude(x) <= opt_.ground_altitude;
    }

    std::string describe(const State& x) const {
        std::string s;
        for (std::size_t i = 0; i < N; ++i)
            s += fmt::format("{}{} = {:.10g}", i ? ", " : "", FT::names[i], x[i]);
        return s;
    }

    void check_finite(const State& x, double t) {
        bool ok = true;
        for (double v : x) ok = ok && std::isfinite(v);
        if (ok) return;
        std::string hint;
        if constexpr (F == StateForm::euler) {
            if (std::abs(std::cos(last_good_[euler::theta])) < 1e-3)
                hint =
                    "; the Euler-angle form is singular at theta = +-90 deg: use the quaternion "
                    "form";
            else if (std::abs(last_good_[euler::V]) < 1e-3)
                hint = "; the Euler-angle form is singular at V = 0: use the quaternion form";
        }
        result_.end_message = fmt::format("non-finite state at t = {:g} s", t);
        result_.metadata = make_metadata(m_, in_, opt_, "aborted (" + result_.end_message + ")");
        if (opt_.on_abort) opt_.on_abort(result_);
        throw NumericalError(
            fmt::format("simulate: the state became non-finite (NaN/Inf) at t = {:.6g} s after {} "
                        "steps: {}; last finite state at "
                        "t = {:.6g} s: {}{}",
                        t, result_.steps, describe(x), last_good_t_, describe(last_good_), hint));
    }

    /// Append an output row for state x at time t.
    void emit(const State& x, double t) {
        const SaturatedControls sc = saturate(in_.at(t), m_.limits);
        for (int c = 0; c < n_channels; ++c)
            if (sc.saturated[c]) ++result_.saturation.output_samples[c];
        Loads<double> L;
        const typename FT::Vec s = to_vec(x);
        (void)FT::rhs(m_, s, sc.controls, &L);
        EulerState<double> e = FT::to_euler(s);
        // Keep phi and psi continuous between rows (the quaternion form returns them wrapped).
        if (!result_.rows.empty()) {
            e[euler::phi] = unwrap(e[euler::phi], prev_phi_);
            e[euler::psi] = unwrap(e[euler::psi], prev_psi_);
        }
        prev_phi_ = e[euler::phi];
        prev_psi_ = e[euler::psi];
        const FlightOutputs o = outputs(m_, L, e);
        const Controls<double>& u = sc.controls;
        result_.rows.push_back({t,
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
                                o.Cn});
        result_.final_state = e;
        result_.final_controls = u;
        result_.final_time = t;
    }

    static double unwrap(double a, double prev) {
        constexpr double two_pi = 2.0 * core::pi;
        return a - two_pi * std::round((a - prev) / two_pi);
    }

    void accept(const State& x, double t) {
        ++result_.steps;
        last_good_ = x;
        last_good_t_ = t;
        report_progress(t, false);
    }

    void report_progress(double t, bool final) {
        if (!opt_.progress) return;
        if (!final && (result_.steps & 31) != 0) return;  // read the clock every 32 steps only
        const auto now = Clock::now();
        const double since = std::chrono::duration<double>(now - last_progress_).count();
        if (!final && since < opt_.progress_interval) return;
        last_progress_ = now;
        SimulationProgress p;
        p.t = t;
        p.duration = opt_.duration;
        p.wall_elapsed = std::chrono::duration<double>(now - start_).count();
        p.wall_remaining = t > 0 ? p.wall_elapsed * std::max(0.0, opt_.duration - t) / t : 0.0;
        opt_.progress(p);
    }

    void end(EndReason reason, std::string message) {
        result_.end_reason = reason;
        result_.end_message = std::move(message);
    }

    std::string left_message(const LeftAtmosphere& e) const {
        return fmt::format(
            "altitude {:.1f} m left the US Standard Atmosphere 1976 range [{:.0f}, {:.0f}] m near "
            "t = {:.4g} s; stopped at the last state inside, t = {:.6g} s",
            e.altitude, range_.low, range_.high, e.t, last_good_t_);
    }

    void run_rk4(const State& x0);
    void run_dopri5(const State& x0);
    [[nodiscard]] double output_interval() const;

    const FlightModel& m_;
    const InputHistory& in_;
    const SimulationOptions& opt_;
    AltitudeRange range_;
    SimulationResult result_;
    State last_good_{};
    double last_good_t_ = 0.0;
    double prev_phi_ = 0.0, prev_psi_ = 0.0;
    std::int64_t n_rhs_ = 0;
    Clock::time_point start_, last_progress_;
};

template <StateForm F>
double Driver<F>::output_interval() const {
    const double want = opt_.output_interval > 0 ? opt_.output_interval : opt_.dt;
    if (opt_.integrator == Integrator::rk4) {
        const double k = std::max(1.0, std::round(want / opt_.dt));
        return k * opt_.dt;
    }
    return want;
}

template <StateForm F>
void Driver<F>::run_rk4(const State& x0) {
    odeint::runge_kutta4<State> stepper;
    System sys{this};
    const double dt = opt_.dt, T = opt_.duration;
    const auto every = static_cast<std::int64_t>(std::llround(output_interval() / dt));
    // Steps of dt from 0; the last one shortened to land on T exactly.
    const auto n_steps = static_cast<std::int64_t>(std::ceil(T / dt - 1e-9));
    State x = x0;
    emit(x, 0.0);
    for (std::int64_t n = 0; n < n_steps; ++n) {
        const double t0 = static_cast<double>(n) * dt;
        const double t1 = n + 1 == n_steps ? T : static_cast<double>(n + 1) * dt;
        State x1;
        try {
            stepper.do_step(sys, x, t0, x1, t1 - t0);
        } catch (const LeftAtmosphere& e) {
            end(EndReason::left_atmosphere, left_message(e));
            if (result_.final_time != t0) emit(x, t0);
            return;
        }
        check_finite(x1, t1);
        if (!range_.contains(altitude(x1))) {
            end(EndReason::left_atmosphere, left_message({t1, altitude(x1)}));
            if (result_.final_time != t0) emit(x, t0);
            return;
        }
        if (below_ground(x1)) {
            // Regula falsi (Illinois variant) on the length of the step that reaches the ground.
            const double g0 = opt_.ground_altitude;
            double a = 0.0, fa = altitude(x) - g0, b = t1 - t0, fb = altitude(x1) - g0;
            State xc = x1;
            double tc = b;
            for (int it = 0; it < 60 && fb != 0.0; ++it) {
                tc = b - fb * (b - a) / (fb - fa);
                stepper.do_step(sys, x, t0, xc, tc);
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
            accept(xc, t0 + tc);
            emit(xc, t0 + tc);
            end(EndReason::ground,
                fmt::format("reached the ground (altitude {:g} m) at t = {:.6g} s", g0, t0 + tc));
            return;
        }
        x = x1;
        accept(x, t1);
        if ((n + 1) % every == 0 || n + 1 == n_steps) emit(x, t1);
    }
    end(EndReason::completed, fmt::format("completed {:g} s", T));
}

template <StateForm F>
void Driver<F>::run_dopri5(const State& x0) {
    using Stepper = odeint::runge_kutta_dopri5<State>;
    const double dt_out = output_interval();
    const double max_dt = opt_.max_step > 0 ? opt_.max_step : dt_out;
    auto stepper = odeint::make_dense_output(opt_.atol, opt_.rtol, max_dt, Stepper());
    System sys{this};
    const double T = opt_.duration;
    stepper.initialize(x0, 0.0, std::min(opt_.dt, max_dt));
    emit(x0, 0.0);
    std::int64_t j = 1;  // next output index
    auto out_time = [&](std::int64_t k) { return std::min(T, static_cast<double>(k) * dt_out); };
    const auto n_out = static_cast<std::int64_t>(std::ceil(T / dt_out - 1e-9));
    State xo;
    while (j <= n_out) {
        const double t_prev = stepper.current_time();
        try {
            stepper.do_step(sys);
        } catch (const LeftAtmosphere& e) {
            end(EndReason::left_atmosphere, left_message(e));
            if (result_.final_time != last_good_t_) emit(last_good_, last_good_t_);
            return;
        } catch (const odeint::odeint_error& e) {
            throw NumericalError(
                fmt::format("simulate: dopri5 failed at t = {:.6g} s ({}); state: {}", t_prev,
                            e.what(), describe(last_good_)));
        }
        const double t1 = stepper.current_time();
        const State& x1 = stepper.current_state();
        check_finite(x1, t1);
        if (!range_.contains(altitude(x1))) {
            end(EndReason::left_atmosphere, left_message({t1, altitude(x1)}));
            if (result_.final_time != last_good_t_) emit(last_good_, last_good_t_);
            return;
        }
        if (below_ground(x1)) {
            // Bisection on the dense-output interpolant for the ground crossing.
            double a = t_prev, b = t1;
            for (int it = 0; it < 80 && b - a > 1e-10; ++it) {
                const double c = 0.5 * (a + b);
                stepper.calc_state(c, xo);
                (below_ground(xo) ? b : a) = c;
            }
            while (j <= n_out && out_time(j) < a) {
                stepper.calc_state(out_time(j), xo);
                emit(xo, out_time(j));
                ++j;
            }
            stepper.calc_state(b, xo);
            accept(xo, b);
            emit(xo, b);
            end(EndReason::ground,
                fmt::format("reached the ground (altitude {:g} m) at t = {:.6g} s",
                            opt_.ground_altitude, b));
            return;
        }
        accept(x1, t1);
        while (j <= n_out && out_time(j) <= t1) {
            stepper.calc_state(out_time(j), xo);
            emit(xo, out_time(j));
            ++j;
        }
    }
    end(EndReason::completed, fmt::format("completed {:g} s", T));
}

template <StateForm F>
SimulationResult Driver<F>::run(const EulerState<double>& initial) {
    start_ = last_progress_ = Clock::now();
    result_.columns = trajectory_columns();
    const State x0 = to_array(FT::from_euler(initial));
    last_good_ = x0;
    if (m_.aero) m_.aero->reset_out_of_range();

    // Input rows outside the limits.
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

    if (opt_.integrator == Integrator::rk4)
        run_rk4(x0);
    else
        run_dopri5(x0);

    result_.rhs_evaluations = n_rhs_;
    result_.wall_seconds = std::chrono::duration<double>(Clock::now() - start_).count();
    report_progress(result_.final_time, true);
    if (m_.aero) result_.out_of_range = m_.aero->out_of_range();
    return std::move(result_);
}

}  // namespace

SimulationResult simulate(const FlightModel& model_in, const EulerState<double>& initial,
                          const InputHistory& inputs, const SimulationOptions& options) {
    options.validate();
    // A copy with the derived flags set from the tables (finalize also validates): a model whose
    // builder forgot finalize() would otherwise drop the alpha-dot/beta-dot terms silently.
    FlightModel model = model_in;
    finalize(model);
    if (!initial.allFinite()) throw InputError("simulate: the initial state is not finite");
    const double h0 = -initial[euler::z];
    const AltitudeRange range;
    if (!range.contains(h0))
        throw InputError(fmt::format(
            "simulate: initial altitude {} m is outside the US Standard Atmosphere 1976 range "
            "[{:.0f}, {:.0f}] m",
            h0, range.low, range.high));
    if (!std::isnan(options.ground_altitude) && h0 <= options.ground_altitude)
        throw InputError(
            fmt::format("simulate: initial altitude {} m is at or below the ground altitude {} m",
                        h0, options.ground_altitude));
    if (options.form == StateForm::euler) {
        if (!(initial[euler::V] > 0.0))
            throw InputError(fmt::format(
                "simulate: the Euler-angle form needs V > 0 (got {} m/s); use the quaternion "
                "form",
                initial[euler::V]));
        if (std::abs(std::cos(initial[euler::theta])) < 1e-9)
            throw InputError(
                "simulate: the Euler-angle form is singular at theta = +-90 deg; use the "
                "quaternion form");
    }

    SimulationResult r;
    if (options.form == StateForm::euler)
        r = Driver<StateForm::euler>(model, inputs, options).run(initial);
    else
        r = Driver<StateForm::quaternion>(model, inputs, options).run(initial);

    r.metadata = make_metadata(model, inputs, options,
                               fmt::format("{} ({})", to_string(r.end_reason), r.end_message));
    return r;
}

void write_trajectory(const std::filesystem::path& file, const SimulationResult& result) {
    core::write_file_atomic(file, core::to_csv(result.columns, result.rows, result.metadata));
}

}  // namespace manta::flightdyn
