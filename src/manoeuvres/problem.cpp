/// @file problem.cpp
/// Bounds, entry trim, final conditions, initial guess, solution and trajectory output of a
/// manoeuvre problem (problem.hpp, docs/manoeuvres.md).

#include "manta/manoeuvres/problem.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <numbers>
#include <sstream>

#include "manta/core/error.hpp"
#include "manta/core/frames.hpp"
#include "manta/core/io.hpp"
#include "manta/flightdyn/trim.hpp"
#include "manta/optimal/model.hpp"

namespace manta::manoeuvres {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
namespace Q = flightdyn::quat;

/// Bounds of a target on a quantity with entry value `entry`.
optimal::Bounds resolve(const Target& t, double entry) {
    if (t.kind == Target::Kind::entry) return {entry + t.lower, entry + t.upper};
    return {t.lower, t.upper};
}

/// Angle wrapped to (-pi, pi].
double wrap(double a) {
    a = std::remainder(a, 2.0 * kPi);
    return a <= -kPi ? a + 2.0 * kPi : a;
}

Eigen::Vector4d quat_mul(const Eigen::Vector4d& a, const Eigen::Vector4d& b) {
    return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
            a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
            a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
            a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}

}  // namespace

flightdyn::FlightModel manoeuvre_model(const aircraft::AircraftDefinition& aircraft,
                                       const ManoeuvreSpec& spec,
                                       std::shared_ptr<const aero::AeroDatabase> tables) {
    flightdyn::FlightModel m = aircraft.flight_model(spec.mass_case);
    if (tables) m.aero = std::move(tables);
    m.interpolation = aero::Interpolation::c1;
    if (spec.mass) m.mass.mass = *spec.mass;
    if (spec.cg_mac_fraction) {
        const auto& surfaces = aircraft.geometry.surfaces;
        const auto it = std::find_if(surfaces.begin(), surfaces.end(),
                                     [](const auto& s) { return s.name == "wing"; });
        if (it == surfaces.end()) {
            throw InputError(fmt::format(
                "{}: mass.cg_mac_fraction needs a lifting surface named 'wing' in aircraft '{}'",
                spec.file.string(), aircraft.name));
        }
        m.mass.cg_geom.x() =
            it->mac_leading_edge().x() + *spec.cg_mac_fraction * aircraft.reference.chord;
    }
    flightdyn::finalize(m);
    return m;
}

