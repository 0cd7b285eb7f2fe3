#include "manta/flightdyn/eom.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "manta/core/error.hpp"
#include "manta/core/frames.hpp"

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
    model.inertia_inverse = model.mass.inertia.inverse();
    model.inertia_inverse_of = model.mass.inertia;
    validate(model);
}

namespace detail {

Loads<double> consistent_loads_affine(const FlightModel& m, double h, const Vec3<double>& v_body,
                                      double airspeed, double alpha, double beta,
                                      const Vec3<double>& w, const Controls<double>& u,
                                      const Vec3<double>& gravity_body) {
    // Atmosphere and thrust do not depend on the angle rates.
    Loads<double> L = propulsive_loads(m, h, airspeed, alpha, beta, u);
    const double uw2 = v_body.x() * v_body.x() + v_body.z() * v_body.z();
    if (!m.angle_rate_terms || !m.aero || !(airspeed > 1e-9) || !(uw2 > 1e-18)) {
        add_aero_loads(m, L, w, u, 0.0, 0.0);
        return L;
    }
    // Coefficients at zero angle rates and their slopes in alpha_dot_hat, beta_dot_hat.
    const aero::AeroQuery<double> q = aero_query(m, L, w, u, 0.0, 0.0);
    const aero::AngleRateExpansion e = m.aero->evaluate_with_angle_rates(q, m.interpolation);
    const double inv2V = 0.5 / L.airspeed;
    // alpha_dot_hat and beta_dot_hat per rad/s of alpha_dot and beta_dot (as aero_query has them).
    const double ka = m.reference.chord * inv2V, kb = m.reference.span * inv2V;
    const double qS = L.dynamic_pressure * m.reference.area;
    // Aero force and moment at zero angle rates (F0, M0) and per rad/s of each rate (Fa, Ma and
    // Fb, Mb): the differences La - L0, Lb - L0 of consistent_loads_passes.
    // A rate whose flag is off is left out, as consistent_loads_passes leaves out its pass.
    Vec3<double> F0, M0, Fa, Ma, Fb, Mb;
    aero_force_moment(m, qS, e.value, F0, M0);
    Fa.setZero();
    Ma.setZero();
    Fb.setZero();
    Mb.setZero();
    if (m.alpha_dot_terms) aero_force_moment(m, qS * ka, e.d_alpha_dot_hat, Fa, Ma);
    if (m.beta_dot_terms) aero_force_moment(m, qS * kb, e.d_beta_dot_hat, Fb, Mb);
    const Vec3<double> force0 = L.force_body + F0;
    const Vec3<double> moment0 = L.moment_body + M0;
    // The angle rates are linear in the body acceleration vd (angle_rates): alpha_dot =
    // (u vd_z - w vd_x) / uw2, beta_dot = (vd_y V - v (v . vd) / V) / (V sqrt(uw2)).
    const Vec3<double>& v = v_body;
    const double V = std::sqrt(uw2 + v.y() * v.y());
    const double inv_uw2 = 1.0 / uw2, inv_V = 1.0 / V, inv_Vq = 1.0 / (V * std::sqrt(uw2));
    auto rates_of = [&](const Vec3<double>& vd, double& ad, double& bd) {
        ad = (v.x() * vd.z() - v.z() * vd.x()) * inv_uw2;
        const double Vd = (v.x() * vd.x() + v.y() * vd.y() + v.z() * vd.z()) * inv_V;
        bd = (vd.y() * V - v.y() * Vd) * inv_Vq;
    };
    const double inv_m = 1.0 / m.mass.mass;
    double a0 = 0.0, b0 = 0.0, a1 = 0.0, b1 = 0.0, a2 = 0.0, b2 = 0.0;
    rates_of(velocity_rate(m, force0, gravity_body, v_body, w), a0, b0);
    if (m.alpha_dot_terms) rates_of(Vec3<double>(Fa * inv_m), a1, b1);
    if (m.beta_dot_terms) rates_of(Vec3<double>(Fb * inv_m), a2, b2);
    // (I - K) x = f0 with K = [[a1, a2], [b1, b2]].
    const double k11 = 1.0 - a1, k12 = -a2, k21 = -b1, k22 = 1.0 - b2;
    const double inv_det = 1.0 / (k11 * k22 - k12 * k21);
    const double ad = (a0 * k22 - k12 * b0) * inv_det;
    const double bd = (k11 * b0 - k21 * a0) * inv_det;
    L.force_body = force0 + ad * Fa + bd * Fb;
    L.moment_body = moment0 + ad * Ma + bd * Mb;
    // The consistent alpha_dot_hat and beta_dot_hat.
    const double xa = m.alpha_dot_terms ? ad * ka : 0.0;
    const double xb = m.beta_dot_terms ? bd * kb : 0.0;
    auto& C = L.coefficients;
    const auto& C0 = e.value;
    const auto& Ca = e.d_alpha_dot_hat;
    const auto& Cb = e.d_beta_dot_hat;
    C.CX = C0.CX + xa * Ca.CX + xb * Cb.CX;
    C.CY = C0.CY + xa * Ca.CY + xb * Cb.CY;
    C.CZ = C0.CZ + xa * Ca.CZ + xb * Cb.CZ;
    C.Cl = C0.Cl + xa * Ca.Cl + xb * Cb.Cl;
    C.Cm = C0.Cm + xa * Ca.Cm + xb * Cb.Cm;
    C.Cn = C0.Cn + xa * Ca.Cn + xb * Cb.Cn;
    return L;
}

}  // namespace detail

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
    const Eigen::Vector3d uvw =
        core::air_velocity_body(s[euler::V], s[euler::alpha], s[euler::beta]);
    out[quat::u] = uvw.x();
    out[quat::v] = uvw.y();
    out[quat::w] = uvw.z();
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
