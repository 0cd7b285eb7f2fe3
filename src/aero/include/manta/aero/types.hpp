#pragma once
/// @file types.hpp
/// Aerodynamic vocabulary shared by every aero source and by flight dynamics.
///
/// Axes (docs/conventions.md): body x forward, y right wing, z down. Force coefficients come in
/// two sets: wind axes (CL lift, CD drag, CY side force along the wind y axis) and body axes
/// (CX forward, CY right, CZ down). Moment coefficients Cl, Cm, Cn are always body axes about the
/// moment reference point, normalised by q S b, q S c, q S b. Angles in radians.

#include <array>
#include <cmath>

namespace manta::aero {

/// Inputs of an aerodynamic model at one instant. Rates are non-dimensional:
/// p_hat = p b / (2V), q_hat = q c / (2V), r_hat = r b / (2V), alpha_dot_hat = alpha_dot c / (2V),
/// beta_dot_hat = beta_dot b / (2V). Control deflections in radians with the paper's signs:
/// elevator trailing edge down +, aileron left trailing edge down + (right up), rudder trailing
/// edge toward the left wing +.
template <class T>
struct AeroQuery {
    T alpha{0.0};
    T beta{0.0};
    T mach{0.0};
    T p_hat{0.0};
    T q_hat{0.0};
    T r_hat{0.0};
    T alpha_dot_hat{0.0};
    T beta_dot_hat{0.0};
    T elevator{0.0};
    T aileron{0.0};
    T rudder{0.0};
};

/// Body-axis force and moment coefficients (moments about the moment reference point).
template <class T>
struct BodyCoefficients {
    T CX{0.0};
    T CY{0.0};
    T CZ{0.0};
    T Cl{0.0};
    T Cm{0.0};
    T Cn{0.0};
};

/// Wind-axis force coefficients.
template <class T>
struct WindForceCoefficients {
    T CL{0.0};
    T CD{0.0};
    T CY{0.0};
};

/// Body-axis force coefficients from wind-axis ones. With the wind axes of Stevens & Lewis:
/// x_w = (ca cb, sb, sa cb), y_w = (-ca sb, cb, -sa sb), z_w = (-sa, 0, ca) in body components,
/// F_body = -CD x_w + CY y_w - CL z_w.
template <class T>
[[nodiscard]] std::array<T, 3> body_from_wind(const T& CL, const T& CD, const T& CY, const T& alpha,
                                              const T& beta) {
    using std::cos;
    using std::sin;
    const T ca = cos(alpha), sa = sin(alpha), cb = cos(beta), sb = sin(beta);
    return {T(-CD * ca * cb - CY * ca * sb + CL * sa), T(-CD * sb + CY * cb),
            T(-CD * sa * cb - CY * sa * sb - CL * ca)};
}

/// Wind-axis force coefficients from body-axis ones (inverse of body_from_wind).
template <class T>
[[nodiscard]] WindForceCoefficients<T> wind_from_body(const T& CX, const T& CY, const T& CZ,
                                                      const T& alpha, const T& beta) {
    using std::cos;
    using std::sin;
    const T ca = cos(alpha), sa = sin(alpha), cb = cos(beta), sb = sin(beta);
    WindForceCoefficients<T> w;
    w.CD = -(CX * ca * cb + CY * sb + CZ * sa * cb);
    w.CY = -CX * ca * sb + CY * cb - CZ * sa * sb;
    w.CL = CX * sa - CZ * ca;
    return w;
}

}  // namespace manta::aero
