#pragma once
/// @file atmosphere.hpp
/// U.S. Standard Atmosphere 1976 (NOAA/NASA/USAF, NOAA-S/T 76-1562, Washington DC, 1976), the
/// seven layers of the lower atmosphere up to 84.852 km geopotential (86 km geometric).
/// Templated on the scalar so derivatives follow the layer of each call.

#include <array>
#include <cmath>

#include "manta/core/error.hpp"
#include "manta/core/scalar.hpp"

namespace manta::flightdyn {

/// Air properties at one altitude (SI).
template <class T>
struct AtmosphereState {
    T temperature{0.0};         ///< [K]
    T pressure{0.0};            ///< [Pa]
    T density{0.0};             ///< [kg/m^3]
    T speed_of_sound{0.0};      ///< [m/s]
    T dynamic_viscosity{0.0};   ///< [Pa s] (Sutherland's law, as in the 1976 standard)
    T geopotential_altitude{0.0};  ///< [m']
};

namespace us1976 {
inline constexpr double earth_radius = 6356766.0;    ///< r0 [m], for geopotential altitude
inline constexpr double g0 = 9.80665;                ///< [m/s^2]
inline constexpr double gas_constant = 287.0528742;  ///< R* / M0 [J/(kg K)] = 8314.32 / 28.9644
inline constexpr double gamma = 1.4;
inline constexpr double sutherland_beta = 1.458e-6;  ///< [kg/(s m K^1/2)]
inline constexpr double sutherland_s = 110.4;        ///< [K]
/// Layer bases: geopotential altitude [m'], temperature [K], lapse rate [K/m'], pressure [Pa].
struct Layer {
    double h_base;
    double t_base;
    double lapse;
    double p_base;
};
inline constexpr std::array<Layer, 7> layers = {{
    {0.0, 288.15, -0.0065, 101325.0},
    {11000.0, 216.65, 0.0, 22632.0559},
    {20000.0, 216.65, 0.0010, 5474.88867},
    {32000.0, 228.65, 0.0028, 868.018685},
    {47000.0, 270.65, 0.0, 110.906306},
    {51000.0, 270.65, -0.0028, 66.9388731},
    {71000.0, 214.65, -0.0020, 3.95642043},
}};
inline constexpr double h_top = 84852.0;     ///< top of the model [m']
inline constexpr double h_bottom = -5000.0;  ///< lowest altitude accepted [m']
}  // namespace us1976

/// Geopotential altitude [m'] from geometric altitude [m].
template <class T>
[[nodiscard]] T geopotential_from_geometric(const T& z) {
    return us1976::earth_radius * z / (us1976::earth_radius + z);
}

/// Geometric altitude [m] from geopotential altitude [m'].
template <class T>
[[nodiscard]] T geometric_from_geopotential(const T& h) {
    return us1976::earth_radius * h / (us1976::earth_radius - h);
}

/// Atmosphere at geopotential altitude `h` [m'], -5 km <= h <= 84.852 km (InputError outside).
template <class T>
[[nodiscard]] AtmosphereState<T> us1976_geopotential(const T& h) {
    using std::exp;
    using std::pow;
    using std::sqrt;
    const double hv = core::value_of(h);
    if (!(hv >= us1976::h_bottom && hv <= us1976::h_top)) {
        throw InputError("atmosphere: geopotential altitude " + std::to_string(hv) +
                         " m is outside the US Standard Atmosphere 1976 range [-5000, 84852] m");
    }
    std::size_t i = 0;
    while (i + 1 < us1976::layers.size() && hv >= us1976::layers[i + 1].h_base) ++i;
    const auto& L = us1976::layers[i];
    constexpr double gmr = us1976::g0 / us1976::gas_constant;  // g0 M0 / R*
    AtmosphereState<T> a;
    a.geopotential_altitude = h;
    const T dh = h - L.h_base;
    if (L.lapse == 0.0) {
        a.temperature = T(0.0) * dh + L.t_base;
        a.pressure = L.p_base * exp(-gmr * dh / L.t_base);
    } else {
        a.temperature = L.t_base + L.lapse * dh;
        a.pressure = L.p_base * pow(T(a.temperature / L.t_base), -gmr / L.lapse);
    }
    a.density = a.pressure / (us1976::gas_constant * a.temperature);
    a.speed_of_sound = sqrt(T(us1976::gamma * us1976::gas_constant * a.temperature));
    a.dynamic_viscosity =
        us1976::sutherland_beta * a.temperature * sqrt(a.temperature) / (a.temperature + us1976::sutherland_s);
    return a;
}

/// Atmosphere at geometric altitude `z` [m] (flight altitude).
template <class T>
[[nodiscard]] AtmosphereState<T> us1976(const T& z) {
    return us1976_geopotential(geopotential_from_geometric(z));
}

}  // namespace manta::flightdyn
