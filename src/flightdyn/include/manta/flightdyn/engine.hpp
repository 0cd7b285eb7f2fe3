#pragma once
/// @file engine.hpp
/// Engine thrust T(h, M, throttle). Two models:
///  - `lapse`: T = throttle * T_sl * sigma^n * (1 + a1 M + a2 M^2), sigma = rho / rho_sl.
///    A density-ratio power law of the semi-empirical kind given by Roskam & Lan, *Airplane
///    Aerodynamics and Performance* (DARcorporation, 1997), ch. 7, for turbojets and turbofans,
///    with a Mach polynomial for ram and inlet effects. Defaults n = 0.7, a1 = -0.3, a2 = 0.15 for
///    a small-bypass-ratio turbofan; documented in docs/flight-dynamics.md.
///  - `table`: T(altitude, mach, throttle) by trilinear interpolation with linear extrapolation
///    (the Stevens & Lewis F-16 idle/military/maximum tables fit this form exactly).
/// Thrust acts along the body x axis rotated by `thrust_angle` (nose-up positive) through
/// `position` (geometry axes); the paper sets propulsive moments to zero (position at the CG).

#include <array>
#include <cmath>
#include <string>
#include <type_traits>
#include <vector>

#include "manta/core/scalar.hpp"

namespace manta::flightdyn {

struct EngineModel {
    enum class Type { lapse, table };
    Type type = Type::lapse;

    // lapse model
    double static_thrust_sl = 0.0;  ///< T_sl at full throttle, sea level, M = 0 [N]
    double density_exponent = 0.7;  ///< n
    double mach_a1 = -0.3;
    double mach_a2 = 0.15;

    // table model: thrust[(i_alt * n_mach + i_mach) * n_throttle + i_throttle] [N]
    std::vector<double> altitude;  ///< [m], increasing
    std::vector<double> mach;      ///< increasing
    std::vector<double> throttle;  ///< increasing, within [0, 1]
    std::vector<double> thrust;

    double thrust_angle = 0.0;  ///< [rad] thrust line above body x (nose-up positive)
    bool has_position = false;  ///< false: thrust acts through the CG (no moment)
    std::array<double, 3> position{0.0, 0.0, 0.0};  ///< point of action, geometry axes [m]

    /// Thrust [N] at geometric altitude h [m], Mach M, throttle in [0, 1], density ratio sigma.
    template <class T>
    [[nodiscard]] T thrust_at(const T& h, const T& M, const T& throttle_setting,
                              const T& sigma) const;
    /// The same with ln(sigma) known as well (AtmosphereState::log_density_ratio): for double the
    /// lapse law's sigma^n is then exp(n ln sigma), without a logarithm; other scalars use sigma.
    template <class T>
    [[nodiscard]] T thrust_at(const T& h, const T& M, const T& throttle_setting, const T& sigma,
                              const T& log_sigma) const;

    /// Validate sizes and monotonicity; InputError naming `where`.
    void validate(const std::string& where) const;
};

namespace detail {
/// Bracketing cell and linear weight along a sorted axis with linear extrapolation.
inline std::size_t cell_of(const std::vector<double>& axis, double x) {
    if (axis.size() < 2) return 0;
    std::size_t i = 0;
    while (i + 2 < axis.size() && x >= axis[i + 1]) ++i;
    return i;
}
}  // namespace detail

template <class T>
T EngineModel::thrust_at(const T& h, const T& M, const T& throttle_setting, const T& sigma,
                         const T& log_sigma) const {
    if constexpr (std::is_same_v<T, double>) {
        if (type == Type::lapse) {
            // sigma^n as exp(n ln sigma): within about (1 + |n ln sigma|) ulp of std::pow (2 to 3
            // ulp below 15 km), and one exponential instead of a power.
            return throttle_setting * static_thrust_sl * std::exp(density_exponent * log_sigma) *
                   (1.0 + mach_a1 * M + mach_a2 * M * M);
        }
    } else {
        (void)log_sigma;
    }
    return thrust_at(h, M, throttle_setting, sigma);
}

template <class T>
T EngineModel::thrust_at(const T& h, const T& M, const T& throttle_setting, const T& sigma) const {
    using std::pow;
    if (type == Type::lapse) {
        return throttle_setting * static_thrust_sl * pow(sigma, density_exponent) *
               (1.0 + mach_a1 * M + mach_a2 * M * M);
    }
    // Trilinear with linear extrapolation.
    const std::vector<double>* ax[3] = {&altitude, &mach, &throttle};
    const T x[3] = {h, M, throttle_setting};
    std::size_t i0[3];
    T w[3];
    for (int k = 0; k < 3; ++k) {
        const auto& a = *ax[k];
        if (a.size() < 2) {
            i0[k] = 0;
            w[k] = T(0.0);
            continue;
        }
        i0[k] = detail::cell_of(a, core::value_of(x[k]));
        w[k] = (x[k] - a[i0[k]]) / (a[i0[k] + 1] - a[i0[k]]);
    }
    const std::size_t nm = mach.size(), nt = throttle.size();
    T result = T(0.0) * h;
    for (int c = 0; c < 8; ++c) {
        T weight = T(1.0) + T(0.0) * h;
        std::size_t idx[3];
        bool skip = false;
        for (int k = 0; k < 3; ++k) {
            const int bit = (c >> k) & 1;
            if (ax[k]->size() < 2) {
                if (bit) skip = true;
                idx[k] = 0;
                continue;
            }
            idx[k] = i0[k] + static_cast<std::size_t>(bit);
            weight = weight * (bit ? w[k] : T(1.0 - w[k]));
        }
        if (skip) continue;
        result = result + weight * thrust[(idx[0] * nm + idx[1]) * nt + idx[2]];
    }
    return result;
}

}  // namespace manta::flightdyn
