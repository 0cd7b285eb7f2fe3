#pragma once
/// @file biot_savart.hpp
/// Private: velocities induced by straight vortex segments (Biot-Savart law), shared by the
/// steady and unsteady solvers. Unit circulation; multiply by Gamma.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

namespace manta::vlm::detail {

inline constexpr double inv_four_pi = 0.25 / std::numbers::pi;

/// Velocity at p of a segment from x1 to x2. Zero on the segment's line (where the induced
/// velocity is singular: a point on its own bound vortex) and for points within `core2` (squared
/// distance, relative to the squared length) of the line.
[[nodiscard]] inline Eigen::Vector3d segment(const Eigen::Vector3d& p, const Eigen::Vector3d& x1,
                                             const Eigen::Vector3d& x2, double core2 = 1e-12) {
    const Eigen::Vector3d r1 = p - x1;
    const Eigen::Vector3d r2 = p - x2;
    const Eigen::Vector3d c = r1.cross(r2);
    const double c2 = c.squaredNorm();
    const Eigen::Vector3d r0 = x2 - x1;
    const double l2 = r0.squaredNorm();
    if (c2 <= core2 * l2 * l2) return Eigen::Vector3d::Zero();
    const double n1 = r1.norm(), n2 = r2.norm();
    const double k = r0.dot(r1 / n1 - r2 / n2) * inv_four_pi / c2;
    return k * c;
}

/// Velocity at p of a semi-infinite segment from x1 to infinity along the unit vector d.
[[nodiscard]] inline Eigen::Vector3d semi_infinite(const Eigen::Vector3d& p,
                                                   const Eigen::Vector3d& x1,
                                                   const Eigen::Vector3d& d, double core2 = 1e-24) {
    const Eigen::Vector3d r1 = p - x1;
    const Eigen::Vector3d c = d.cross(r1);
    const double c2 = c.squaredNorm();
    const double n1 = r1.norm();
    if (c2 <= core2 || n1 == 0.0) return Eigen::Vector3d::Zero();
    return (inv_four_pi * (1.0 + d.dot(r1) / n1) / c2) * c;
}

/// Horseshoe of unit circulation: from infinity (along +x) to a, a to b, b to infinity.
[[nodiscard]] inline Eigen::Vector3d horseshoe(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                               const Eigen::Vector3d& b) {
    const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
    return segment(p, a, b) + semi_infinite(p, b, x) - semi_infinite(p, a, x);
}

}  // namespace manta::vlm::detail
