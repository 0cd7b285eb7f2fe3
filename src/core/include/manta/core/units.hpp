#pragma once
/// @file units.hpp
/// Physical constants and the unit conversions used at MANTA's edges (user files, published
/// data in US customary units). Inside MANTA everything is SI and radians.

#include <numbers>

namespace manta::core {

inline constexpr double pi = std::numbers::pi;
inline constexpr double deg_to_rad = pi / 180.0;
inline constexpr double rad_to_deg = 180.0 / pi;

/// Standard gravity g0 [m/s^2] (US Standard Atmosphere 1976; CGPM 1901).
inline constexpr double standard_gravity = 9.80665;

// Exact definitions of the international foot and pound (1959).
inline constexpr double foot = 0.3048;                                ///< [m]
inline constexpr double pound_mass = 0.45359237;                      ///< [kg]
inline constexpr double pound_force = pound_mass * standard_gravity;  ///< [N]
inline constexpr double slug = pound_force / foot;                    ///< [kg] = 14.5939...
inline constexpr double slug_ft2 = slug * foot * foot;                ///< [kg m^2]
inline constexpr double slug_per_ft3 = slug / (foot * foot * foot);   ///< [kg/m^3]
inline constexpr double psf = pound_force / (foot * foot);            ///< lbf/ft^2 [Pa]
inline constexpr double rankine = 5.0 / 9.0;                          ///< [K]

[[nodiscard]] constexpr double deg(double degrees) noexcept {
    return degrees * deg_to_rad;
}

}  // namespace manta::core
