#pragma once
/// @file eom.hpp
/// Rigid-body 6-DoF equations of motion over a flat, non-rotating earth (Stevens, Lewis &
/// Johnson, *Aircraft Control and Simulation*, 3rd ed., Wiley 2015, sec. 2.5-2.6 and 3.6).
///
/// One source of truth for forces and moments, `compute_loads`, feeds two state forms:
///  - Euler-angle form, the paper's state (x, y, z, phi, theta, psi, V, alpha, beta, p, q, r);
///    singular at theta = +-90 deg and at V = 0;
///  - quaternion form (x, y, z, q0, q1, q2, q3, u, v, w, p, q, r) with no attitude singularity.
/// Earth axes x north, y east, z down; altitude h = -z. Body axes x forward, y right, z down.
/// Everything is templated on the scalar so the same code runs with automatic differentiation.

#include <Eigen/Core>
#include <Eigen/LU>  // Matrix3d::inverse()
#include <array>
#include <cmath>
#include <span>
#include <type_traits>

#include "manta/aero/database.hpp"
#include "manta/core/fastmath.hpp"
#include "manta/core/frames.hpp"
#include "manta/core/scalar.hpp"
#include "manta/flightdyn/atmosphere.hpp"
#include "manta/flightdyn/model.hpp"

namespace manta::flightdyn {

/// Control inputs: deflections [rad] with the paper's signs, throttle [0..1].
template <class T>
struct Controls {
    T elevator{0.0};
    T aileron{0.0};
    T rudder{0.0};
    T throttle{0.0};
};

/// Indices of the Euler-angle state vector (the paper's order).
namespace euler {
enum Index : int { x = 0, y, z, phi, theta, psi, V, alpha, beta, p, q, r, size };
}
/// Indices of the quaternion state vector (q0 scalar part; body-to-earth rotation).
namespace quat {
enum Index : int { x = 0, y, z, q0, q1, q2, q3, u, v, w, p, q, r, size };
}

template <class T>
using EulerState = Eigen::Matrix<T, euler::size, 1>;
template <class T>
using QuatState = Eigen::Matrix<T, quat::size, 1>;
template <class T>
using Vec3 = Eigen::Matrix<T, 3, 1>;

/// Forces and moments on the aircraft and the air data they came from.
template <class T>
struct Loads {
    Vec3<T> force_body;   ///< aerodynamic + thrust force, body axes [N] (gravity excluded)
    Vec3<T> moment_body;  ///< moment about the CG, body axes [N m]
    aero::BodyCoefficients<T> coefficients;  ///< about the moment reference point
    AtmosphereState<T> atmosphere;
    T airspeed{0.0};  ///< [m/s]
    T alpha{0.0};     ///< [rad]
    T beta{0.0};      ///< [rad]
    T mach{0.0};
    T dynamic_pressure{0.0};  ///< [Pa]
    T thrust{0.0};            ///< [N]
};

/// Set derived data of a model (whether the aero tables use alpha-dot/beta-dot terms, the inverse
/// inertia tensor) and check it is complete; InputError naming what is missing. Call once after
/// building a model.
void finalize(FlightModel& model);
/// Check a model is usable (mass, inertia, reference values); InputError otherwise.
void validate(const FlightModel& model);

namespace detail {
template <class T>
T zero_like(const T& x) {
    return x * 0.0;
}

/// s = sin(x), c = cos(x): core::sin_cos for double (about one ulp, a fraction of the library
/// calls' cost), std::sin and std::cos for other scalars (automatic differentiation).
template <class T>
void sin_cos(const T& x, T& s, T& c) {
    if constexpr (std::is_same_v<T, double>) {
        core::sin_cos(x, s, c);
    } else {
        using std::cos;
        using std::sin;
        s = sin(x);
        c = cos(x);
    }
}

/// Inverse inertia tensor of the model: the one cached by finalize() while the inertia is still
/// the tensor it was computed from (compared on every call), else computed here.
[[nodiscard]] inline Eigen::Matrix3d inverse_inertia(const FlightModel& m) {
    if (m.inertia_inverse_of == m.mass.inertia) [[likely]] {
        return m.inertia_inverse;
    }
    return m.mass.inertia.inverse();
}
}  // namespace detail

namespace detail {

/// Air data, atmosphere and thrust at a state: the loads without their aerodynamic part.
/// `airspeed`, `alpha`, `beta` are those of the body velocity (|v|, atan2(w, u), asin(v/|v|)).
template <class T>
[[nodiscard]] Loads<T> propulsive_loads(const FlightModel& m, const T& h, const T& airspeed,
                                        const T& alpha, const T& beta, const Controls<T>& u) {
    Loads<T> L;
    L.atmosphere = us1976(h);
    const T zero = zero_like(h);
    const bool moving = core::value_of(airspeed) > 1e-9;
    L.airspeed = airspeed;
    L.alpha = moving ? alpha : zero;
    L.beta = moving ? beta : zero;
    L.mach = L.airspeed / L.atmosphere.speed_of_sound;
    L.dynamic_pressure = 0.5 * L.atmosphere.density * (airspeed * airspeed);
    // Thrust along the thrust line; a moment only if the engine position is off the CG.
    const T sigma = L.atmosphere.density / us1976_constants::reference_density;
    L.thrust = m.engine.thrust_at(h, L.mach, u.throttle, sigma, L.atmosphere.log_density_ratio);
    double se = 0.0, ce = 1.0;
    core::sin_cos(m.engine.thrust_angle, se, ce);
    L.force_body << L.thrust * ce, zero, -L.thrust * se;
    L.moment_body.setConstant(zero);
    if (m.engine.has_position) {
        const Eigen::Vector3d r = core::body_from_geometry(
            Eigen::Vector3d(m.engine.position[0], m.engine.position[1], m.engine.position[2]) -
            m.mass.cg_geom);
        const Vec3<T>& FT = L.force_body;
        L.moment_body.x() += r.y() * FT.z() - r.z() * FT.y();
        L.moment_body.y() += r.z() * FT.x() - r.x() * FT.z();
        L.moment_body.z() += r.x() * FT.y() - r.y() * FT.x();
    }
    return L;
}

/// The aero table query of loads whose air data are set, at body rates `omega_body`, controls
/// `u` and angle rates alpha_dot, beta_dot [rad/s] (airspeed > 0).
template <class T>
[[nodiscard]] aero::AeroQuery<T> aero_query(const FlightModel& m, const Loads<T>& L,
                                            const Vec3<T>& omega_body, const Controls<T>& u,
                                            const T& alpha_dot, const T& beta_dot) {
    const double b = m.reference.span, c = m.reference.chord;
    aero::AeroQuery<T> q;
    q.alpha = L.alpha;
    q.beta = L.beta;
    q.mach = L.mach;
    const T inv2V = 0.5 / L.airspeed;
    q.p_hat = omega_body.x() * b * inv2V;
    q.q_hat = omega_body.y() * c * inv2V;
    q.r_hat = omega_body.z() * b * inv2V;
    q.alpha_dot_hat = alpha_dot * c * inv2V;
    q.beta_dot_hat = beta_dot * b * inv2V;
    q.elevator = u.elevator;
    q.aileron = u.aileron;
    q.rudder = u.rudder;
    return q;
}

/// Aerodynamic force F (body axes) and moment M about the CG of coefficients C at qS = dynamic
/// pressure x reference area: F = qS (CX, CY, CZ), M = qS (b Cl, c Cm, b Cn) + r x F with r from
/// the CG to the moment reference point.
template <class T>
void aero_force_moment(const FlightModel& m, const T& qS, const aero::BodyCoefficients<T>& C,
                       Vec3<T>& F, Vec3<T>& M) {
    const double b = m.reference.span, c = m.reference.chord;
    F = Vec3<T>(qS * C.CX, qS * C.CY, qS * C.CZ);
    const Eigen::Vector3d r = core::body_from_geometry(m.moment_reference_geom - m.mass.cg_geom);
    M = Vec3<T>(qS * b * C.Cl + (r.y() * F.z() - r.z() * F.y()),
                qS * c * C.Cm + (r.z() * F.x() - r.x() * F.z()),
                qS * b * C.Cn + (r.x() * F.y() - r.y() * F.x()));
}

/// Add the aerodynamic coefficients, force and moment (about the CG) at body rates `omega_body`,
/// controls `u` and angle rates alpha_dot, beta_dot [rad/s] to loads whose air data are set.
/// Nothing is added without an aero database or below 1e-9 m/s, where alpha and beta are undefined.
template <class T>
void add_aero_loads(const FlightModel& m, Loads<T>& L, const Vec3<T>& omega_body,
                    const Controls<T>& u, const T& alpha_dot, const T& beta_dot) {
    if (!m.aero || !(core::value_of(L.airspeed) > 1e-9)) return;
    const aero::AeroQuery<T> q = aero_query(m, L, omega_body, u, alpha_dot, beta_dot);
    L.coefficients = m.aero->evaluate(q, m.interpolation);
    const T qS = L.dynamic_pressure * m.reference.area;
    // Moment about the reference point, then transferred to the CG: M_cg = M_ref + r x F.
    Vec3<T> F, M;
    aero_force_moment(m, qS, L.coefficients, F, M);
    L.moment_body += M;
    L.force_body += F;
}

/// compute_loads with the air data of the body velocity already known (the Euler-angle form has
/// them in its state, which saves an atan2 and an asin per evaluation).
template <class T>
[[nodiscard]] Loads<T> compute_loads_known(const FlightModel& m, const T& h, const T& airspeed,
                                           const T& alpha, const T& beta, const Vec3<T>& omega_body,
                                           const Controls<T>& u, const T& alpha_dot,
                                           const T& beta_dot) {
    Loads<T> L = propulsive_loads(m, h, airspeed, alpha, beta, u);
    add_aero_loads(m, L, omega_body, u, alpha_dot, beta_dot);
    return L;
}

}  // namespace detail

/// Aerodynamic and propulsive loads at altitude `h` [m] for air-relative body velocity
/// `v_body` [m/s], body rates `omega_body` [rad/s], controls `u`, and angle rates alpha_dot,
/// beta_dot [rad/s] (used only by tables with alpha-dot/beta-dot columns).
template <class T>
[[nodiscard]] Loads<T> compute_loads(const FlightModel& m, const T& h, const Vec3<T>& v_body,
                                     const Vec3<T>& omega_body, const Controls<T>& u,
                                     const T& alpha_dot, const T& beta_dot) {
    using std::asin;
    using std::atan2;
    using std::sqrt;
    const T airspeed = sqrt(T(v_body.squaredNorm()));
    const T zero = detail::zero_like(h);
    const bool moving = core::value_of(airspeed) > 1e-9;
    const T alpha = moving ? T(atan2(v_body.z(), v_body.x())) : zero;
    const T beta = moving ? T(asin(T(v_body.y() / airspeed))) : zero;
    return detail::compute_loads_known(m, h, airspeed, alpha, beta, omega_body, u, alpha_dot,
                                       beta_dot);
}

namespace detail {

/// Body-axis acceleration dv/dt = F/m + g_body - omega x v.
template <class T>
[[nodiscard]] Vec3<T> velocity_rate(const FlightModel& m, const Vec3<T>& force_body,
                                    const Vec3<T>& gravity_body, const Vec3<T>& v,
                                    const Vec3<T>& w) {
    const double inv_m = 1.0 / m.mass.mass;
    return Vec3<T>(force_body.x() * inv_m + gravity_body.x() - (w.y() * v.z() - w.z() * v.y()),
                   force_body.y() * inv_m + gravity_body.y() - (w.z() * v.x() - w.x() * v.z()),
                   force_body.z() * inv_m + gravity_body.z() - (w.x() * v.y() - w.y() * v.x()));
}

}  // namespace detail

/// Body-axis accelerations from loads: v_dot = F/m + g_body - omega x v, and
/// omega_dot = I^-1 (M - omega x (I omega + h_engine)).
template <class T>
void rigid_body_accelerations(const FlightModel& m, const Loads<T>& L, const Vec3<T>& gravity_body,
                              const Vec3<T>& v_body, const Vec3<T>& w, Vec3<T>& v_dot,
                              Vec3<T>& w_dot) {
    v_dot = detail::velocity_rate(m, L.force_body, gravity_body, v_body, w);
    const Eigen::Matrix3d& I = m.mass.inertia;
    const Eigen::Vector3d& he = m.engine_angular_momentum;
    Vec3<T> H;
    H.x() = I(0, 0) * w.x() + I(0, 1) * w.y() + I(0, 2) * w.z() + he.x();
    H.y() = I(1, 0) * w.x() + I(1, 1) * w.y() + I(1, 2) * w.z() + he.y();
    H.z() = I(2, 0) * w.x() + I(2, 1) * w.y() + I(2, 2) * w.z() + he.z();
    const Vec3<T> rhs(L.moment_body.x() - (w.y() * H.z() - w.z() * H.y()),
                      L.moment_body.y() - (w.z() * H.x() - w.x() * H.z()),
                      L.moment_body.z() - (w.x() * H.y() - w.y() * H.x()));
    const Eigen::Matrix3d Ii = detail::inverse_inertia(m);
    w_dot.x() = Ii(0, 0) * rhs.x() + Ii(0, 1) * rhs.y() + Ii(0, 2) * rhs.z();
    w_dot.y() = Ii(1, 0) * rhs.x() + Ii(1, 1) * rhs.y() + Ii(1, 2) * rhs.z();
    w_dot.z() = Ii(2, 0) * rhs.x() + Ii(2, 1) * rhs.y() + Ii(2, 2) * rhs.z();
}

namespace detail {

/// alpha_dot and beta_dot implied by the body velocity v and its rate vd:
/// alpha_dot = (u wd - w ud) / (u^2 + w^2), beta_dot = (vd V - v V_dot) / (V^2 cos(beta)),
/// V cos(beta) = sqrt(u^2 + w^2) (Stevens, Lewis & Johnson 2015, eq. 2.5-7).
template <class T>
void angle_rates(const Vec3<T>& v, const Vec3<T>& vd, T& alpha_dot, T& beta_dot) {
    using std::sqrt;
    const T uw2 = v.x() * v.x() + v.z() * v.z();
    const T V2 = uw2 + v.y() * v.y();
    const T V = sqrt(V2);
    alpha_dot = (v.x() * vd.z() - v.z() * vd.x()) / uw2;
    const T Vd = (v.x() * vd.x() + v.y() * vd.y() + v.z() * vd.z()) / V;
    beta_dot = (vd.y() * V - v.y() * Vd) / (V * sqrt(uw2));
}

/// consistent_loads for any scalar: three load evaluations, at (alpha_dot, beta_dot) = (0, 0),
/// (1, 0) and (0, 1) rad/s (one extra table pass per angle rate the tables use), give the 2x2
/// linear system (I - K) [alpha_dot, beta_dot] = f0, and the loads at its solution are the same
/// affine combination of the three. The AD scalars take this path; `double` takes
/// consistent_loads_affine, which gets the same system from one table pass.
template <class T>
[[nodiscard]] Loads<T> consistent_loads_passes(const FlightModel& m, const T& h,
                                               const Vec3<T>& v_body, const T& airspeed,
                                               const T& alpha, const T& beta, const Vec3<T>& w,
                                               const Controls<T>& u, const Vec3<T>& gravity_body) {
    const T zero = zero_like(h);
    // Atmosphere and thrust do not depend on the angle rates: once.
    const Loads<T> base = propulsive_loads(m, h, airspeed, alpha, beta, u);
    Loads<T> L = base;
    add_aero_loads(m, L, w, u, zero, zero);
    const double uw2 = core::value_of(v_body.x()) * core::value_of(v_body.x()) +
                       core::value_of(v_body.z()) * core::value_of(v_body.z());
    if (!m.angle_rate_terms || !m.aero || !(core::value_of(airspeed) > 1e-9) || !(uw2 > 1e-18))
        return L;
    const T one = zero + 1.0;
    // One extra table pass per angle rate the tables use: the Ranger's alpha-dot terms alone cost
    // one; a model with no beta-dot columns leaves Lb = L (its column of K is zero).
    Loads<T> La = L, Lb = L;
    if (m.alpha_dot_terms) {
        La = base;
        add_aero_loads(m, La, w, u, one, zero);
    }
    if (m.beta_dot_terms) {
        Lb = base;
        add_aero_loads(m, Lb, w, u, zero, one);
    }
    T a0, b0, a1, b1, a2, b2;
    angle_rates(v_body, velocity_rate(m, L.force_body, gravity_body, v_body, w), a0, b0);
    a1 = a0;
    b1 = b0;
    a2 = a0;
    b2 = b0;
    if (m.alpha_dot_terms)
        angle_rates(v_body, velocity_rate(m, La.force_body, gravity_body, v_body, w), a1, b1);
    if (m.beta_dot_terms)
        angle_rates(v_body, velocity_rate(m, Lb.force_body, gravity_body, v_body, w), a2, b2);
    // (I - K) x = f0 with K = [[a1 - a0, a2 - a0], [b1 - b0, b2 - b0]].
    const T k11 = 1.0 - (a1 - a0), k12 = -(a2 - a0), k21 = -(b1 - b0), k22 = 1.0 - (b2 - b0);
    const T det = k11 * k22 - k12 * k21;
    const T ad = (a0 * k22 - k12 * b0) / det;
    const T bd = (k11 * b0 - k21 * a0) / det;
    auto mix = [&](const T& x0, const T& xa, const T& xb) {
        return T(x0 + ad * (xa - x0) + bd * (xb - x0));
    };
    for (int i = 0; i < 3; ++i) {
        L.force_body[i] = mix(L.force_body[i], La.force_body[i], Lb.force_body[i]);
        L.moment_body[i] = mix(L.moment_body[i], La.moment_body[i], Lb.moment_body[i]);
    }
    auto& C = L.coefficients;
    C.CX = mix(C.CX, La.coefficients.CX, Lb.coefficients.CX);
    C.CY = mix(C.CY, La.coefficients.CY, Lb.coefficients.CY);
    C.CZ = mix(C.CZ, La.coefficients.CZ, Lb.coefficients.CZ);
    C.Cl = mix(C.Cl, La.coefficients.Cl, Lb.coefficients.Cl);
    C.Cm = mix(C.Cm, La.coefficients.Cm, Lb.coefficients.Cm);
    C.Cn = mix(C.Cn, La.coefficients.Cn, Lb.coefficients.Cn);
    return L;
}

/// consistent_loads for double (eom.cpp): one table pass gives the coefficients at zero angle
/// rates and their derivatives with respect to alpha_dot_hat and beta_dot_hat
/// (AeroDatabase::evaluate_with_angle_rates), hence the loads and K of consistent_loads_passes
/// without evaluating the tables again. Equal to that path to rounding.
[[nodiscard]] Loads<double> consistent_loads_affine(const FlightModel& m, double h,
                                                    const Vec3<double>& v_body, double airspeed,
                                                    double alpha, double beta,
                                                    const Vec3<double>& w,
                                                    const Controls<double>& u,
                                                    const Vec3<double>& gravity_body);

/// Loads at a state with the alpha-dot and beta-dot terms of the tables made consistent with the
/// motion they cause. The loads are affine in (alpha_dot, beta_dot) (the dynamic table adds
/// C_alphadot alpha_dot_hat + C_betadot beta_dot_hat), and so are the angle rates the resulting
/// accelerations imply, so the consistent rates solve a 2x2 linear system (I - K) x = f0 and the
/// loads follow from them exactly. Skipped when the tables have no such terms, or when alpha and
/// beta are undefined (V = 0 or u = w = 0).
template <class T>
[[nodiscard]] Loads<T> consistent_loads(const FlightModel& m, const T& h, const Vec3<T>& v_body,
                                        const T& airspeed, const T& alpha, const T& beta,
                                        const Vec3<T>& w, const Controls<T>& u,
                                        const Vec3<T>& gravity_body) {
    if constexpr (std::is_same_v<T, double>) {
        return consistent_loads_affine(m, h, v_body, airspeed, alpha, beta, w, u, gravity_body);
    } else {
        return consistent_loads_passes(m, h, v_body, airspeed, alpha, beta, w, u, gravity_body);
    }
}

}  // namespace detail

namespace detail {

/// Instruction set of the fused double-precision right-hand side (src/flightdyn/fast_rhs.cpp).
enum class FastKernelSet {
    /// AVX2 with FMA where the processor has it; MANTA_FLIGHTDYN_KERNELS=baseline forces the
    /// baseline set, =reference turns the fused path off (the templates alone, for comparisons)
    automatic,
    baseline,  ///< baseline x86-64 (SSE2)
    avx2,      ///< AVX2 with FMA (unavailable: the fused path reports false)
};

/// The fused right-hand side in double: atmosphere, thrust, one multilinear pass over the aero
/// tables with the alpha-dot/beta-dot partials, the implicit angle-rate solve, accelerations and
/// kinematics in one compiled function, equal to euler_rhs_reference to rounding. Returns false,
/// with `d` unspecified, where it does not apply (thrust tables, C1 interpolation, an
/// out-of-table query, which the reference path counts, altitude outside the atmosphere, V near
/// zero, non-principal air data); the caller then takes the reference path. Counts one aero
/// evaluation when it succeeds.
[[nodiscard]] bool fast_euler_rhs(const FlightModel& m, const EulerState<double>& s,
                                  const Controls<double>& u, EulerState<double>& d,
                                  FastKernelSet which = FastKernelSet::automatic);
/// The same for the quaternion form (equal to quaternion_rhs_reference to rounding).
[[nodiscard]] bool fast_quaternion_rhs(const FlightModel& m, const QuatState<double>& s,
                                       const Controls<double>& u, QuatState<double>& d,
                                       FastKernelSet which = FastKernelSet::automatic);
/// The batched kernel of `which` (AVX2: four states per pass) over s[0, n), u, d: on return
/// d[0, next) is written, next a multiple of four (0 where the set has no batched kernel, the
/// model is not covered by the fused path, or n < 4); lanes the pass refuses are computed by
/// euler_rhs. euler_rhs_batch is the public entry.
void batched_euler_rhs(const FlightModel& m, const EulerState<double>* s, const Controls<double>* u,
                       EulerState<double>* d, std::size_t n, FastKernelSet which,
                       std::size_t& next);
/// The same for quaternion states (quaternion_rhs_batch is the public entry).
void batched_quaternion_rhs(const FlightModel& m, const QuatState<double>* s,
                            const Controls<double>* u, QuatState<double>* d, std::size_t n,
                            FastKernelSet which, std::size_t& next);
/// True when this build has the AVX2 kernels and the processor runs them.
[[nodiscard]] bool has_avx2_rhs_kernels();
/// Name of the kernel set the automatic choice uses ("avx2", "baseline" or "reference").
[[nodiscard]] const char* fast_rhs_kernel_name();

/// euler_rhs by the templates alone (any scalar): the reference of the fused path.
template <class T>
[[nodiscard]] EulerState<T> euler_rhs_reference(const FlightModel& m, const EulerState<T>& s,
                                                const Controls<T>& u,
                                                Loads<T>* loads_out = nullptr) {
    using std::asin;
    using std::atan2;
    using std::sqrt;
    T sphi, cphi, sth, cth, spsi, cpsi, sa, ca, sb, cb;
    detail::sin_cos(s[euler::phi], sphi, cphi);
    detail::sin_cos(s[euler::theta], sth, cth);
    detail::sin_cos(s[euler::psi], spsi, cpsi);
    detail::sin_cos(s[euler::alpha], sa, ca);
    detail::sin_cos(s[euler::beta], sb, cb);
    const T V = s[euler::V];
    const Vec3<T> v_body(V * ca * cb, V * sb, V * sa * cb);
    const Vec3<T> w(s[euler::p], s[euler::q], s[euler::r]);
    const T h = -s[euler::z];
    const double g = m.environment.gravity;
    const Vec3<T> g_body(-g * sth, g * sphi * cth, g * cphi * cth);
    // Air data of v_body: the state's own (V, alpha, beta) when they are the principal values,
    // as atan2/asin would return them; otherwise (V < 0, |alpha| > pi, |beta| > pi/2) computed.
    const double Vv = core::value_of(V), av = core::value_of(s[euler::alpha]),
                 bv = core::value_of(s[euler::beta]);
    const bool principal = Vv > 0.0 && std::abs(av) <= core::pi && std::abs(bv) < 0.5 * core::pi;
    const T airspeed = principal ? V : T(sqrt(T(v_body.squaredNorm())));
    const T alpha = principal ? s[euler::alpha] : T(atan2(v_body.z(), v_body.x()));
    const T beta = principal || !(core::value_of(airspeed) > 0.0)
                       ? s[euler::beta]
                       : T(asin(T(v_body.y() / airspeed)));
    const Loads<T> L = detail::consistent_loads(m, h, v_body, airspeed, alpha, beta, w, u, g_body);
    Vec3<T> v_dot, w_dot;
    rigid_body_accelerations(m, L, g_body, v_body, w, v_dot, w_dot);

    EulerState<T> d;
    const T &uu = v_body.x(), &vv = v_body.y(), &ww = v_body.z();
    // Air-data rates V_dot = v . v_dot / V, alpha_dot = (u w_dot - w u_dot) / (u^2 + w^2),
    // beta_dot = (V v_dot - v V_dot) / (V^2 cos(beta)) = (V^2 v_dot - v (v . v_dot)) / (V^3 cb):
    // the reciprocals depend on the state alone, so no division waits for the loads.
    const T inv_V = 1.0 / V;
    const T inv_uw2 = 1.0 / (uu * uu + ww * ww);
    const T inv_V3cb = 1.0 / (V * V * V * cb);
    const T v_vdot = uu * v_dot.x() + vv * v_dot.y() + ww * v_dot.z();
    d[euler::V] = v_vdot * inv_V;
    d[euler::alpha] = (uu * v_dot.z() - ww * v_dot.x()) * inv_uw2;
    d[euler::beta] = (V * V * v_dot.y() - vv * v_vdot) * inv_V3cb;
    // Attitude kinematics (3-2-1 Euler angles).
    const std::array<T, 3> angle_rates =
        core::euler_rates_from_body_rates_sc(sphi, cphi, sth, cth, w.x(), w.y(), w.z());
    d[euler::phi] = angle_rates[0];
    d[euler::theta] = angle_rates[1];
    d[euler::psi] = angle_rates[2];
    // Navigation: earth-axis velocity = C_earth_from_body * v_body.
    const std::array<T, 3> v_earth = core::earth_from_body(
        core::dcm_body_from_earth_sc(sphi, cphi, sth, cth, spsi, cpsi), uu, vv, ww);
    d[euler::x] = v_earth[0];
    d[euler::y] = v_earth[1];
    d[euler::z] = v_earth[2];
    d[euler::p] = w_dot.x();
    d[euler::q] = w_dot.y();
    d[euler::r] = w_dot.z();
    if (loads_out) *loads_out = L;
    return d;
}

/// quaternion_rhs by the templates alone (any scalar): the reference of the fused path.
template <class T>
[[nodiscard]] QuatState<T> quaternion_rhs_reference(const FlightModel& m, const QuatState<T>& s,
                                                    const Controls<T>& u,
                                                    Loads<T>* loads_out = nullptr) {
    using std::asin;
    using std::atan2;
    using std::sqrt;
    const T q0 = s[quat::q0], q1 = s[quat::q1], q2 = s[quat::q2], q3 = s[quat::q3];
    const Vec3<T> v_body(s[quat::u], s[quat::v], s[quat::w]);
    const Vec3<T> w(s[quat::p], s[quat::q], s[quat::r]);
    const T h = -s[quat::z];
    // C_earth_from_body of the unit quaternion (normalised here so drift does not scale vectors).
    const T n2 = q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3;
    const T inv_n2 = 1.0 / n2;
    const auto C = core::dcm_earth_from_quaternion_sc(q0, q1, q2, q3, inv_n2);
    const T &c11 = C[0][0], &c12 = C[0][1], &c13 = C[0][2];
    const T &c21 = C[1][0], &c22 = C[1][1], &c23 = C[1][2];
    const T &c31 = C[2][0], &c32 = C[2][1], &c33 = C[2][2];
    const double g = m.environment.gravity;
    const Vec3<T> g_body(g * c31, g * c32, g * c33);  // C_body_from_earth * (0, 0, g)
    const T airspeed = sqrt(T(v_body.squaredNorm()));
    const T zero = detail::zero_like(h);
    const bool moving = core::value_of(airspeed) > 1e-9;
    const T alpha = moving ? T(atan2(v_body.z(), v_body.x())) : zero;
    const T beta = moving ? T(asin(T(v_body.y() / airspeed))) : zero;
    const Loads<T> L = detail::consistent_loads(m, h, v_body, airspeed, alpha, beta, w, u, g_body);
    Vec3<T> v_dot, w_dot;
    rigid_body_accelerations(m, L, g_body, v_body, w, v_dot, w_dot);
    QuatState<T> d;
    d[quat::x] = c11 * v_body.x() + c12 * v_body.y() + c13 * v_body.z();
    d[quat::y] = c21 * v_body.x() + c22 * v_body.y() + c23 * v_body.z();
    d[quat::z] = c31 * v_body.x() + c32 * v_body.y() + c33 * v_body.z();
    // q_dot = 1/2 q (x) (0, omega) + k (1 - |q|^2) q, the second term holding the norm at 1
    // (Stevens, Lewis & Johnson 2015, eq. 1.8-15 with the correction term of sec. 3.6).
    const double k = 1.0;
    const T corr = k * (1.0 - n2);
    d[quat::q0] = 0.5 * (-q1 * w.x() - q2 * w.y() - q3 * w.z()) + corr * q0;
    d[quat::q1] = 0.5 * (q0 * w.x() + q2 * w.z() - q3 * w.y()) + corr * q1;
    d[quat::q2] = 0.5 * (q0 * w.y() + q3 * w.x() - q1 * w.z()) + corr * q2;
    d[quat::q3] = 0.5 * (q0 * w.z() + q1 * w.y() - q2 * w.x()) + corr * q3;
    d[quat::u] = v_dot.x();
    d[quat::v] = v_dot.y();
    d[quat::w] = v_dot.z();
    d[quat::p] = w_dot.x();
    d[quat::q] = w_dot.y();
    d[quat::r] = w_dot.z();
    if (loads_out) *loads_out = L;
    return d;
}

}  // namespace detail

/// Time derivative of the Euler-angle state. If the aero tables carry alpha-dot or beta-dot
/// terms the implicit dependence is solved exactly (the loads are affine in them; see
/// detail::consistent_loads). In double without `loads_out` the fused kernel
/// (detail::fast_euler_rhs) runs where it applies; otherwise, and for every other scalar,
/// detail::euler_rhs_reference.
template <class T>
[[nodiscard]] EulerState<T> euler_rhs(const FlightModel& m, const EulerState<T>& s,
                                      const Controls<T>& u, Loads<T>* loads_out = nullptr) {
    if constexpr (std::is_same_v<T, double>) {
        if (loads_out == nullptr) {
            EulerState<double> d;
            if (detail::fast_euler_rhs(m, s, u, d)) return d;
        }
    }
    return detail::euler_rhs_reference(m, s, u, loads_out);
}

/// Time derivative of the quaternion state (see euler_rhs for alpha-dot terms and the fused
/// double path).
template <class T>
[[nodiscard]] QuatState<T> quaternion_rhs(const FlightModel& m, const QuatState<T>& s,
                                          const Controls<T>& u, Loads<T>* loads_out = nullptr) {
    if constexpr (std::is_same_v<T, double>) {
        if (loads_out == nullptr) {
            QuatState<double> d;
            if (detail::fast_quaternion_rhs(m, s, u, d)) return d;
        }
    }
    return detail::quaternion_rhs_reference(m, s, u, loads_out);
}

/// Time derivatives of many Euler states at once: d[i] equals euler_rhs(m, s[i], u[i]) to
/// rounding (1e-13 relative to 1 + |value|) for every i. Where the processor has AVX2 with FMA,
/// each group of four states takes one pass four lanes wide (atmosphere, thrust, trigonometry,
/// the table cells and weights, the implicit angle-rate solve, accelerations and kinematics; the
/// tables' corner rows per state);
/// the rest, and any state the pass does not cover (see detail::fast_euler_rhs), go through
/// euler_rhs one by one. The three spans must have the same length (InputError otherwise); `d`
/// may not overlap `s`.
void euler_rhs_batch(const FlightModel& m, std::span<const EulerState<double>> s,
                     std::span<const Controls<double>> u, std::span<EulerState<double>> d);
/// The same for the quaternion form (d[i] equals quaternion_rhs(m, s[i], u[i]) to rounding); the
/// four-lane pass takes the air angles from a vector atan2 and their sines and cosines from the
/// velocity components.
void quaternion_rhs_batch(const FlightModel& m, std::span<const QuatState<double>> s,
                          std::span<const Controls<double>> u, std::span<QuatState<double>> d);

/// Quaternion (q0, q1, q2, q3) of 3-2-1 Euler angles (body-to-earth rotation).
[[nodiscard]] Eigen::Vector4d quaternion_from_euler(double phi, double theta, double psi);
/// 3-2-1 Euler angles (phi, theta, psi) of a quaternion; psi in (-pi, pi].
[[nodiscard]] Eigen::Vector3d euler_from_quaternion(const Eigen::Vector4d& q);
/// Convert between the two state forms.
[[nodiscard]] QuatState<double> to_quaternion_state(const EulerState<double>& s);
[[nodiscard]] EulerState<double> to_euler_state(const QuatState<double>& s);

/// Derived outputs at a state, for trajectories and reports.
struct FlightOutputs {
    double altitude = 0.0;  ///< [m]
    double mach = 0.0;
    double dynamic_pressure = 0.0;  ///< [Pa]
    double nz = 0.0;  ///< load factor: -(aero + thrust z force) / (m g), 1 in level flight
    double ny = 0.0;
    double thrust = 0.0;  ///< [N]
    double CL = 0.0, CD = 0.0, CY = 0.0, Cl = 0.0, Cm = 0.0,
           Cn = 0.0;                 ///< wind forces, body moments (MRP)
    double flight_path_angle = 0.0;  ///< gamma [rad]
};
[[nodiscard]] FlightOutputs outputs(const FlightModel& m, const Loads<double>& loads,
                                    const EulerState<double>& s);

}  // namespace manta::flightdyn
