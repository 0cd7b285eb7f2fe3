/// Trim and linearisation (trim.hpp).
///
/// The trim unknowns z = (throttle, elevator, alpha, aileron, rudder, beta) fix the whole state
/// through the constraints of Stevens, Lewis & Johnson, *Aircraft Control and Simulation*, 3rd
/// ed. 2015, sec. 3.6: bank phi from the turn-coordination constraint, pitch theta from the
/// rate-of-climb constraint, body rates from the turn rate. The residual is the time derivative
/// of (V, alpha, beta, p, q, r) from `euler_rhs`; its Jacobian comes exactly from the same code
/// run with `core::Dual`, so Newton's method converges quadratically to machine precision.

#include "manta/flightdyn/trim.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "manta/core/autodiff.hpp"
#include "manta/core/error.hpp"
#include "manta/core/units.hpp"

namespace manta::flightdyn {

namespace {

using core::Dual;

/// Trim unknowns, in the order of the Newton vector.
enum Unknown : int { u_throttle = 0, u_elevator, u_alpha, u_aileron, u_rudder, u_beta, n_unknowns };
using Vec6 = Eigen::Matrix<double, n_unknowns, 1>;
using Mat6 = Eigen::Matrix<double, n_unknowns, n_unknowns>;

/// Residual components, in the order of the Newton vector.
constexpr std::array<int, n_unknowns> residual_index = {euler::V, euler::alpha, euler::beta,
                                                        euler::p, euler::q,     euler::r};

/// State and controls that the unknowns `z` imply for the target (S&L 2015 sec. 3.6).
template <class T>
struct TrimPoint {
    EulerState<T> state;
    Controls<T> controls;
};

/// arctan for double and for first-order AD scalars (Eigen's AutoDiffScalar has no atan).
template <class T>
T arctan(const T& x) {
    if constexpr (std::is_arithmetic_v<T>) {
        return std::atan(x);
    } else {
        T r = x;
        const double v = core::value_of(x);
        r.value() = std::atan(v);
        r.derivatives() = x.derivatives() / (1.0 + v * v);
        return r;
    }
}

/// Bank angle from the turn-coordination constraint, Stevens, Lewis & Johnson (2015) eq. 3.6-5:
///   tan(phi) = G cos(beta)/cos(alpha) * ((a - b^2) + b tan(alpha) sqrt(c (1 - b^2) + G^2 sin^2
///   beta))
///              / (a^2 - b^2 (1 + c tan^2 alpha)),
/// G = psi_dot V / g, a = 1 - G tan(alpha) sin(beta), b = sin(gamma)/cos(beta), c = 1 + G^2 cos^2
/// beta.
template <class T>
T coordinated_bank(const T& alpha, const T& beta, double G, double gamma) {
    using std::cos;
    using std::sin;
    using std::sqrt;
    using std::tan;
    if (G == 0.0) return alpha * 0.0;
    const T ta = tan(alpha);
    const T sb = sin(beta), cb = cos(beta);
    const T a = 1.0 - G * ta * sb;
    const T b = std::sin(gamma) / cb;
    const T c = 1.0 + G * G * cb * cb;
    const T root = sqrt(T(c * (1.0 - b * b) + G * G * sb * sb));
    const T num = G * cb / cos(alpha) * ((a - b * b) + b * ta * root);
    const T den = a * a - b * b * (1.0 + c * ta * ta);
    return arctan(T(num / den));
}

/// Pitch angle from the rate-of-climb constraint, Stevens, Lewis & Johnson (2015) eq. 3.6-3:
///   tan(theta) = (a b + sin(gamma) sqrt(a^2 - sin^2 gamma + b^2)) / (a^2 - sin^2 gamma),
/// a = cos(alpha) cos(beta), b = sin(phi) sin(beta) + cos(phi) sin(alpha) cos(beta).
template <class T>
T climb_pitch(const T& alpha, const T& beta, const T& phi, double gamma) {
    using std::cos;
    using std::sin;
    using std::sqrt;
    const double sg = std::sin(gamma);
    const T a = cos(alpha) * cos(beta);
    const T b = sin(phi) * sin(beta) + cos(phi) * sin(alpha) * cos(beta);
    const T num = a * b + sg * sqrt(T(a * a - sg * sg + b * b));
    const T den = a * a - sg * sg;
    return arctan(T(num / den));
}

template <class T>
TrimPoint<T> trim_point(const TrimTarget& tg, double gravity, const std::array<T, n_unknowns>& z,
                        const T& zero) {
    using std::cos;
    using std::sin;
    TrimPoint<T> pt;
    const double G = tg.turn_rate * tg.airspeed / gravity;
    const T& alpha = z[u_alpha];
    const T& beta = z[u_beta];
    const T phi = coordinated_bank(alpha, beta, G, tg.climb_angle);
    const T theta = climb_pitch(alpha, beta, phi, tg.climb_angle);
    auto& s = pt.state;
    s[euler::x] = zero;
    s[euler::y] = zero;
    s[euler::z] = zero - tg.altitude;
    s[euler::phi] = phi;
    s[euler::theta] = theta;
    s[euler::psi] = zero + tg.heading;
    s[euler::V] = zero + tg.airspeed;
    s[euler::alpha] = alpha;
    s[euler::beta] = beta;
    // Body rates of a steady turn about the earth vertical: omega = psi_dot * (earth z in body).
    s[euler::p] = -tg.turn_rate * sin(theta);
    s[euler::q] = tg.turn_rate * cos(theta) * sin(phi);
    s[euler::r] = tg.turn_rate * cos(theta) * cos(phi);
    pt.controls.throttle = z[u_throttle];
    pt.controls.elevator = z[u_elevator];
    pt.controls.aileron = z[u_aileron];
    pt.controls.rudder = z[u_rudder];
    return pt;
}

TrimPoint<double> trim_point(const TrimTarget& tg, double gravity, const Vec6& z) {
    std::array<double, n_unknowns> zz{};
    for (int i = 0; i < n_unknowns; ++i) zz[static_cast<std::size_t>(i)] = z[i];
    return trim_point<double>(tg, gravity, zz, 0.0);
}

/// The six dynamic derivatives at z (SI units).
Vec6 residual(const FlightModel& m, const TrimTarget& tg, const Vec6& z) {
    const TrimPoint<double> pt = trim_point(tg, m.environment.gravity, z);
    const EulerState<double> d = euler_rhs(m, pt.state, pt.controls);
    Vec6 f;
    for (int i = 0; i < n_unknowns; ++i) f[i] = d[residual_index[static_cast<std::size_t>(i)]];
    return f;
}

/// Residual and its exact Jacobian with respect to z.
void residual_and_jacobian(const FlightModel& m, const TrimTarget& tg, const Vec6& z, Vec6& f,
                           Mat6& J) {
    std::array<Dual, n_unknowns> zz;
    for (int i = 0; i < n_unknowns; ++i)
        zz[static_cast<std::size_t>(i)] = core::make_dual(z[i], n_unknowns, i);
    const Dual zero = core::make_constant(0.0, n_unknowns);
    const TrimPoint<Dual> pt = trim_point<Dual>(tg, m.environment.gravity, zz, zero);
    const EulerState<Dual> d = euler_rhs(m, pt.state, pt.controls);
    for (int i = 0; i < n_unknowns; ++i) {
        const Dual& di = d[residual_index[static_cast<std::size_t>(i)]];
        f[i] = di.value();
        if (di.derivatives().size() == n_unknowns) {
            J.row(i) = di.derivatives().transpose();
        } else {
            J.row(i).setZero();
        }
    }
}

/// Range [lo, hi] of `axis` over the database tables that carry it (the static table first);
/// nullopt when no table has that axis.
std::optional<std::array<double, 2>> table_range(
    const aero::AeroDatabase& db, aero::Axis axis,
    std::optional<aero::TableKind> kind = std::nullopt) {
    std::optional<std::array<double, 2>> r;
    for (const auto& t : db.tables()) {
        if (kind && t.kind != *kind) continue;
        for (const auto& a : t.axes) {
            if (a.axis != axis || a.breakpoints.size() < 2) continue;
            const std::array<double, 2> ab{a.breakpoints.front(), a.breakpoints.back()};
            // Intersection: the range where every table that needs the axis has data.
            if (!r) {
                r = ab;
            } else {
                (*r)[0] = std::max((*r)[0], ab[0]);
                (*r)[1] = std::min((*r)[1], ab[1]);
            }
        }
    }
    return r;
}

/// Range of a control axis over the control tables that carry it (nullopt if none).
std::optional<std::array<double, 2>> control_range(const aero::AeroDatabase& db, aero::Axis axis) {
    return table_range(db, axis, aero::TableKind::control);
}

std::string describe_target(const TrimTarget& tg) {
    std::string s = fmt::format("V = {:g} m/s, h = {:g} m", tg.airspeed, tg.altitude);
    if (tg.climb_angle != 0.0)
        s += fmt::format(", climb angle {:g} deg", tg.climb_angle * core::rad_to_deg);
    if (tg.turn_rate != 0.0)
        s += fmt::format(", turn rate {:g} deg/s", tg.turn_rate * core::rad_to_deg);
    return s;
}

std::string angle_text(double rad) {
    return fmt::format("{:.4g} rad ({:.4g} deg)", rad, rad * core::rad_to_deg);
}

/// Problems of a converged trim with the tables and the model's limits ("" if none).
std::vector<std::string> check_trim(const FlightModel& m, const TrimTarget& tg, const Vec6& z) {
    std::vector<std::string> issues;
    const aero::AeroDatabase& db = *m.aero;
    auto check_table = [&](aero::Axis axis, const char* name, double value,
                           const std::optional<std::array<double, 2>>& range) {
        if (!range) return;
        const double tol = 1e-9 * std::max(1.0, std::abs(value));
        if (value > (*range)[1] + tol) {
            issues.push_back(fmt::format(
                "{} {} is beyond the aero table (max {})", name, angle_text(value),
                aero::is_angle(axis) ? angle_text((*range)[1]) : fmt::format("{:g}", (*range)[1])));
        } else if (value < (*range)[0] - tol) {
            issues.push_back(fmt::format(
                "{} {} is beyond the aero table (min {})", name, angle_text(value),
                aero::is_angle(axis) ? angle_text((*range)[0]) : fmt::format("{:g}", (*range)[0])));
        }
    };
    check_table(aero::Axis::alpha, "alpha", z[u_alpha], table_range(db, aero::Axis::alpha));
    check_table(aero::Axis::beta, "beta", z[u_beta], table_range(db, aero::Axis::beta));
    // Mach: compare with the tables' Mach axis.
    if (const auto mr = table_range(db, aero::Axis::mach)) {
        const double a = us1976(tg.altitude).speed_of_sound;
        const double mach = tg.airspeed / a;
        if (mach > (*mr)[1] + 1e-9 || mach < (*mr)[0] - 1e-9)
            issues.push_back(fmt::format("Mach {:.4g} is beyond the aero table ({:g} to {:g})",
                                         mach, (*mr)[0], (*mr)[1]));
    }
    auto check_limit = [&](const char* name, double value, const std::array<double, 2>& lim) {
        const double tol = 1e-9;
        if (value > lim[1] + tol) {
            issues.push_back(fmt::format("needs {} {:.4g} deg > limit {:.4g} deg", name,
                                         value * core::rad_to_deg, lim[1] * core::rad_to_deg));
        } else if (value < lim[0] - tol) {
            issues.push_back(fmt::format("needs {} {:.4g} deg < limit {:.4g} deg", name,
                                         value * core::rad_to_deg, lim[0] * core::rad_to_deg));
        }
    };
    if (z[u_throttle] > m.limits.throttle[1] + 1e-9) {
        issues.push_back(
            fmt::format("needs throttle {:.4g} > {:g}", z[u_throttle], m.limits.throttle[1]));
    } else if (z[u_throttle] < m.limits.throttle[0] - 1e-9) {
        issues.push_back(
            fmt::format("needs throttle {:.4g} < {:g}", z[u_throttle], m.limits.throttle[0]));
    }
    check_limit("elevator", z[u_elevator], m.limits.elevator);
    check_limit("aileron", z[u_aileron], m.limits.aileron);
    check_limit("rudder", z[u_rudder], m.limits.rudder);
    check_table(aero::Axis::elevator, "elevator", z[u_elevator],
                control_range(db, aero::Axis::elevator));
    check_table(aero::Axis::aileron, "aileron", z[u_aileron],
                control_range(db, aero::Axis::aileron));
    check_table(aero::Axis::rudder, "rudder", z[u_rudder], control_range(db, aero::Axis::rudder));
    return issues;
}

std::string join(const std::vector<std::string>& parts, const char* sep) {
    std::string s;
    for (std::size_t i = 0; i < parts.size(); ++i) {
        if (i) s += sep;
        s += parts[i];
    }
    return s;
}

/// Lift coefficient (wind axes) at alpha with the controls neutral and no rates.
double lift_coefficient(const FlightModel& m, double alpha, double mach) {
    aero::AeroQuery<double> q;
    q.alpha = alpha;
    q.mach = mach;
    const auto c = m.aero->evaluate(q, m.interpolation);
    return c.CX * std::sin(alpha) - c.CZ * std::cos(alpha);
}

/// Starting point: alpha from the lift needed, then elevator for zero pitching moment and
/// throttle for zero acceleration along the path, each from a secant on the model itself.
struct Guess {
    Vec6 z = Vec6::Zero();
    double CL_needed = 0.0;
    double CL_max = 0.0;  ///< largest CL found on the scanned alpha range
    double alpha_CL_max = 0.0;
    bool lift_found = true;  ///< false: no alpha in the scanned range gives CL_needed
};

Guess initial_guess(const FlightModel& m, const TrimTarget& tg) {
    Guess g;
    const auto atm = us1976(tg.altitude);
    const double qbar = 0.5 * atm.density * tg.airspeed * tg.airspeed;
    const double mach = tg.airspeed / atm.speed_of_sound;
    const double gravity = m.environment.gravity;
    const double G = tg.turn_rate * tg.airspeed / gravity;
    const double weight = m.mass.mass * gravity;
    g.CL_needed =
        weight * std::cos(tg.climb_angle) * std::sqrt(1.0 + G * G) / (qbar * m.reference.area);

    // Scan alpha upward over the table range (beyond it by half the range where the tables
    // extrapolate linearly) for the first crossing of CL_needed.
    std::array<double, 2> range{-core::deg(10.0), core::deg(30.0)};
    if (const auto r = table_range(*m.aero, aero::Axis::alpha)) range = *r;
    if (m.aero->extrapolation() == aero::Extrapolation::linear) {
        const double w = range[1] - range[0];
        range = {std::max(range[0] - 0.25 * w, -core::deg(60.0)),
                 std::min(range[1] + 0.5 * w, core::deg(80.0))};
    }
    const int n = 400;
    double a_prev = range[0];
    double cl_prev = lift_coefficient(m, a_prev, mach);
    g.CL_max = cl_prev;
    g.alpha_CL_max = a_prev;
    double alpha0 = std::numeric_limits<double>::quiet_NaN();
    for (int i = 1; i <= n; ++i) {
        const double a = range[0] + (range[1] - range[0]) * i / n;
        const double cl = lift_coefficient(m, a, mach);
        if (cl > g.CL_max) {
            g.CL_max = cl;
            g.alpha_CL_max = a;
        }
        if (std::isnan(alpha0) && cl_prev < g.CL_needed && cl >= g.CL_needed) {
            alpha0 = a_prev + (a - a_prev) * (g.CL_needed - cl_prev) / (cl - cl_prev);
        }
        a_prev = a;
        cl_prev = cl;
    }
    if (std::isnan(alpha0)) {
        g.lift_found = false;
        alpha0 = g.alpha_CL_max;
    }
    g.z[u_alpha] = alpha0;
    g.z[u_throttle] = 0.5;

    // Pitching moment about the CG and force along the flight path, at beta = 0, wings level.
    const double ca = std::cos(alpha0), sa = std::sin(alpha0);
    const Vec3<double> v_body(tg.airspeed * ca, 0.0, tg.airspeed * sa);
    const Vec3<double> w = Vec3<double>::Zero();
    auto loads = [&](double elevator, double throttle) {
        Controls<double> u;
        u.elevator = elevator;
        u.throttle = throttle;
        return compute_loads<double>(m, tg.altitude, v_body, w, u, 0.0, 0.0);
    };
    auto pitch = [&](double de, double dt) { return loads(de, dt).moment_body.y(); };
    auto along = [&](double de, double dt) {
        const auto L = loads(de, dt);
        return L.force_body.x() * ca + L.force_body.z() * sa - weight * std::sin(tg.climb_angle);
    };
    for (int pass = 0; pass < 3; ++pass) {
        const double de = g.z[u_elevator], dt = g.z[u_throttle];
        const double h = core::deg(1.0);
        const double m0 = pitch(de, dt), m1 = pitch(de + h, dt);
        if (std::abs(m1 - m0) > 0.0 && std::isfinite(m0) && std::isfinite(m1)) {
            g.z[u_elevator] =
                std::clamp(de - h * m0 / (m1 - m0), -core::deg(40.0), core::deg(40.0));
        }
        const double f0 = along(g.z[u_elevator], 0.0), f1 = along(g.z[u_elevator], 1.0);
        if (std::abs(f1 - f0) > 0.0 && std::isfinite(f0) && std::isfinite(f1)) {
            g.z[u_throttle] = std::clamp(-f0 / (f1 - f0), -0.5, 2.0);
        }
    }
    return g;
}

/// Weights that make the residual rows comparable accelerations in units of g: dV/dt / g,
/// (dalpha/dt, dbeta/dt) V / g, (dp/dt, dq/dt, dr/dt) l / g with l half the span (p, r) or
/// half the chord (q).
Vec6 residual_weights(const FlightModel& m, const TrimTarget& tg) {
    const double g = m.environment.gravity > 0.0 ? m.environment.gravity : core::standard_gravity;
    const double half_span = m.reference.span > 0.0 ? 0.5 * m.reference.span : 1.0;
    const double half_chord = m.reference.chord > 0.0 ? 0.5 * m.reference.chord : 1.0;
    Vec6 w;
    w << 1.0 / g, tg.airspeed / g, tg.airspeed / g, half_span / g, half_chord / g, half_span / g;
    return w;
}

/// `m` itself, or a copy with the derived flags of `finalize` set when the caller has not set
/// them: tables with alpha-dot or beta-dot columns need `angle_rate_terms` for the exact
/// dynamics (the trim point does not depend on it, the linear model does).
const FlightModel& finalized(const FlightModel& m, std::optional<FlightModel>& copy) {
    bool needs = false;
    if (m.aero && !m.angle_rate_terms) {
        for (const auto& t : m.aero->tables()) {
            if (t.kind != aero::TableKind::dynamic) continue;
            for (const auto& c : t.columns)
                if (c.ends_with("_alphadot") || c.ends_with("_betadot")) needs = true;
        }
    }
    if (!needs) return m;
    copy.emplace(m);
    finalize(*copy);
    return *copy;
}

void validate_target(const FlightModel& m, const TrimTarget& tg) {
    const std::string who = m.name.empty() ? "trim" : fmt::format("trim of '{}'", m.name);
    if (!(std::isfinite(tg.airspeed) && tg.airspeed > 0.0))
        throw InputError(
            fmt::format("{}: airspeed {} m/s; expected a finite number > 0", who, tg.airspeed));
    bool altitude_ok = std::isfinite(tg.altitude);
    if (altitude_ok) {
        try {
            (void)us1976(tg.altitude);
        } catch (const InputError&) {
            altitude_ok = false;
        }
    }
    if (!altitude_ok)
        throw InputError(
            fmt::format("{}: altitude {} m is outside the US Standard Atmosphere 1976 range "
                        "[-5000, 86000] m",
                        who, tg.altitude));
    if (!(std::isfinite(tg.climb_angle) && std::abs(tg.climb_angle) < core::deg(89.0)))
        throw InputError(fmt::format("{}: climb angle {} rad ({} deg); expected |gamma| < 89 deg",
                                     who, tg.climb_angle, tg.climb_angle * core::rad_to_deg));
    if (!std::isfinite(tg.turn_rate))
        throw InputError(
            fmt::format("{}: turn rate {} rad/s; expected a finite number", who, tg.turn_rate));
    if (!std::isfinite(tg.heading))
        throw InputError(
            fmt::format("{}: heading {} rad; expected a finite number", who, tg.heading));
    if (!m.aero)
        throw InputError(
            fmt::format("{}: the model has no aerodynamic database; trim needs one", who));
    if (!(m.environment.gravity > 0.0))
        throw InputError(fmt::format("{}: gravity {} m/s^2; trim needs gravity > 0", who,
                                     m.environment.gravity));
    validate(m);
}

}  // namespace

TrimResult trim(const FlightModel& model_in, const TrimTarget& target, const TrimOptions& options) {
    std::optional<FlightModel> copy;
    const FlightModel& model = finalized(model_in, copy);
    validate_target(model, target);
    if (!(options.tolerance > 0.0) || options.max_iterations < 1)
        throw InputError(
            fmt::format("trim options: tolerance {} and max_iterations {}; expected > 0 and >= 1",
                        options.tolerance, options.max_iterations));
    const std::string where = fmt::format("no trim at {}", describe_target(target));
    const Guess guess = initial_guess(model, target);
    const Vec6 w = residual_weights(model, target);

    auto merit = [&](const Vec6& z, Vec6* f_out) {
        const Vec6 f = residual(model, target, z);
        if (f_out) *f_out = f;
        if (!f.allFinite()) return std::numeric_limits<double>::infinity();
        return 0.5 * w.cwiseProduct(f).squaredNorm();
    };

    // Largest step per unknown: keeps Newton inside the region where the linearisation of the
    // tables means something (angles) and away from the Euler-angle singularities.
    Vec6 max_step;
    max_step << 1.0, core::deg(15.0), core::deg(10.0), core::deg(15.0), core::deg(15.0),
        core::deg(10.0);
    const double angle_bound = core::deg(85.0);

    Vec6 z = guess.z;
    Vec6 f;
    Mat6 J;
    int iterations = 0;
    bool converged = false;
    std::string failure;
    double scaled = std::numeric_limits<double>::infinity();
    for (; iterations <= options.max_iterations; ++iterations) {
        residual_and_jacobian(model, target, z, f, J);
        if (!f.allFinite() || !J.allFinite()) {
            failure = "the equations of motion gave a non-finite value";
            break;
        }
        scaled = w.cwiseProduct(f).cwiseAbs().maxCoeff();
        if (scaled < options.tolerance) {
            converged = true;
            break;
        }
        if (iterations == options.max_iterations) {
            failure = fmt::format("Newton's method did not converge in {} iterations",
                                  options.max_iterations);
            break;
        }
        // Newton step on the weighted system; the minimum-norm least-squares step where the
        // Jacobian is singular (e.g. a control with no effect).
        const Mat6 Jw = w.asDiagonal() * J;
        const Vec6 fw = w.cwiseProduct(f);
        Eigen::CompleteOrthogonalDecomposition<Mat6> cod(Jw);
        cod.setThreshold(1e-13);
        Vec6 dz = cod.solve(-fw);
        if (!dz.allFinite()) {
            failure = "the trim Jacobian is singular";
            break;
        }
        double shrink = 1.0;
        for (int i = 0; i < n_unknowns; ++i) {
            if (std::abs(dz[i]) > max_step[i])
                shrink = std::min(shrink, max_step[i] / std::abs(dz[i]));
        }
        dz *= shrink;
        // Backtracking (Armijo) line search on 0.5 |W f|^2; the Newton direction is a descent
        // direction with slope -|W f|^2 (times the shrink factor).
        const double m0 = 0.5 * fw.squaredNorm();
        double lambda = 1.0;
        bool accepted = false;
        Vec6 z_new = z;
        for (int k = 0; k < 40; ++k) {
            z_new = z + lambda * dz;
            const bool inside =
                std::abs(z_new[u_alpha]) < angle_bound && std::abs(z_new[u_beta]) < angle_bound;
            if (inside) {
                const double m1 = merit(z_new, nullptr);
                if (m1 <= (1.0 - 1e-4 * lambda * shrink) * m0) {
                    accepted = true;
                    break;
                }
            }
            lambda *= 0.5;
        }
        if (!accepted) {
            failure = fmt::format("the line search stalled at scaled residual {:.3g}", scaled);
            break;
        }
        z = z_new;
    }

    if (converged) {
        // Polish: a converged Newton iterate is one step from machine precision; take steps while
        // they reduce the residual.
        for (int k = 0; k < 3; ++k) {
            const Mat6 Jw = w.asDiagonal() * J;
            Eigen::CompleteOrthogonalDecomposition<Mat6> cod(Jw);
            const Vec6 z_new = z + cod.solve(-w.cwiseProduct(f));
            Vec6 f_new;
            Mat6 J_new;
            if (!z_new.allFinite()) break;
            residual_and_jacobian(model, target, z_new, f_new, J_new);
            if (!(f_new.allFinite() && w.cwiseProduct(f_new).cwiseAbs().maxCoeff() <
                                           w.cwiseProduct(f).cwiseAbs().maxCoeff()))
                break;
            z = z_new;
            f = f_new;
            J = J_new;
        }
    }

    if (!converged) {
        // Say why, as specifically as we can.
        std::vector<std::string> reasons;
        if (!guess.lift_found) {
            reasons.push_back(
                fmt::format("it needs CL {:.3g} but the tables give at most {:.3g} (at alpha {})",
                            guess.CL_needed, guess.CL_max, angle_text(guess.alpha_CL_max)));
        }
        if (z.allFinite()) {
            const auto issues = check_trim(model, target, z);
            reasons.insert(reasons.end(), issues.begin(), issues.end());
        }
        reasons.push_back(fmt::format(
            "{} (after {} iterations: alpha {}, throttle {:.4g}, elevator {:.4g} deg)", failure,
            iterations, angle_text(z[u_alpha]), z[u_throttle], z[u_elevator] * core::rad_to_deg));
        throw ConvergenceError(fmt::format("{}: {}", where, join(reasons, "; ")));
    }

    TrimResult result;
    const TrimPoint<double> pt = trim_point(target, model.environment.gravity, z);
    result.state = pt.state;
    result.controls = pt.controls;
    result.residual_norm = f.cwiseAbs().maxCoeff();
    result.iterations = iterations;
    const auto issues = check_trim(model, target, z);
    if (!issues.empty()) {
        if (options.enforce_limits)
            throw ConvergenceError(fmt::format("{}: {}", where, join(issues, "; ")));
        result.violations = join(issues, "; ");
    }
    return result;
}

LinearModel linearise(const FlightModel& model_in, const EulerState<double>& x0,
                      const Controls<double>& u0) {
    std::optional<FlightModel> copy;
    const FlightModel& model = finalized(model_in, copy);
    validate(model);
    constexpr int nx = euler::size, nu = 4, n = nx + nu;
    EulerState<Dual> x;
    for (int i = 0; i < nx; ++i) x[i] = core::make_dual(x0[i], n, i);
    Controls<Dual> u;
    u.elevator = core::make_dual(u0.elevator, n, nx + 0);
    u.aileron = core::make_dual(u0.aileron, n, nx + 1);
    u.rudder = core::make_dual(u0.rudder, n, nx + 2);
    u.throttle = core::make_dual(u0.throttle, n, nx + 3);
    const EulerState<Dual> d = euler_rhs(model, x, u);
    LinearModel lin;
    lin.x0 = x0;
    lin.u0 = u0;
    for (int i = 0; i < nx; ++i) {
        Eigen::VectorXd g = d[i].derivatives();
        if (g.size() != n) g = Eigen::VectorXd::Zero(n);
        if (!g.allFinite())
            throw NumericalError(fmt::format(
                "linearise: derivative of state {} is not finite at the given point", i));
        lin.A.row(i) = g.head(nx).transpose();
        lin.B.row(i) = g.tail(nu).transpose();
    }
    return lin;
}

}  // namespace manta::flightdyn