ManoeuvreProblem::ManoeuvreProblem(flightdyn::FlightModel model, ManoeuvreSpec spec)
    : model_(std::move(model)), spec_(std::move(spec)) {
    flightdyn::validate(model_);
    // ---- entry state ----
    flightdyn::EulerState<double> e;
    flightdyn::Controls<double> c;
    if (spec_.entry_trimmed) {
        flightdyn::TrimTarget target;
        target.airspeed = spec_.entry_speed;
        target.altitude = spec_.entry_altitude;
        target.climb_angle = spec_.entry_climb;
        target.heading = spec_.entry_heading;
        const flightdyn::TrimResult tr = flightdyn::trim(model_, target);
        e = tr.state;
        c = tr.controls;
    } else {
        namespace E = flightdyn::euler;
        e.setZero();
        e[E::z] = -spec_.entry_altitude;
        e[E::V] = spec_.entry_speed;
        e[E::alpha] = spec_.entry_alpha;
        e[E::beta] = spec_.entry_beta;
        e[E::phi] = spec_.entry_bank;
        e[E::theta] = spec_.entry_pitch;
        e[E::psi] = spec_.entry_heading;
        e[E::p] = spec_.entry_p;
        e[E::q] = spec_.entry_q;
        e[E::r] = spec_.entry_r;
        c = {spec_.entry_controls[0], spec_.entry_controls[1], spec_.entry_controls[2],
             spec_.entry_controls[3]};
    }
    const flightdyn::QuatState<double> qs = flightdyn::to_quaternion_state(e);
    x0_ = Eigen::VectorXd::Zero(state::size);
    for (int i = 0; i < Q::size; ++i) x0_[i] = qs[i];
    u0_ = Eigen::Vector4d(c.elevator, c.aileron, c.rudder, c.throttle);
    x0_.tail<4>() = u0_;

    // ---- variables ----
    optimal::ProblemInfo& p = info_;
    p.name = spec_.name;
    const double vmax = spec_.speed_range[1];
    const double hlo = spec_.altitude_range[0], hhi = spec_.altitude_range[1];
    p.states = {{"x_m", -1e5, 1e5, 1000.0},
                {"y_m", -1e5, 1e5, 1000.0},
                {"z_m", -hhi, -hlo, 1000.0},
                {"q0", -1.05, 1.05, 1.0},
                {"q1", -1.05, 1.05, 1.0},
                {"q2", -1.05, 1.05, 1.0},
                {"q3", -1.05, 1.05, 1.0},
                {"u_m_s", spec_.speed_range[0] * 0.5, vmax, 100.0},
                {"v_m_s", -0.5 * vmax, 0.5 * vmax, 10.0},
                {"w_m_s", -0.5 * vmax, 0.5 * vmax, 10.0},
                {"p_rad_s", -spec_.body_rate_max[0], spec_.body_rate_max[0], 1.0},
                {"q_rad_s", -spec_.body_rate_max[1], spec_.body_rate_max[1], 1.0},
                {"r_rad_s", -spec_.body_rate_max[2], spec_.body_rate_max[2], 1.0},
                {"roll_rad", -30.0, 30.0, 1.0}};
    // a one-way roll (path.roll_direction): the body roll rate keeps its sign at every node
    if (spec_.roll_direction < 0) p.states[Q::p].upper = 0.0;
    if (spec_.roll_direction > 0) p.states[Q::p].lower = 0.0;
    if (spec_.roll_direction != 0 &&
        !(x0_[Q::p] >= p.states[Q::p].lower && x0_[Q::p] <= p.states[Q::p].upper)) {
        throw InputError(fmt::format(
            "{}: path.roll_direction {}: the entry roll rate p is {} deg/s; expected {} 0",
            spec_.file.string(), spec_.roll_direction < 0 ? "left" : "right", x0_[Q::p] / kDeg,
            spec_.roll_direction < 0 ? "at most" : "at least"));
    }
    const double elo = spec_.east_range[0], ehi = spec_.east_range[1];
    p.states[Q::y] = {"y_m", elo, ehi, 1000.0};
    const auto& lim = model_.limits;
    const double tlo = std::max(lim.throttle[0], spec_.throttle[0]);
    const double thi = std::min(lim.throttle[1], spec_.throttle[1]);
    if (!(tlo <= thi)) {
        throw InputError(
            fmt::format("{}: path.throttle [{}, {}] does not overlap the aircraft's "
                        "throttle range [{}, {}]",
                        spec_.file.string(), spec_.throttle[0], spec_.throttle[1], lim.throttle[0],
                        lim.throttle[1]));
    }
    p.states.push_back({"elevator_rad", lim.elevator[0], lim.elevator[1], 0.1});
    p.states.push_back({"aileron_rad", lim.aileron[0], lim.aileron[1], 0.1});
    p.states.push_back({"rudder_rad", lim.rudder[0], lim.rudder[1], 0.1});
    p.states.push_back({"throttle", tlo, thi, 1.0});
    if (!(u0_[3] >= tlo && u0_[3] <= thi)) {
        throw InputError(fmt::format("{}: entry throttle {} outside path.throttle [{}, {}]",
                                     spec_.file.string(), u0_[3], tlo, thi));
    }
    const double sr = spec_.control_rate, tr = spec_.throttle_rate;
    p.controls = {{"elevator_rate_rad_s", -sr, sr, sr},
                  {"aileron_rate_rad_s", -sr, sr, sr},
                  {"rudder_rate_rad_s", -sr, sr, sr},
                  {"throttle_rate_1_s", -tr, tr, tr}};
    rate_inverse_ = {1.0 / sr, 1.0 / sr, 1.0 / sr, 1.0 / tr};
    p.path = {{"alpha", spec_.alpha[0], spec_.alpha[1], 0.1},
              {"beta", spec_.beta[0], spec_.beta[1], 0.1},
              {"load_factor", spec_.load_factor[0], spec_.load_factor[1], 1.0}};
    if (spec_.mach_max > 0.0) p.path.push_back({"mach", 0.0, spec_.mach_max, 0.1});
    if (spec_.speed_path) {
        p.path.push_back({"speed", spec_.speed_range[0], spec_.speed_range[1], 100.0});
    }
    if (spec_.bank_range) {
        p.path.push_back({"bank", (*spec_.bank_range)[0], (*spec_.bank_range)[1], 1.0});
    }
    p.initial_time = optimal::fixed(0.0);
    p.final_time = {spec_.duration[0], spec_.duration[1]};
    p.time_scale = spec_.duration_guess;
    p.objective_scale = spec_.duration_guess;
    p.initial_states.clear();
    for (int i = 0; i < state::size; ++i) p.initial_states.push_back(optimal::fixed(x0_[i]));
    for (const auto& v : p.states) p.final_states.push_back({v.lower, v.upper});

    // ---- final conditions ----
    const double h0 = spec_.entry_altitude;
    if (spec_.altitude.active()) {
        const optimal::Bounds b = resolve(spec_.altitude, h0);
        p.final_states[Q::z] = {-b.upper, -b.lower};
    }
    if (spec_.north_change.active()) p.final_states[Q::x] = resolve(spec_.north_change, 0.0);
    if (spec_.east_change.active()) p.final_states[Q::y] = resolve(spec_.east_change, 0.0);
    if (spec_.roll_angle.active()) p.final_states[state::roll] = resolve(spec_.roll_angle, 0.0);
    if (spec_.final_rates_zero) {
        for (int i : {int(Q::p), int(Q::q), int(Q::r)}) p.final_states[i] = optimal::fixed(0.0);
    }
    // `where` is "final" (events on x(tf)) or "intermediate" (interior events at the junction of
    // the two phases)
    if (spec_.intermediate.active()) {
        if (spec_.segments < 2) spec_.segments = 2;
        if (spec_.segments % 2 != 0) {
            throw InputError(fmt::format(
                "{}: mesh.segments {} with an intermediate condition; expected an even number "
                "(half of the segments before it, half after)",
                spec_.file.string(), spec_.segments));
        }
    }
    const int junction = spec_.segments / 2;
    auto add = [&](const std::string& where, EventDef::Quantity q, double centre,
                   const std::string& name, double lo, double hi, double scale) {
        if (where == "final") {
            events_.push_back({q, centre});
            p.events.push_back({where + " " + name, lo, hi, scale});
        } else {
            interior_events_.push_back({q, centre});
            p.interior_events.push_back({{where + " " + name, lo, hi, scale}, junction});
        }
    };
    const double V0 = e[flightdyn::euler::V];
    auto add_speed = [&](const std::string& where, const Target& t) {
        if (!t.active()) return;
        const optimal::Bounds b = resolve(t, V0);
        add(where, EventDef::Quantity::speed, 0.0, "speed", b.lower, b.upper, 10.0);
    };
    /// An angle modulo 2 pi within [lo, hi] (half-width below 90 deg): sin(a - centre) within
    /// [sin(lo - centre), sin(hi - centre)] and cos(a - centre) >= 0.
    auto add_angle = [&](const std::string& where, const Target& t, double entry, double shift,
                         EventDef::Quantity qs_, EventDef::Quantity qc, const std::string& name) {
        if (!t.active()) return;
        const optimal::Bounds b = resolve(t, entry);
        const double centre = 0.5 * (b.lower + b.upper);
        const double half = 0.5 * (b.upper - b.lower);
        if (!(half < 0.5 * kPi)) {
            throw InputError(fmt::format("{}: {} {} range is {} deg wide; expected below 180 deg",
                                         spec_.file.string(), where, name, 2.0 * half / kDeg));
        }
        add(where, qs_, centre + shift, name + " (sin)", -std::sin(half), std::sin(half), 0.1);
        add(where, qc, centre + shift, name + " (cos)", 0.0, optimal::kInf, 1.0);
    };
    auto add_sin = [&](const std::string& where, const Target& t, double entry,
                       EventDef::Quantity q, const std::string& name) {
        if (!t.active()) return;
        const optimal::Bounds b = resolve(t, entry);
        const double lo = std::clamp(b.lower, -0.5 * kPi, 0.5 * kPi);
        const double hi = std::clamp(b.upper, -0.5 * kPi, 0.5 * kPi);
        add(where, q, 0.0, name, std::sin(lo), std::sin(hi), 0.1);
    };
    // heading targets are changes from the entry heading: their centres shift by it
    add_speed("final", spec_.speed);
    add_angle("final", spec_.heading_change, 0.0, spec_.entry_heading,
              EventDef::Quantity::heading_sin, EventDef::Quantity::heading_cos, "heading");
    add_angle("final", spec_.bank, e[flightdyn::euler::phi], 0.0, EventDef::Quantity::bank_sin,
              EventDef::Quantity::bank_cos, "bank");
    add_sin("final", spec_.pitch, e[flightdyn::euler::theta], EventDef::Quantity::pitch_sin,
            "pitch");
    add_sin("final", spec_.flight_path_angle, spec_.entry_climb, EventDef::Quantity::gamma_sin,
            "flight-path angle");
    add_sin("final", spec_.sideslip, e[flightdyn::euler::beta], EventDef::Quantity::sideslip_sin,
            "sideslip");
    if (spec_.intermediate.active()) {
        const IntermediateSpec& m = spec_.intermediate;
        const std::string w = "intermediate";
        add_speed(w, m.speed);
        if (m.altitude.active()) {
            const optimal::Bounds b = resolve(m.altitude, h0);
            add(w, EventDef::Quantity::altitude, 0.0, "altitude", b.lower, b.upper, 100.0);
        }
        add_angle(w, m.heading_change, 0.0, spec_.entry_heading, EventDef::Quantity::heading_sin,
                  EventDef::Quantity::heading_cos, "heading");
        add_angle(w, m.bank, e[flightdyn::euler::phi], 0.0, EventDef::Quantity::bank_sin,
                  EventDef::Quantity::bank_cos, "bank");
        add_sin(w, m.pitch, e[flightdyn::euler::theta], EventDef::Quantity::pitch_sin, "pitch");
        add_sin(w, m.flight_path_angle, spec_.entry_climb, EventDef::Quantity::gamma_sin,
                "flight-path angle");
    }
    p.validate();
}

