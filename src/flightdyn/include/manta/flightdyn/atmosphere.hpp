#pragma once
/// @file atmosphere.hpp
/// U.S. Standard Atmosphere 1976 (NOAA/NASA/USAF, NOAA-S/T 76-1562, Washington DC, 1976), the
/// seven layers of the lower atmosphere up to 84.852 km geopotential (86 km geometric).
/// Templated on the scalar so derivatives follow the layer of each call.

#include <array>
#include <cmath>
#include <type_traits>

#include "manta/core/error.hpp"
#include "manta/core/scalar.hpp"

namespace manta::flightdyn {

/// Air properties at one altitude (SI).
template <class T>
struct AtmosphereState {
    T temperature{0.0};            ///< [K]
    T pressure{0.0};               ///< [Pa]
    T density{0.0};                ///< [kg/m^3]
    T speed_of_sound{0.0};         ///< [m/s]
    T dynamic_viscosity{0.0};      ///< [Pa s] (Sutherland's law, as in the 1976 standard)
    T geopotential_altitude{0.0};  ///< [m']
    /// ln(sigma), sigma = density / us1976_constants::reference_density: the density ratio of
    /// engine lapse laws, whose power sigma^n = exp(n ln sigma) then needs no logarithm.
    T log_density_ratio{0.0};
};

namespace us1976_constants {
inline constexpr double earth_radius = 6356766.0;          ///< r0 [m], for geopotential altitude
inline constexpr double g0 = 9.80665;                      ///< [m/s^2]
inline constexpr double universal_gas_constant = 8314.32;  ///< R* [J/(kmol K)] (the 1976 value)
inline constexpr double molar_mass = 28.9644;  ///< M0 [kg/kmol], sea-level mean molecular weight
inline constexpr double gas_constant =
    universal_gas_constant / molar_mass;  ///< R* / M0 = 287.05312 J/(kg K)
inline constexpr double gamma = 1.4;
inline constexpr double sutherland_beta = 1.458e-6;  ///< [kg/(s m K^1/2)]
inline constexpr double sutherland_s = 110.4;        ///< [K]
/// Layer bases: geopotential altitude [m'], temperature [K], lapse rate [K/m'], pressure [Pa].
/// The base pressures are each layer's formula evaluated at its top in double precision (so the
/// profile is continuous to rounding); printed in the standard as 22632.06, 5474.889, 868.0187,
/// 110.9063, 66.93887 and 3.956420 Pa.
struct Layer {
    double h_base;
    double t_base;
    double lapse;
    double p_base;
};
inline constexpr std::array<Layer, 7> layers = {{
    {0.0, 288.15, -0.0065, 101325.0},
    {11000.0, 216.65, 0.0, 22632.06397346291},
    {20000.0, 216.65, 0.0010, 5474.888669677774},
    {32000.0, 228.65, 0.0028, 868.0186847552278},
    {47000.0, 270.65, 0.0, 110.9063055549659},
    {51000.0, 270.65, -0.0028, 66.93887311868727},
    {71000.0, 214.65, -0.0020, 3.956420428040725},
}};
inline constexpr double h_top = 84852.0;     ///< top of the model [m']
inline constexpr double h_bottom = -5000.0;  ///< lowest altitude accepted [m']
/// Sea-level density as the standard prints it [kg/m^3]: the reference of density ratios.
inline constexpr double reference_density = 1.225;
}  // namespace us1976_constants

namespace detail {
/// ln(sigma) at each layer base, ln(p_base / (R T_base rho_ref)) (computed once).
[[nodiscard]] inline const std::array<double, us1976_constants::layers.size()>&
us1976_log_sigma_base() {
    static const auto table = [] {
        std::array<double, us1976_constants::layers.size()> c{};
        for (std::size_t i = 0; i < c.size(); ++i) {
            const auto& L = us1976_constants::layers[i];
            c[i] = std::log(L.p_base / (us1976_constants::gas_constant * L.t_base *
                                        us1976_constants::reference_density));
        }
        return c;
    }();
    return table;
}
}  // namespace detail

/// Geopotential altitude [m'] from geometric altitude [m].
template <class T>
[[nodiscard]] T geopotential_from_geometric(const T& z) {
    return us1976_constants::earth_radius * z / (us1976_constants::earth_radius + z);
}

/// Geometric altitude [m] from geopotential altitude [m'].
template <class T>
[[nodiscard]] T geometric_from_geopotential(const T& h) {
    return us1976_constants::earth_radius * h / (us1976_constants::earth_radius - h);
}

/// Atmosphere at geopotential altitude `h` [m'], -5 km <= h <= 84.852 km (InputError outside).
template <class T>
[[nodiscard]] AtmosphereState<T> us1976_geopotential(const T& h) {
    using std::exp;
    using std::pow;
    using std::sqrt;
    const double hv = core::value_of(h);
    if (!(hv >= us1976_constants::h_bottom && hv <= us1976_constants::h_top)) {
        throw InputError("atmosphere: geopotential altitude " + std::to_string(hv) +
                         " m is outside the US Standard Atmosphere 1976 range [-5000, 84852] m");
    }
    std::size_t i = 0;
    while (i + 1 < us1976_constants::layers.size() && hv >= us1976_constants::layers[i + 1].h_base)
        ++i;
    const auto& L = us1976_constants::layers[i];
    constexpr double gmr = us1976_constants::g0 / us1976_constants::gas_constant;  // g0 M0 / R*
    AtmosphereState<T> a;
    a.geopotential_altitude = h;
    const T dh = h - L.h_base;
    if constexpr (std::is_same_v<T, double>) {
        // The same formulas with a shorter chain of dependent operations: theta^k is
        // exp(k ln theta), within about (1 + |k ln theta|) ulp of std::pow (|k ln theta| < 3
        // over every layer of the model), and ln(sigma) follows from the same logarithm,
        // rho / rho_ref = (rho_base / rho_ref) theta^(k - 1), for the engine lapse.
        const double log_sigma_base = detail::us1976_log_sigma_base()[i];
        if (L.lapse == 0.0) {
            const double x = -gmr * dh / L.t_base;  // ln(p / p_base) = ln(sigma / sigma_base)
            a.temperature = L.t_base;
            a.pressure = L.p_base * std::exp(x);
            a.log_density_ratio = log_sigma_base + x;
        } else {
            const double k = -gmr / L.lapse;
            a.temperature = L.t_base + L.lapse * dh;
            const double log_theta = std::log(a.temperature / L.t_base);
            a.pressure = L.p_base * std::exp(k * log_theta);
            a.log_density_ratio = log_sigma_base + (k - 1.0) * log_theta;
        }
        a.density = a.pressure / (us1976_constants::gas_constant * a.temperature);
    } else {
        using std::log;
        if (L.lapse == 0.0) {
            a.temperature = T(0.0) * dh + L.t_base;
            a.pressure = L.p_base * exp(-gmr * dh / L.t_base);
        } else {
            a.temperature = L.t_base + L.lapse * dh;
            a.pressure = L.p_base * pow(T(a.temperature / L.t_base), -gmr / L.lapse);
        }
        a.density = a.pressure / (us1976_constants::gas_constant * a.temperature);
        a.log_density_ratio = log(T(a.density / us1976_constants::reference_density));
    }
    a.speed_of_sound =
        sqrt(T(us1976_constants::gamma * us1976_constants::gas_constant * a.temperature));
    a.dynamic_viscosity = us1976_constants::sutherland_beta * a.temperature * sqrt(a.temperature) /
                          (a.temperature + us1976_constants::sutherland_s);
    return a;
}

/// Atmosphere at geometric altitude `z` [m] (flight altitude).
template <class T>
[[nodiscard]] AtmosphereState<T> us1976(const T& z) {
    return us1976_geopotential(geopotential_from_geometric(z));
}

}  // namespace manta::flightdyn
