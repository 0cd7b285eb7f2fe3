#pragma once
/// @file gas.hpp
/// Flow states of the Euler solver (docs/euler.md).
///
/// The solver works in non-dimensional variables: free-stream density 1 and free-stream speed of
/// sound 1, so the free-stream pressure is 1/gamma and the free-stream speed is the Mach number;
/// lengths stay in metres (the mesh's unit). Conservative state U = (rho, rho u, rho v, rho w,
/// rho E); primitive state W = (rho, u, v, w, p); calorically perfect gas,
/// p = (gamma - 1) (rho E - rho |u|^2 / 2).

#include <Eigen/Core>
#include <cmath>

#include "manta/core/frames.hpp"

namespace manta::euler {

/// Number of conserved variables.
inline constexpr int n_vars = 5;

using Vec3 = Eigen::Vector3d;
using Vec5 = Eigen::Matrix<double, 5, 1>;
using Mat5 = Eigen::Matrix<double, 5, 5>;
/// One state per node, column n for node n (node-major in memory: 5 contiguous values per node).
using NodeStates = Eigen::Matrix<double, 5, Eigen::Dynamic>;

/// Conservative state from primitive (rho, u, v, w, p).
[[nodiscard]] inline Vec5 conservative(const Vec5& W, double gamma) noexcept {
    const double rho = W[0];
    const double ke = 0.5 * rho * (W[1] * W[1] + W[2] * W[2] + W[3] * W[3]);
    Vec5 U;
    U << rho, rho * W[1], rho * W[2], rho * W[3], W[4] / (gamma - 1.0) + ke;
    return U;
}

/// Primitive state (rho, u, v, w, p) from conservative.
[[nodiscard]] inline Vec5 primitive(const Vec5& U, double gamma) noexcept {
    const double rho = U[0];
    const double inv = 1.0 / rho;
    const double u = U[1] * inv, v = U[2] * inv, w = U[3] * inv;
    Vec5 W;
    W << rho, u, v, w, (gamma - 1.0) * (U[4] - 0.5 * rho * (u * u + v * v + w * w));
    return W;
}

/// Speed of sound of a primitive state.
[[nodiscard]] inline double sound_speed(const Vec5& W, double gamma) noexcept {
    return std::sqrt(gamma * W[4] / W[0]);
}

/// Unit free-stream direction in the mesh axes for angle of attack `alpha` and sideslip `beta`
/// [rad]. Mesh axes: x downstream (aft), y toward the right wing, z up (the body axes turned
/// 180 deg about y), so the direction is (cos a cos b, -sin b, sin a cos b): positive sideslip
/// is wind from the right, as in flight mechanics. (SU2 writes +sin b for the y component.)
[[nodiscard]] inline Vec3 free_stream_direction(double alpha, double beta) noexcept {
    return core::free_stream_geometry(alpha, beta);
}

/// Free-stream primitive state (1, M d, 1/gamma) in the solver's variables, d from
/// `free_stream_direction`.
[[nodiscard]] inline Vec5 free_stream(double mach, double alpha, double beta,
                                      double gamma) noexcept {
    const Vec3 d = mach * free_stream_direction(alpha, beta);
    Vec5 W;
    W << 1.0, d.x(), d.y(), d.z(), 1.0 / gamma;
    return W;
}

}  // namespace manta::euler