optimal::Guess ManoeuvreProblem::guess() const {
    std::vector<GuessWaypoint> w = spec_.guess;
    const Eigen::Vector3d eul0 = flightdyn::euler_from_quaternion(x0_.segment<4>(Q::q0));
    const double V0 = x0_.segment<3>(Q::u).norm();
    if (w.empty() || w.front().fraction > 0.0) {
        w.insert(w.begin(), GuessWaypoint{0.0, eul0[0], eul0[1], 0.0, V0});
    }
    if (w.back().fraction < 1.0) {
        GuessWaypoint last = w.back();
        last.fraction = 1.0;
        w.push_back(last);
    }
    std::vector<Eigen::Vector4d> wq;
    for (const auto& p : w) {
        Eigen::Vector4d q =
            flightdyn::quaternion_from_euler(p.bank, p.pitch, p.heading + spec_.entry_heading);
        if (!wq.empty() && q.dot(wq.back()) < 0.0) q = -q;
        wq.push_back(q);
    }
    if (wq.front().dot(x0_.segment<4>(Q::q0)) < 0.0) {
        for (auto& q : wq) q = -q;
    }
    const double alpha0 = std::atan2(x0_[Q::w], x0_[Q::u]);
    const double T = spec_.duration_guess;
    const int n = 401;
    std::vector<double> time(n);
    std::vector<Eigen::Vector4d> qs(n);
    std::vector<double> speed(n);
    for (int k = 0; k < n; ++k) {
        const double f = static_cast<double>(k) / (n - 1);
        time[k] = f * T;
        std::size_t j = 0;
        while (j + 2 < w.size() && f > w[j + 1].fraction) ++j;
        const double s =
            std::clamp((f - w[j].fraction) / (w[j + 1].fraction - w[j].fraction), 0.0, 1.0);
        // smoothstep between waypoints: zero attitude rate at each waypoint
        const double sm = s * s * (3.0 - 2.0 * s);
        qs[k] = ((1.0 - sm) * wq[j] + sm * wq[j + 1]).normalized();
        const double va = w[j].speed > 0.0 ? w[j].speed : V0;
        const double vb = w[j + 1].speed > 0.0 ? w[j + 1].speed : V0;
        speed[k] = (1.0 - s) * va + s * vb;
    }
    Eigen::MatrixXd X(n, state::size);
    Eigen::MatrixXd U(n, 4);  // control rates
    Eigen::Vector3d pos = x0_.segment<3>(Q::x);
    double roll = 0.0;
    for (int k = 0; k < n; ++k) {
        const int a = std::max(k - 1, 0), b = std::min(k + 1, n - 1);
        const Eigen::Vector4d qdot = (qs[b] - qs[a]) / (time[b] - time[a]);
        const Eigen::Vector4d conj(qs[k][0], -qs[k][1], -qs[k][2], -qs[k][3]);
        const Eigen::Vector4d om = 2.0 * quat_mul(conj, qdot);
        const Eigen::Vector3d vb(speed[k] * std::cos(alpha0), 0.0, speed[k] * std::sin(alpha0));
        if (k > 0) {
            const double dt = time[k] - time[k - 1];
            const Eigen::Vector3d vprev = core::dcm_earth_from_unit_quaternion(qs[k - 1]) *
                                          Eigen::Vector3d(speed[k - 1] * std::cos(alpha0), 0.0,
                                                          speed[k - 1] * std::sin(alpha0));
            pos += 0.5 * dt * (vprev + core::dcm_earth_from_unit_quaternion(qs[k]) * vb);
            roll += 0.5 * dt * (om[1] + X(k - 1, Q::p));
        }
        X.row(k).segment<3>(Q::x) = pos;
        X.row(k).segment<4>(Q::q0) = qs[k];
        X.row(k).segment<3>(Q::u) = vb;
        X.row(k).segment<3>(Q::p) = om.tail<3>();
        X(k, state::roll) = roll;
        X.row(k).tail<4>() = u0_;
        U.row(k).setZero();
    }
    X.row(0) = x0_;
    return optimal::Guess::from_history(std::move(time), std::move(X), std::move(U));
}

