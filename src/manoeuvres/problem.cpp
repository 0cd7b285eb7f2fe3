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

/// Rotation body-to-earth of a unit quaternion (q0 scalar).
Eigen::Matrix3d dcm(const Eigen::Vector4d& q) {
    const double q0 = q[0], q1 = q[1], q2 = q[2], q3 = q[3];
    Eigen::Matrix3d c;
    c << q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3, 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2),
        2 * (q1 * q2 + q0 * q3), q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3, 2 * (q2 * q3 - q0 * q1),
        2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3;
    return c;
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
    auto add = [&](EventDef::Quantity q, double centre, const std::string& name, double lo,
                   double hi, double scale) {
        events_.push_back({q, centre});
        p.events.push_back({name, lo, hi, scale});
    };
    const double V0 = e[flightdyn::euler::V];
    if (spec_.speed.active()) {
        const optimal::Bounds b = resolve(spec_.speed, V0);
        add(EventDef::Quantity::speed, 0.0, "final speed", b.lower, b.upper, 10.0);
    }
    /// An angle modulo 2 pi within [lo, hi] (half-width below 90 deg): sin(a - centre) within
    /// [sin(lo - centre), sin(hi - centre)] and cos(a - centre) >= 0.
    auto add_angle = [&](const Target& t, double entry, EventDef::Quantity qs_,
                         EventDef::Quantity qc, const std::string& name) {
        if (!t.active()) return;
        const optimal::Bounds b = resolve(t, entry);
        const double centre = 0.5 * (b.lower + b.upper);
        const double half = 0.5 * (b.upper - b.lower);
        if (!(half < 0.5 * kPi)) {
            throw InputError(
                fmt::format("{}: final {} range is {} deg wide; expected below 180 deg",
                            spec_.file.string(), name, 2.0 * half / kDeg));
        }
        add(qs_, centre, "final " + name + " (sin)", -std::sin(half), std::sin(half), 0.1);
        add(qc, centre, "final " + name + " (cos)", 0.0, optimal::kInf, 1.0);
    };
    add_angle(spec_.heading_change, 0.0, EventDef::Quantity::heading_sin,
              EventDef::Quantity::heading_cos, "heading");
    // heading events are relative to the entry heading: shift their centres
    for (auto& ev : events_) {
        if (ev.quantity == EventDef::Quantity::heading_sin ||
            ev.quantity == EventDef::Quantity::heading_cos) {
            ev.centre += spec_.entry_heading;
        }
    }
    add_angle(spec_.bank, e[flightdyn::euler::phi], EventDef::Quantity::bank_sin,
              EventDef::Quantity::bank_cos, "bank");
    auto add_sin = [&](const Target& t, double entry, EventDef::Quantity q,
                       const std::string& name) {
        if (!t.active()) return;
        const optimal::Bounds b = resolve(t, entry);
        const double lo = std::clamp(b.lower, -0.5 * kPi, 0.5 * kPi);
        const double hi = std::clamp(b.upper, -0.5 * kPi, 0.5 * kPi);
        add(q, 0.0, "final " + name, std::sin(lo), std::sin(hi), 0.1);
    };
    add_sin(spec_.pitch, e[flightdyn::euler::theta], EventDef::Quantity::pitch_sin, "pitch");
    add_sin(spec_.flight_path_angle, spec_.entry_climb, EventDef::Quantity::gamma_sin,
            "flight-path angle");
    add_sin(spec_.sideslip, e[flightdyn::euler::beta], EventDef::Quantity::sideslip_sin,
            "sideslip");
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
            const Eigen::Vector3d vprev =
                dcm(qs[k - 1]) * Eigen::Vector3d(speed[k - 1] * std::cos(alpha0), 0.0,
                                                 speed[k - 1] * std::sin(alpha0));
            pos += 0.5 * dt * (vprev + dcm(qs[k]) * vb);
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

