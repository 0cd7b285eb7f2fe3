#pragma once
/// @file frames.hpp
/// The frames of docs/conventions.md and the conversions between them, written once for every
/// module (flightdyn, vlm, euler, replay, report, manoeuvres, the CLI):
///  - geometry axes (x aft, y right, z up; aircraft files, VLM lattices, CFD meshes) and body
///    axes (x forward, y right, z down) differ by a rotation of 180 deg about y:
///    (x, y, z)_body = (-x, y, -z)_geometry. The rotation is proper, so it applies alike to
///    positions, forces, moments and angular rates, and it is its own inverse;
///  - the 3-2-1 Euler angles (psi yaw, theta pitch, phi roll) from a reference frame (earth, or
///    the frame moving with the entry free stream of a motion file) to body axes:
///    v_body = C v_frame, C = R1(phi) R2(theta) R3(psi) (Stevens, Lewis & Johnson 2015,
///    eq. 1.3-20), and the unit quaternion (q0 scalar) of the same rotation;
///  - the Euler-angle rates and the body rates p, q, r (Stevens, Lewis & Johnson 2015,
///    eq. 1.4-4 and its inverse);
///  - the aircraft velocity in body axes from airspeed, angle of attack and sideslip.
/// The forms of any scalar that take the angles' sines and cosines (`_sc`) are in
/// frames_scalar.hpp, included here.

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>

#include "manta/core/frames_scalar.hpp"

namespace manta::core {

// ----------------------------------------------------------------- geometry <-> body

/// Vector (position, force, moment, angular rate) from geometry axes (x aft, y right, z up) to
/// body axes (x forward, y right, z down): x and z change sign.
[[nodiscard]] inline Eigen::Vector3d body_from_geometry(const Eigen::Vector3d& g) {
    return {-g.x(), g.y(), -g.z()};
}

/// Vector from body axes to geometry axes (the same rotation: it is its own inverse).
[[nodiscard]] inline Eigen::Vector3d geometry_from_body(const Eigen::Vector3d& b) {
    return {-b.x(), b.y(), -b.z()};
}

/// The matrix D of body_from_geometry, diag(-1, 1, -1) (D = D^T = D^-1), for composing rotations
/// (v_body = D v_geometry).
[[nodiscard]] inline Eigen::Matrix3d dcm_body_from_geometry() {
    return Eigen::Vector3d(-1.0, 1.0, -1.0).asDiagonal();
}

// ----------------------------------------------------------------- 3-2-1 Euler angles

/// C_body_from_earth of 3-2-1 Euler angles [rad]: v_body = C v_earth.
[[nodiscard]] inline Eigen::Matrix3d dcm_body_from_earth(double phi, double theta, double psi) {
    const Matrix33<double> c =
        dcm_body_from_earth_sc(std::sin(phi), std::cos(phi), std::sin(theta), std::cos(theta),
                               std::sin(psi), std::cos(psi));
    Eigen::Matrix3d C;
    C << c[0][0], c[0][1], c[0][2], c[1][0], c[1][1], c[1][2], c[2][0], c[2][1], c[2][2];
    return C;
}

/// The same of an angle triple (phi, theta, psi).
[[nodiscard]] inline Eigen::Matrix3d dcm_body_from_earth(const std::array<double, 3>& euler) {
    return dcm_body_from_earth(euler[0], euler[1], euler[2]);
}

/// C_earth_from_body = C_body_from_earth^T of 3-2-1 Euler angles [rad]: v_earth = C v_body.
[[nodiscard]] inline Eigen::Matrix3d dcm_earth_from_body(double phi, double theta, double psi) {
    return dcm_body_from_earth(phi, theta, psi).transpose();
}

/// The principal 3-2-1 angles (phi, theta, psi) of C_body_from_earth: theta in [-pi/2, pi/2],
/// phi and psi in [-pi, pi]. At theta = +-90 deg only phi -+ psi is defined; this returns the
/// pair atan2 gives.
[[nodiscard]] inline std::array<double, 3> euler_from_dcm(const Eigen::Matrix3d& C) {
    const double theta = std::asin(std::clamp(-C(0, 2), -1.0, 1.0));
    return {std::atan2(C(1, 2), C(2, 2)), theta, std::atan2(C(0, 1), C(0, 0))};
}

/// C_earth_from_body of a unit quaternion (q0 scalar; Stevens, Lewis & Johnson 2015,
/// eq. 1.8-16); the caller normalises q.
[[nodiscard]] inline Eigen::Matrix3d dcm_earth_from_unit_quaternion(const Eigen::Vector4d& q) {
    const Matrix33<double> c = dcm_earth_from_quaternion_sc(q[0], q[1], q[2], q[3], 1.0);
    Eigen::Matrix3d C;
    C << c[0][0], c[0][1], c[0][2], c[1][0], c[1][1], c[1][2], c[2][0], c[2][1], c[2][2];
    return C;
}

/// C_earth_from_body of a quaternion of any non-zero norm (normalised first).
[[nodiscard]] inline Eigen::Matrix3d dcm_earth_from_quaternion(const Eigen::Vector4d& q) {
    return dcm_earth_from_unit_quaternion(q / q.norm());
}

// ----------------------------------------------------------------- angle rates

/// Body rates (p, q, r) [rad/s] of 3-2-1 Euler angles [rad] and their rates [rad/s].
[[nodiscard]] inline std::array<double, 3> body_rates_from_euler_rates(
    const std::array<double, 3>& euler, const std::array<double, 3>& euler_rates) {
    return body_rates_from_euler_rates_sc(std::sin(euler[0]), std::cos(euler[0]),
                                          std::sin(euler[1]), std::cos(euler[1]), euler_rates[0],
                                          euler_rates[1], euler_rates[2]);
}

/// Euler-angle rates [rad/s] of 3-2-1 Euler angles [rad] and body rates (p, q, r) [rad/s].
[[nodiscard]] inline std::array<double, 3> euler_rates_from_body_rates(
    const std::array<double, 3>& euler, const std::array<double, 3>& body_rates) {
    return euler_rates_from_body_rates_sc(std::sin(euler[0]), std::cos(euler[0]),
                                          std::sin(euler[1]), std::cos(euler[1]), body_rates[0],
                                          body_rates[1], body_rates[2]);
}

// ----------------------------------------------------------------- wind -> body

/// Aircraft velocity relative to the air in body axes at airspeed V, angle of attack alpha and
/// sideslip beta [rad]: (V cos(alpha) cos(beta), V sin(beta), V sin(alpha) cos(beta)).
[[nodiscard]] inline Eigen::Vector3d air_velocity_body(double V, double alpha, double beta) {
    return {V * std::cos(alpha) * std::cos(beta), V * std::sin(beta),
            V * std::sin(alpha) * std::cos(beta)};
}

/// Unit direction of the free stream (the air's velocity relative to the aircraft) in geometry
/// axes: geometry_from_body(-air_velocity_body(1, alpha, beta)) = (cos(alpha) cos(beta),
/// -sin(beta), sin(alpha) cos(beta)); positive sideslip is wind from the right.
[[nodiscard]] inline Eigen::Vector3d free_stream_geometry(double alpha, double beta) {
    return {std::cos(alpha) * std::cos(beta), -std::sin(beta), std::sin(alpha) * std::cos(beta)};
}

}  // namespace manta::core