std::unique_ptr<optimal::Model> make_model(const ManoeuvreProblem& problem) {
    return optimal::make_model(problem);
}

namespace {

/// The mesh of a manoeuvre: `segments` segments of `nodes` points; with an intermediate
/// condition the breaks are free, the junction of the phases starting at `junction_fraction`
/// and the other breaks spread evenly within each phase.
optimal::Mesh manoeuvre_mesh(const ManoeuvreSpec& spec, int nodes, double junction_fraction) {
    optimal::Mesh m = optimal::Mesh::uniform(spec.segments, nodes);
    if (!spec.intermediate.active()) return m;
    const int half = spec.segments / 2;
    for (int k = 0; k <= spec.segments; ++k) {
        m.breaks[static_cast<std::size_t>(k)] =
            k <= half ? junction_fraction * k / half
                      : junction_fraction + (1.0 - junction_fraction) * (k - half) / half;
    }
    m.free_breaks = true;
    if (spec.tie_breaks) m.phase_breaks = {half};
    m.min_segment_fraction = std::min(0.02, 0.5 / spec.segments);
    return m;
}

}  // namespace

ManoeuvreResult fly(const ManoeuvreProblem& problem, const optimal::SolverOptions& options,
                    int nodes) {
    ManoeuvreResult r;
    const ManoeuvreSpec& spec = problem.spec();
    const int n = nodes > 0 ? nodes : spec.nodes;
    double junction = spec.intermediate.fraction;
    const auto model = make_model(problem);
    optimal::Guess guess = problem.guess();
    double cpu = 0.0, wall = 0.0;
    int its = 0;
    if (spec.coarse_nodes > 0 && spec.coarse_nodes < n) {
        // continuation: the same problem on a coarse mesh, its solution as the guess; a one-way
        // roll (path.roll_direction) is left out there: on 10 points per segment the sign
        // bound on p stalls IPOPT from the waypoint guess, the full mesh then imposes it
        std::unique_ptr<ManoeuvreProblem> two_way;
        std::unique_ptr<optimal::Model> coarse_model;
        if (spec.roll_direction != 0) {
            ManoeuvreSpec s = spec;
            s.roll_direction = 0;
            two_way = std::make_unique<ManoeuvreProblem>(problem.model(), std::move(s));
            coarse_model = make_model(*two_way);
        }
        optimal::SolverOptions coarse = options;
        coarse.resimulate = false;
        coarse.tolerance = std::max(options.tolerance, 1e-5);
        coarse.failure_csv.clear();
        const optimal::Solution c =
            optimal::solve(coarse_model ? *coarse_model : *model,
                           manoeuvre_mesh(spec, spec.coarse_nodes, junction), guess, coarse);
        r.coarse_iterations = c.iterations;
        cpu = c.cpu_time;
        wall = c.wall_time;
        its = c.iterations;
        if (c.converged()) {
            guess = optimal::Guess::from_solution(c);
            if (spec.intermediate.active()) {
                const double t0 = c.initial_time, tf = c.final_time;
                junction = (c.breaks[static_cast<std::size_t>(spec.segments / 2)] - t0) / (tf - t0);
            }
        }
    }
    r.mesh = manoeuvre_mesh(spec, n, junction);
    r.solution = optimal::solve(*model, r.mesh, guess, options);
    r.solution.cpu_time += cpu;
    r.solution.wall_time += wall;
    r.solution.iterations += its;
    return r;
}

