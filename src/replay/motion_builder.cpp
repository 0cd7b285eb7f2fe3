/// @file motion_builder.cpp
/// Motion file of a replay from a trajectory (motion_builder.hpp, docs/replay.md).

#include "manta/replay/motion_builder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "manta/core/error.hpp"
#include "manta/core/frames.hpp"
#include "manta/replay/input_checks.hpp"

namespace manta::replay {

using Eigen::Matrix3d;
using Eigen::Vector3d;

namespace {

constexpr double pi = std::numbers::pi;

/// `a` shifted by a multiple of 2 pi to lie nearest `ref`.
double nearest(double a, double ref) {
    return a + 2.0 * pi * std::round((ref - a) / (2.0 * pi));
}

/// Of the two equivalent triples of `e`, each angle shifted by 2 pi k, the one nearest `prev`.
std::array<double, 3> nearest_triple(const std::array<double, 3>& e,
                                     const std::array<double, 3>& prev) {
    const std::array<std::array<double, 3>, 2> cand{
        std::array<double, 3>{e[0], e[1], e[2]},
        std::array<double, 3>{e[0] + pi, pi - e[1], e[2] + pi}};
    std::array<double, 3> best{};
    double best_d = std::numeric_limits<double>::infinity();
    for (const auto& c : cand) {
        std::array<double, 3> s{};
        double d = 0.0;
        for (std::size_t k = 0; k < 3; ++k) {
            s[k] = nearest(c[k], prev[k]);
            d += (s[k] - prev[k]) * (s[k] - prev[k]);
        }
        if (d < best_d) {
            best_d = d;
            best = s;
        }
    }
    return best;
}

Vector3d air_velocity_earth(const aero::MotionState& s) {
    // modes: elevator aileron rudder V alpha beta mach
    const Vector3d uvw = core::air_velocity_body(s.modes[3], s.modes[4], s.modes[5]);
    return core::dcm_body_from_earth(s.euler).transpose() * uvw;
}

}  // namespace

std::array<double, 3> continuous_euler(const Matrix3d& C, const std::array<double, 3>* previous) {
    std::array<double, 3> e = core::euler_from_dcm(C);
    if (!previous) return e;
    if (std::abs(C(0, 2)) > 1.0 - 1e-12) {
        // Gimbal lock: only phi - psi (theta = +90 deg) or phi + psi (-90 deg) is defined;
        // keep phi.
        e[0] = (*previous)[0];
        e[2] = C(0, 2) < 0.0 ? e[0] - std::atan2(C(1, 0), C(1, 1))
                             : std::atan2(-C(1, 0), C(1, 1)) - e[0];
    }
    return nearest_triple(e, *previous);
}

aero::Motion trajectory_interpolant(const Trajectory& tr) {
    aero::Motion m;
    m.t = tr.t;
    m.position = tr.position;
    const std::size_t n = tr.size();
    for (auto& a : m.angles) a.resize(n);
    std::array<double, 3> prev{};
    for (std::size_t i = 0; i < n; ++i) {
        std::array<double, 3> e{tr.euler[0][i], tr.euler[1][i], tr.euler[2][i]};
        if (i > 0) e = nearest_triple(e, prev);
        for (std::size_t k = 0; k < 3; ++k) m.angles[k][i] = e[k];
        prev = e;
    }
    m.add_mode("elevator", tr.controls[0]);
    m.add_mode("aileron", tr.controls[1]);
    m.add_mode("rudder", tr.controls[2]);
    // The motion proper (attitude, position, control deflections) is checked against the
    // motion's plausible ranges; the flight-state channels below (V in m/s, the air angles,
    // Mach, body rates) ride along as further columns and are not control deflections.
    m.validate(tr.source);
    m.add_mode("V", tr.V);
    m.add_mode("alpha", tr.alpha);
    m.add_mode("beta", tr.beta);
    m.add_mode("mach", trajectory_mach(tr));
    m.add_mode("p", tr.rates[0]);
    m.add_mode("q", tr.rates[1]);
    m.add_mode("r", tr.rates[2]);
    return m;
}

Trajectory first_seconds(const Trajectory& tr, double duration) {
    if (!(duration >= 1e-6 && std::isfinite(duration)))
        throw InputError(
            fmt::format("{}: replay of the first {} s; expected a duration of at least 1e-6 s",
                        tr.source, duration));
    const double t_cut = tr.t.front() + duration;
    constexpr double slack = 1e-9;
    if (t_cut >= tr.t.back() - slack) return tr;
    // Rows kept as they are: those before the cut (and one within the slack of it).
    const auto first_after = static_cast<std::size_t>(
        std::upper_bound(tr.t.begin(), tr.t.end(), t_cut - slack) - tr.t.begin());
    Trajectory cut = tr;
    const bool on_row = std::abs(tr.t[first_after] - t_cut) <= slack;
    const std::size_t kept = on_row ? first_after + 1 : first_after;
    auto shrink = [kept](auto& v) {
        if (!v.empty()) v.resize(kept);
    };
    shrink(cut.t);
    for (auto* group : {&cut.position, &cut.euler, &cut.rates, &cut.controls})
        for (auto& v : *group) shrink(v);
    shrink(cut.V);
    shrink(cut.alpha);
    shrink(cut.beta);
    shrink(cut.throttle);
    shrink(cut.mach);
    shrink(cut.phase);
    shrink(cut.line);
    if (on_row) return cut;

    // The last row at t_cut, from the interpolant (modes: elevator aileron rudder V alpha beta
    // mach p q r).
    const aero::MotionState s = trajectory_interpolant(tr).at(t_cut);
    const std::size_t b = kept - 1;  // the row before the cut (kept >= 1: t_cut > t0)
    cut.t.push_back(t_cut);
    for (std::size_t k = 0; k < 3; ++k) cut.position[k].push_back(s.position[k]);
    std::array<double, 3> e = core::euler_from_dcm(core::dcm_body_from_earth(s.euler));
    e[0] = nearest(e[0], tr.euler[0][b]);
    e[2] = nearest(e[2], tr.euler[2][b]);
    for (std::size_t k = 0; k < 3; ++k) cut.euler[k].push_back(e[k]);
    for (std::size_t k = 0; k < 3; ++k) cut.controls[k].push_back(s.modes[k]);
    cut.V.push_back(s.modes[3]);
    cut.alpha.push_back(s.modes[4]);
    cut.beta.push_back(s.modes[5]);
    if (!tr.mach.empty()) cut.mach.push_back(s.modes[6]);
    for (std::size_t k = 0; k < 3; ++k) cut.rates[k].push_back(s.modes[7 + k]);
    if (!tr.throttle.empty()) {
        const double f = (t_cut - tr.t[b]) / (tr.t[b + 1] - tr.t[b]);
        cut.throttle.push_back(tr.throttle[b] + f * (tr.throttle[b + 1] - tr.throttle[b]));
    }
    if (!tr.phase.empty()) cut.phase.push_back(tr.phase[b]);
    cut.line.push_back(tr.line[b]);
    return cut;
}

TimeStepChoice choose_time_step(const Trajectory& tr, const TimeStepRule& rule, double chord) {
    TimeStepChoice c;
    constexpr double inf = std::numeric_limits<double>::infinity();
    double w = 0.0;
    for (std::size_t i = 0; i < tr.size(); ++i)
        w = std::max(w, std::hypot(tr.rates[0][i], tr.rates[1][i], tr.rates[2][i]));
    c.rate_scale = w > 0.0 ? 1.0 / w : inf;
    c.control_scale = inf;
    for (const auto& d : tr.controls) {
        const auto [lo, hi] = std::minmax_element(d.begin(), d.end());
        double rate = 0.0;
        for (std::size_t i = 1; i < d.size(); ++i)
            rate = std::max(rate, std::abs(d[i] - d[i - 1]) / (tr.t[i] - tr.t[i - 1]));
        if (*hi - *lo > 1e-6 && rate > 0.0)
            c.control_scale = std::min(c.control_scale, (*hi - *lo) / rate);
    }
    const double scale = std::min(c.rate_scale, c.control_scale);
    const double raw = rule.fraction * scale;
    double upper = rule.max_dt;
    std::string upper_why = fmt::format("upper bound {} s", rule.max_dt);
    if (chord > 0.0) {
        const double v = *std::max_element(tr.V.begin(), tr.V.end());
        const double convective = rule.max_chords * chord / v;
        if (convective < upper) {
            upper = convective;
            upper_why = fmt::format("convective bound {:.4g} s ({} reference chords at {:.4g} m/s)",
                                    convective, rule.max_chords, v);
        }
    }
    if (raw > upper) {
        c.dt = upper;
        c.reason = fmt::format("{}; {} x the shortest time scale, {:.3g} s, is longer", upper_why,
                               rule.fraction, scale);
    } else if (raw < rule.min_dt) {
        c.dt = rule.min_dt;
        c.reason = fmt::format("lower bound {} s ({} x the shortest time scale is {:.3g} s)",
                               rule.min_dt, rule.fraction, raw);
    } else {
        c.dt = raw;
        c.reason =
            fmt::format("{} x the {} time scale {:.3g} s", rule.fraction,
                        c.rate_scale <= c.control_scale ? "body-rate" : "control-motion", scale);
    }
    return c;
}

ReplayMotion build_motion(const Trajectory& tr, double h) {
    if (!(h > 0.0 && std::isfinite(h)))
        throw InputError(fmt::format("replay: motion sample step {} s; expected > 0", h));
    const aero::Motion I = trajectory_interpolant(tr);
    ReplayMotion rm;
    rm.sample_dt = h;
    const double t0 = tr.t.front(), tN = tr.t.back();
    const auto n = static_cast<std::size_t>(std::max(1.0, std::ceil((tN - t0) / h - 1e-6)));
    std::vector<double> times(n + 1);
    for (std::size_t k = 0; k < n; ++k) times[k] = t0 + static_cast<double>(k) * h;
    times[n] = tN;

    const aero::MotionState s0 = I.at(t0);
    const Vector3d va0 = air_velocity_earth(s0);
    rm.v0 = tr.V.front();
    rm.mach0 = s0.modes[6];
    rm.altitude0 = -tr.position[2].front();
    rm.entry_position = Vector3d(tr.position[0][0], tr.position[1][0], tr.position[2][0]);
    rm.chi0 = std::atan2(va0.y(), va0.x());
    rm.gamma0 = std::asin(std::clamp(-va0.z() / va0.norm(), -1.0, 1.0));
    // The 3-2-1 rotation by the track angle about z, then the flight-path angle about y.
    rm.earth_to_motion = core::dcm_body_from_earth(0.0, rm.gamma0, rm.chi0);
    const Matrix3d& Cme = rm.earth_to_motion;
    const Vector3d ex = rm.v0 * Vector3d::UnitX();
    auto rel_velocity = [&](double t) { return Vector3d(Cme * air_velocity_earth(I.at(t)) - ex); };

    aero::Motion& m = rm.motion;
    m.t = times;
    for (auto& c : m.position) c.assign(n + 1, 0.0);
    for (auto& c : m.angles) c.assign(n + 1, 0.0);
    std::array<std::vector<double>, 3> modes;
    for (auto& c : modes) c.assign(n + 1, 0.0);
    Vector3d r = Vector3d::Zero();
    Vector3d f_prev = rel_velocity(times[0]);
    std::array<double, 3> prev{};
    for (std::size_t k = 0; k <= n; ++k) {
        const double t = times[k];
        if (k > 0) {
            const double d = t - times[k - 1];
            const Vector3d fm = rel_velocity(times[k - 1] + 0.5 * d);
            const Vector3d f = rel_velocity(t);
            r += d / 6.0 * (f_prev + 4.0 * fm + f);
            f_prev = f;
        }
        const aero::MotionState s = I.at(t);
        const Matrix3d Cbm = core::dcm_body_from_earth(s.euler) * Cme.transpose();
        const std::array<double, 3> e = continuous_euler(Cbm, k > 0 ? &prev : nullptr);
        prev = e;
        for (std::size_t j = 0; j < 3; ++j) {
            m.position[j][k] = r[static_cast<Eigen::Index>(j)];
            m.angles[j][k] = e[j];
            modes[j][k] = s.modes[j];
        }
    }
    m.add_mode("elevator", std::move(modes[0]));
    m.add_mode("aileron", std::move(modes[1]));
    m.add_mode("rudder", std::move(modes[2]));
    m.metadata.v0 = rm.v0;
    m.metadata.mach = rm.mach0;
    m.metadata.altitude = rm.altitude0;
    m.metadata.comments.push_back(fmt::format("replay motion of {}", tr.source));
    m.metadata.comments.push_back(fmt::format(
        "motion frame: earth axes turned by track {} rad, flight path {} rad; entry "
        "position {} {} {} m",
        rm.chi0, rm.gamma0, rm.entry_position.x(), rm.entry_position.y(), rm.entry_position.z()));
    m.validate("replay motion");
    return rm;
}

AirState motion_air_state(const aero::Motion& motion, double v0, double t) {
    const aero::MotionState s = motion.at(t);
    const Vector3d uvw = core::dcm_body_from_earth(s.euler) *
                         Vector3d(v0 + s.velocity[0], s.velocity[1], s.velocity[2]);
    AirState a;
    a.airspeed = uvw.norm();
    a.alpha = std::atan2(uvw.z(), uvw.x());
    a.beta = a.airspeed > 0.0 ? std::asin(std::clamp(uvw.y() / a.airspeed, -1.0, 1.0)) : 0.0;
    return a;
}

EarthPose earth_pose(const ReplayMotion& rm, double t) {
    const aero::MotionState s = rm.motion.at(t);
    EarthPose p;
    const Vector3d local(rm.v0 * (t - rm.motion.t.front()) + s.position[0], s.position[1],
                         s.position[2]);
    p.position = rm.entry_position + rm.earth_to_motion.transpose() * local;
    p.euler = continuous_euler(core::dcm_body_from_earth(s.euler) * rm.earth_to_motion, nullptr);
    return p;
}

}  // namespace manta::replay
