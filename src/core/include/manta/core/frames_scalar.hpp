#pragma once
/// @file frames_scalar.hpp
/// The 3-2-1 direction cosine matrix and the Euler-angle rate relations of frames.hpp for any
/// scalar with + - * and division of a double by it (double, the automatic-differentiation
/// scalars, the flight kernels' SIMD lanes), from the sines and cosines of the angles, so the
/// equations of motion compute each sine once and share the matrix. This header includes only
/// <array> and defines templates alone: the AVX2 flight kernels include it under a renamed
/// namespace (src/flightdyn/fast_rhs_avx2.cpp), as they do core/fastmath.hpp.

#include <array>

namespace manta::core {

/// A 3 x 3 matrix of any scalar, row-major: m[row][column].
template <class T>
using Matrix33 = std::array<std::array<T, 3>, 3>;

/// C_body_from_earth of 3-2-1 Euler angles from their sines and cosines (any scalar):
///   [ ct cp               ct sp               -st   ]
///   [ sf st cp - cf sp    sf st sp + cf cp    sf ct ]
///   [ cf st cp + sf sp    cf st sp - sf cp    cf ct ]
/// with f = phi, t = theta, p = psi. "Earth" is any reference frame the angles are taken from.
template <class T>
[[nodiscard]] Matrix33<T> dcm_body_from_earth_sc(const T& sphi, const T& cphi, const T& sth,
                                                 const T& cth, const T& spsi, const T& cpsi) {
    return {{{cth * cpsi, cth * spsi, -sth},
             {sphi * sth * cpsi - cphi * spsi, sphi * sth * spsi + cphi * cpsi, sphi * cth},
             {cphi * sth * cpsi + sphi * spsi, cphi * sth * spsi - sphi * cpsi, cphi * cth}}};
}

/// Earth components C^T v of the body vector (u, v, w), C = C_body_from_earth (any scalar).
template <class T>
[[nodiscard]] std::array<T, 3> earth_from_body(const Matrix33<T>& C, const T& u, const T& v,
                                               const T& w) {
    return {C[0][0] * u + C[1][0] * v + C[2][0] * w, C[0][1] * u + C[1][1] * v + C[2][1] * w,
            C[0][2] * u + C[1][2] * v + C[2][2] * w};
}

/// C_earth_from_body of the quaternion (q0 scalar) q / |q| from q and inv_n2 = 1 / |q|^2 (any
/// scalar): the unit-quaternion matrix (Stevens, Lewis & Johnson 2015, eq. 1.8-16) of q, each
/// entry times inv_n2. inv_n2 = 1 takes q as unit.
template <class T>
[[nodiscard]] Matrix33<T> dcm_earth_from_quaternion_sc(const T& q0, const T& q1, const T& q2,
                                                       const T& q3, const T& inv_n2) {
    return {{{(q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3) * inv_n2, 2.0 * (q1 * q2 - q0 * q3) * inv_n2,
              2.0 * (q1 * q3 + q0 * q2) * inv_n2},
             {2.0 * (q1 * q2 + q0 * q3) * inv_n2, (q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3) * inv_n2,
              2.0 * (q2 * q3 - q0 * q1) * inv_n2},
             {2.0 * (q1 * q3 - q0 * q2) * inv_n2, 2.0 * (q2 * q3 + q0 * q1) * inv_n2,
              (q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3) * inv_n2}}};
}

/// Euler-angle rates (phi_dot, theta_dot, psi_dot) of the body rates (p, q, r) from the sines
/// and cosines of phi and theta (any scalar; singular at cos(theta) = 0):
///   phi_dot = p + tan(theta) (q sin(phi) + r cos(phi)), theta_dot = q cos(phi) - r sin(phi),
///   psi_dot = (q sin(phi) + r cos(phi)) / cos(theta).
template <class T>
[[nodiscard]] std::array<T, 3> euler_rates_from_body_rates_sc(const T& sphi, const T& cphi,
                                                              const T& sth, const T& cth,
                                                              const T& p, const T& q, const T& r) {
    const T inv_cth = 1.0 / cth;
    const T qs_rc = q * sphi + r * cphi;
    return {p + sth * qs_rc * inv_cth, q * cphi - r * sphi, qs_rc * inv_cth};
}

/// Body rates (p, q, r) of the Euler-angle rates from the sines and cosines of phi and theta
/// (any scalar): p = phi_dot - psi_dot sin(theta), q = theta_dot cos(phi) + psi_dot sin(phi)
/// cos(theta), r = psi_dot cos(phi) cos(theta) - theta_dot sin(phi).
template <class T>
[[nodiscard]] std::array<T, 3> body_rates_from_euler_rates_sc(const T& sphi, const T& cphi,
                                                              const T& sth, const T& cth,
                                                              const T& phi_dot, const T& theta_dot,
                                                              const T& psi_dot) {
    return {phi_dot - psi_dot * sth, theta_dot * cphi + psi_dot * sphi * cth,
            psi_dot * cphi * cth - theta_dot * sphi};
}

}  // namespace manta::core