std::vector<double> Trajectory::column(const std::string& name) const {
    const auto it = std::find(columns.begin(), columns.end(), name);
    if (it == columns.end()) throw InputError("trajectory has no column '" + name + "'");
    const auto c = static_cast<std::size_t>(it - columns.begin());
    std::vector<double> v;
    v.reserve(rows.size());
    for (const auto& r : rows) v.push_back(r[c]);
    return v;
}

std::string Trajectory::meta(const std::string& key) const {
    for (const auto& [k, v] : metadata) {
        if (k == key) return v;
    }
    return {};
}

namespace {

/// Columns of a trajectory (docs/manoeuvres.md#trajectory-csv): the required ones of the
/// shared trajectory format first, in order, then the derived ones.
const std::vector<std::string>& trajectory_columns() {
    static const std::vector<std::string> c{"t",
                                            "x",
                                            "y",
                                            "z",
                                            "phi",
                                            "theta",
                                            "psi",
                                            "V",
                                            "alpha",
                                            "beta",
                                            "p",
                                            "q",
                                            "r",
                                            "elevator",
                                            "aileron",
                                            "rudder",
                                            "throttle",
                                            "phase",
                                            "mach",
                                            "altitude",
                                            "nz",
                                            "u",
                                            "v",
                                            "w",
                                            "q0",
                                            "q1",
                                            "q2",
                                            "q3",
                                            "elevator_rate",
                                            "aileron_rate",
                                            "rudder_rate",
                                            "throttle_rate",
                                            "thrust",
                                            "CL",
                                            "CD",
                                            "CY",
                                            "Cl",
                                            "Cm",
                                            "Cn",
                                            "CX",
                                            "CZ",
                                            "gamma",
                                            "roll_angle"};
    return c;
}

/// Builds rows of a trajectory from states and controls, unwrapping psi along the way.
class RowBuilder {
public:
    explicit RowBuilder(const ManoeuvreProblem& problem) : problem_(problem) {}

