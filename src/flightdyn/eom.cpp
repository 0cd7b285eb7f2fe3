#include "manta/flightdyn/eom.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "manta/core/error.hpp"

namespace manta::flightdyn {

void finalize(FlightModel& model) {
    model.angle_rate_terms = false;
    model.alpha_dot_terms = false;
    model.beta_dot_terms = false;
    if (model.aero) {
        for (const auto& t : model.aero->tables()) {
            if (t.kind != aero::TableKind::dynamic) continue;
            for (const auto& c : t.columns) {
                if (c.ends_with("_alphadot")) model.alpha_dot_terms = true;
                if (c.ends_with("_betadot")) model.beta_dot_terms = true;
            }
        }
    }
    model.angle_rate_terms = model.alpha_dot_terms || model.beta_dot_terms;
    validate(model);
}

void validate(const FlightModel& m) {
    const std::string who =
        m.name.empty() ? "flight model" : fmt::format("flight model '{}'", m.name);
    if (!(m.mass.mass > 0.0 && std::isfinite(m.mass.mass)))
        throw InputError(
            fmt::format("{}: mass {} kg; expected a finite number > 0", who, m.mass.mass));
    if (!m.mass.inertia.allFinite() ||
        (m.mass.inertia - m.mass.inertia.transpose()).norm() > 1e-9 * m.mass.inertia.norm())
        throw InputError(fmt::format("{}: inertia tensor is not finite and symmetric", who));
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(m.mass.inertia);
    if (es.eigenvalues().minCoeff() <= 0.0)
        throw InputError(fmt::format(
            "{}: inertia tensor is not positive definite (smallest principal moment {} kg m^2)",
            who, es.eigenvalues().minCoeff()));
    if (m.aero) {
        if (!(m.reference.area > 0.0 && m.reference.span > 0.0 && m.reference.chord > 0.0))
            throw InputError(
                fmt::format("{}: reference area, span and chord must be > 0 (got {}, {}, {})", who,
                            m.reference.area, m.reference.span, m.reference.chord));
    }
    if (!(m.environment.gravity >= 0.0 && std::isfinite(m.environment.gravity)))
        throw InputError(fmt::format("{}: gravity {} m/s^2; expected a finite number >= 0", who,
                                     m.environment.gravity));
    m.engine.validate(who + " engine");
}

Eigen::Vector4d quaternion_from_euler(double phi, double theta, double psi) {
    const double cf = std::cos(phi / 2), sf = std::sin(phi / 2);
    const double ct = std::cos(theta / 2), st = std::sin(theta / 2);
    const double cp = std::cos(psi / 2), sp = std::sin(psi / 2);
    return {cf * ct * cp + sf * st * sp, sf * ct * cp - cf * st * sp, cf * st * cp + sf * ct * sp,
            cf * ct * sp - sf * st * cp};
}

Eigen::Vector3d euler_from_quaternion(const Eigen::Vector4d& qin) {
    const Eigen::Vector4d q = qin / qin.norm();
    const double q0 = q[0], q1 = q[1], q2 = q[2], q3 = q[3];
    const double s = std::clamp(2.0 * (q0 * q2 - q1 * q3), -1.0, 1.0);
    const double phi = std::atan2(2.0 * (q0 * q1 + q2 * q3), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3);
    const double theta = std::asin(s);
    const double psi = std::atan2(2.0 * (q0 * q3 + q1 * q2), q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3);
    return {phi, theta, psi};
}

QuatState<double> to_quaternion_state(const EulerState<double>& s) {
    QuatState<double> out;
    out[quat::x] = s[euler::x];
    out[quat::y] = s[euler::y];
    out[quat::z] = s[euler::z];
    out.segment<4>(quat::q0) = quaternion_from_euler(s[euler::phi], s[euler::theta], s[euler::psi]);
    const double V = s[euler::V], a = s[euler::alpha], b = s[euler::beta];
    out[quat::u] = V * std::cos(a) * std::cos(b);
    out[quat::v] = V * std::sin(b);
    out[quat::w] = V * std::sin(a) * std::cos(b);
    out[quat::p] = s[euler::p];
    out[quat::q] = s[euler::q];
    out[quat::r] = s[euler::r];
    return out;
}

EulerState<double> to_euler_state(const QuatState<double>& s) {
    EulerState<double> out;
    out[euler::x] = s[quat::x];
    out[euler::y] = s[quat::y];
    out[euler::z] = s[quat::z];
    const Eigen::Vector3d e = euler_from_quaternion(s.segment<4>(quat::q0));
    out[euler::phi] = e[0];
    out[euler::theta] = e[1];
    out[euler::psi] = e[2];
    const double u = s[quat::u], v = s[quat::v], w = s[quat::w];
    const double V = std::sqrt(u * u + v * v + w * w);
    out[euler::V] = V;
    out[euler::alpha] = V > 0 ? std::atan2(w, u) : 0.0;
    out[euler::beta] = V > 0 ? std::asin(v / V) : 0.0;
    out[euler::p] = s[quat::p];
    out[euler::q] = s[quat::q];
    out[euler::r] = s[quat::r];
    return out;
}

FlightOutputs outputs(const FlightModel& m, const Loads<double>& L, const EulerState<double>& s) {
    FlightOutputs o;
    o.altitude = -s[euler::z];
    o.mach = L.mach;
    o.dynamic_pressure = L.dynamic_pressure;
    o.thrust = L.thrust;
    const double W = m.mass.mass * m.environment.gravity;
    o.nz = W > 0 ? -L.force_body.z() / W : 0.0;
    o.ny = W > 0 ? L.force_body.y() / W : 0.0;
    const auto wind = aero::wind_from_body(L.coefficients.CX, L.coefficients.CY, L.coefficients.CZ,
                                           L.alpha, L.beta);
    o.CL = wind.CL;
    o.CD = wind.CD;
    o.CY = wind.CY;
    o.Cl = L.coefficients.Cl;
    o.Cm = L.coefficients.Cm;
    o.Cn = L.coefficients.Cn;
    // sin(gamma) = -z_dot / V
    const double ca = std::cos(s[euler::alpha]), sa = std::sin(s[euler::alpha]);
    const double cb = std::cos(s[euler::beta]), sb = std::sin(s[euler::beta]);
    const double sf = std::sin(s[euler::phi]), cf = std::cos(s[euler::phi]);
    const double st = std::sin(s[euler::theta]), ct = std::cos(s[euler::theta]);
    const double sg = ca * cb * st - sb * sf * ct - sa * cb * cf * ct;
    o.flight_path_angle = std::asin(std::clamp(sg, -1.0, 1.0));
    return o;
}

// Explicit instantiation for double keeps the common path compiled once.
template EulerState<double> euler_rhs<double>(const FlightModel&, const EulerState<double>&,
                                              const Controls<double>&, Loads<double>*);
template QuatState<double> quaternion_rhs<double>(const FlightModel&, const QuatState<double>&,
                                                  const Controls<double>&, Loads<double>*);

}  // namespace manta::flightdyn