ManoeuvreResult fly(const ManoeuvreProblem& problem, const optimal::SolverOptions& options,
                    int nodes) {
    ManoeuvreResult r;
    const ManoeuvreSpec& spec = problem.spec();
    const int n = nodes > 0 ? nodes : spec.nodes;
    r.mesh = optimal::Mesh::uniform(spec.segments, n);
    const auto model = make_model(problem);
    optimal::Guess guess = problem.guess();
    double cpu = 0.0, wall = 0.0;
    int its = 0;
    if (spec.coarse_nodes > 0 && spec.coarse_nodes < n) {
        // continuation: the same problem on a coarse mesh, its solution as the guess
        optimal::SolverOptions coarse = options;
        coarse.resimulate = false;
        coarse.tolerance = std::max(options.tolerance, 1e-5);
        coarse.failure_csv.clear();
        const optimal::Solution c = optimal::solve(
            *model, optimal::Mesh::uniform(spec.segments, spec.coarse_nodes), guess, coarse);
        r.coarse_iterations = c.iterations;
        cpu = c.cpu_time;
        wall = c.wall_time;
        its = c.iterations;
        if (c.converged()) guess = optimal::Guess::from_solution(c);
    }
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

Trajectory trajectory(const ManoeuvreProblem& problem, const optimal::Solution& s) {
    Trajectory t;
    t.columns = {"t_s",
                 "x_m",
                 "y_m",
                 "altitude_m",
                 "q0",
                 "q1",
                 "q2",
                 "q3",
                 "u_m_s",
                 "v_m_s",
                 "w_m_s",
                 "p_deg_s",
                 "q_deg_s",
                 "r_deg_s",
                 "roll_angle_deg",
                 "bank_deg",
                 "pitch_deg",
                 "heading_deg",
                 "V_m_s",
                 "alpha_deg",
                 "beta_deg",
                 "gamma_deg",
                 "mach",
                 "load_factor",
                 "elevator_deg",
                 "aileron_deg",
                 "rudder_deg",
                 "throttle",
                 "elevator_rate_deg_s",
                 "aileron_rate_deg_s",
                 "rudder_rate_deg_s",
                 "throttle_rate_1_s",
                 "thrust_N",
                 "CX",
                 "CY",
                 "CZ",
                 "CL",
                 "CD",
                 "Cl",
                 "Cm",
                 "Cn"};
    const auto& m = problem.model();
    double heading_prev = 0.0, heading_unwrapped = 0.0;
    bool first = true;
    for (std::size_t k = 0; k < s.segments.size(); ++k) {
        const auto& seg = s.segments[k];
        for (Eigen::Index i = (k == 0 ? 0 : 1); i < seg.time.size(); ++i) {
            const Eigen::VectorXd x = seg.states.row(i).transpose();
            const Eigen::VectorXd u = seg.controls.row(i).transpose();
            flightdyn::QuatState<double> qs;
            for (int j = 0; j < Q::size; ++j) qs[j] = x[j];
            const flightdyn::Controls<double> c{x[state::elevator], x[state::aileron],
                                                x[state::rudder], x[state::throttle]};
            flightdyn::Loads<double> L;
            (void)flightdyn::quaternion_rhs(m, qs, c, &L);
            const flightdyn::EulerState<double> es = flightdyn::to_euler_state(qs);
            const flightdyn::FlightOutputs o = flightdyn::outputs(m, L, es);
            namespace E = flightdyn::euler;
            const double psi = es[E::psi];
            if (first) {
                heading_unwrapped = psi;
                first = false;
            } else {
                heading_unwrapped += wrap(psi - heading_prev);
            }
            heading_prev = psi;
            const double nz = -L.force_body.z() / (m.mass.mass * m.environment.gravity);
            t.rows.push_back({seg.time[i],
                              x[Q::x],
                              x[Q::y],
                              -x[Q::z],
                              x[Q::q0],
                              x[Q::q1],
                              x[Q::q2],
                              x[Q::q3],
                              x[Q::u],
                              x[Q::v],
                              x[Q::w],
                              x[Q::p] / kDeg,
                              x[Q::q] / kDeg,
                              x[Q::r] / kDeg,
                              x[state::roll] / kDeg,
                              es[E::phi] / kDeg,
                              es[E::theta] / kDeg,
                              heading_unwrapped / kDeg,
                              L.airspeed,
                              L.alpha / kDeg,
                              L.beta / kDeg,
                              o.flight_path_angle / kDeg,
                              L.mach,
                              nz,
                              c.elevator / kDeg,
                              c.aileron / kDeg,
                              c.rudder / kDeg,
                              c.throttle,
                              u[0] / kDeg,
                              u[1] / kDeg,
                              u[2] / kDeg,
                              u[3],
                              L.thrust,
                              L.coefficients.CX,
                              L.coefficients.CY,
                              L.coefficients.CZ,
                              o.CL,
                              o.CD,
                              o.Cl,
                              o.Cm,
                              o.Cn});
        }
    }
    return t;
}

void write_trajectory_csv(const Trajectory& t, const std::filesystem::path& file) {
    std::ostringstream f;
    for (std::size_t i = 0; i < t.columns.size(); ++i) f << (i ? "," : "") << t.columns[i];
    f << '\n';
    for (const auto& r : t.rows) {
        for (std::size_t i = 0; i < r.size(); ++i)
            f << (i ? "," : "") << fmt::format("{:.10g}", r[i]);
        f << '\n';
    }
    core::write_file_atomic(file, f.str());
}

ConstraintCheck check(const ManoeuvreProblem& problem, const Trajectory& t) {
    ConstraintCheck c;
    const auto alpha = t.column("alpha_deg");
    const auto nz = t.column("load_factor");
    c.alpha_max_deg = *std::max_element(alpha.begin(), alpha.end());
    c.load_factor_max = *std::max_element(nz.begin(), nz.end());
    c.load_factor_min = *std::min_element(nz.begin(), nz.end());
    const auto& lim = problem.model().limits;
    const std::array<std::pair<std::string, std::array<double, 2>>, 4> ctl{
        {{"elevator_deg", lim.elevator},
         {"aileron_deg", lim.aileron},
         {"rudder_deg", lim.rudder},
         {"throttle", lim.throttle}}};
    for (const auto& [name, range] : ctl) {
        const double f = name == "throttle" ? 1.0 : kDeg;
        for (double v : t.column(name)) {
            c.control_limit_excess =
                std::max({c.control_limit_excess, range[0] - v * f, v * f - range[1]});
        }
    }
    const auto heading = t.column("heading_deg");
    c.final_heading_change_deg = wrap((heading.back() - heading.front()) * kDeg) / kDeg;
    c.final_bank_deg = t.column("bank_deg").back();
    c.final_speed = t.column("V_m_s").back();
    c.final_altitude = t.column("altitude_m").back();
    return c;
}

}  // namespace manta::manoeuvres