    std::vector<double> row(double t, int phase, const Eigen::VectorXd& x,
                            const Eigen::VectorXd& u) {
        const auto& m = problem_.model();
        flightdyn::QuatState<double> qs;
        for (int j = 0; j < Q::size; ++j) qs[j] = x[j];
        const flightdyn::Controls<double> c{x[state::elevator], x[state::aileron], x[state::rudder],
                                            x[state::throttle]};
        flightdyn::Loads<double> L;
        (void)flightdyn::quaternion_rhs(m, qs, c, &L);
        const flightdyn::EulerState<double> es = flightdyn::to_euler_state(qs);
        const flightdyn::FlightOutputs o = flightdyn::outputs(m, L, es);
        namespace E = flightdyn::euler;
        const double psi = es[E::psi];
        psi_ = first_ ? psi : psi_ + wrap(psi - psi_prev_);
        first_ = false;
        psi_prev_ = psi;
        const double nz = -L.force_body.z() / (m.mass.mass * m.environment.gravity);
        return {t,
                x[Q::x],
                x[Q::y],
                x[Q::z],
                es[E::phi],
                es[E::theta],
                psi_,
                L.airspeed,
                L.alpha,
                L.beta,
                x[Q::p],
                x[Q::q],
                x[Q::r],
                c.elevator,
                c.aileron,
                c.rudder,
                c.throttle,
                static_cast<double>(phase),
                L.mach,
                -x[Q::z],
                nz,
                x[Q::u],
                x[Q::v],
                x[Q::w],
                x[Q::q0],
                x[Q::q1],
                x[Q::q2],
                x[Q::q3],
                u[0],
                u[1],
                u[2],
                u[3],
                L.thrust,
                o.CL,
                o.CD,
                o.CY,
                o.Cl,
                o.Cm,
                o.Cn,
                L.coefficients.CX,
                L.coefficients.CZ,
                o.flight_path_angle,
                x[state::roll]};
    }

private:
    const ManoeuvreProblem& problem_;
    bool first_ = true;
    double psi_ = 0.0;
    double psi_prev_ = 0.0;
};

/// The metadata lines of a trajectory of `problem` solved in `s`.
std::vector<std::pair<std::string, std::string>> trajectory_metadata(
    const ManoeuvreProblem& problem, const optimal::Solution& s) {
    std::string phases;
    for (const auto& p : problem.phase_names()) phases += (phases.empty() ? "" : ",") + p;
    return {{"manoeuvre", problem.spec().name},
            {"mass_case", problem.spec().mass_case.empty() ? "default" : problem.spec().mass_case},
            {"phases", phases},
            {"nodes", std::to_string(s.n_nodes())},
            {"final_time", fmt::format("{:.10g}", s.final_time)}};
}

}  // namespace

std::vector<std::string> ManoeuvreProblem::phase_names() const {
    if (spec_.intermediate.active()) return spec_.phase_names;
    return {spec_.phase_names.empty() ? std::string("manoeuvre") : spec_.phase_names.front()};
}

int ManoeuvreProblem::phase_of_segment(int segment, int n_segments) const {
    if (!spec_.intermediate.active()) return 0;
    return segment < n_segments / 2 ? 0 : 1;
}

Trajectory trajectory(const ManoeuvreProblem& problem, const optimal::Solution& s) {
    Trajectory t;
    t.columns = trajectory_columns();
    t.metadata = trajectory_metadata(problem, s);
    RowBuilder b(problem);
    const int K = static_cast<int>(s.segments.size());
    for (int k = 0; k < K; ++k) {
        const auto& seg = s.segments[static_cast<std::size_t>(k)];
        const int phase = problem.phase_of_segment(k, K);
        for (Eigen::Index i = (k == 0 ? 0 : 1); i < seg.time.size(); ++i) {
            t.rows.push_back(b.row(seg.time[i], phase, seg.states.row(i).transpose(),
                                   seg.controls.row(i).transpose()));
        }
    }
    return t;
}

Trajectory dense_trajectory(const ManoeuvreProblem& problem, const optimal::Solution& s,
                            double step) {
    if (!(step > 0.0)) {
        throw InputError(fmt::format("dense trajectory step {} s; expected a positive step", step));
    }
    Trajectory t;
    t.columns = trajectory_columns();
    t.metadata = trajectory_metadata(problem, s);
    t.metadata.emplace_back("step", fmt::format("{:.10g}", step));
    RowBuilder b(problem);
    const double t0 = s.initial_time, tf = s.final_time;
    const int K = static_cast<int>(s.segments.size());
    const auto n = static_cast<long>(std::floor((tf - t0) / step * (1.0 + 1e-12)));
    for (long i = 0; i <= n + 1; ++i) {
        double ti = t0 + static_cast<double>(i) * step;
        if (i == n + 1) {
            if (tf - (t0 + static_cast<double>(n) * step) < 1e-9 * std::max(1.0, tf)) break;
            ti = tf;  // the final time closes the samples
        }
        ti = std::min(ti, tf);
        int k = 0;
        while (k + 1 < K && ti >= s.breaks[static_cast<std::size_t>(k + 1)]) ++k;
        t.rows.push_back(b.row(ti, problem.phase_of_segment(k, K), s.state(ti), s.control(ti)));
    }
    return t;
}

void write_trajectory_csv(const Trajectory& t, const std::filesystem::path& file) {
    std::ostringstream f;
    for (const auto& [k, v] : t.metadata) f << "# " << k << ": " << v << '\n';
    for (std::size_t i = 0; i < t.columns.size(); ++i) f << (i ? "," : "") << t.columns[i];
    f << '\n';
    const auto phase = std::find(t.columns.begin(), t.columns.end(), "phase") - t.columns.begin();
    for (const auto& r : t.rows) {
        for (std::size_t i = 0; i < r.size(); ++i) {
            f << (i ? "," : "");
            if (static_cast<std::ptrdiff_t>(i) == phase) {
                f << static_cast<int>(r[i]);
            } else {
                f << fmt::format("{:.10g}", r[i]);
            }
        }
        f << '\n';
    }
    core::write_file_atomic(file, f.str());
}

ConstraintCheck check(const ManoeuvreProblem& problem, const Trajectory& t) {
    ConstraintCheck c;
    const auto alpha = t.column("alpha");
    const auto nz = t.column("nz");
    c.alpha_max_deg = *std::max_element(alpha.begin(), alpha.end()) / kDeg;
    c.load_factor_max = *std::max_element(nz.begin(), nz.end());
    c.load_factor_min = *std::min_element(nz.begin(), nz.end());
    const auto mach = t.column("mach");
    c.mach_max = *std::max_element(mach.begin(), mach.end());
    const auto h = t.column("altitude");
    c.altitude_min = *std::min_element(h.begin(), h.end());
    c.altitude_max = *std::max_element(h.begin(), h.end());
    const auto& lim = problem.model().limits;
    const std::array<std::pair<std::string, std::array<double, 2>>, 4> ctl{
        {{"elevator", lim.elevator},
         {"aileron", lim.aileron},
         {"rudder", lim.rudder},
         {"throttle", lim.throttle}}};
    for (const auto& [name, range] : ctl) {
        for (double v : t.column(name)) {
            c.control_limit_excess = std::max({c.control_limit_excess, range[0] - v, v - range[1]});
        }
    }
    const auto psi = t.column("psi");
    c.final_heading_change_deg = wrap(psi.back() - psi.front()) / kDeg;
    c.final_bank_deg = wrap(t.column("phi").back()) / kDeg;
    c.final_speed = t.column("V").back();
    c.final_altitude = t.column("altitude").back();
    return c;
}

}  // namespace manta::manoeuvres
