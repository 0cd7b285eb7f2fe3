#pragma once
/// @file scalar.hpp
/// Helpers that let physics code be written once for `double` and for automatic-differentiation
/// scalars (Eigen::AutoDiffScalar). Branch decisions (table cell, atmosphere layer) are taken on
/// `value_of(x)`; the arithmetic stays in the scalar type so derivatives follow the branch taken.

#include <type_traits>

namespace manta::core {

/// Plain value of a scalar: identity for arithmetic types.
template <class T>
requires std::is_arithmetic_v<T>
[[nodiscard]] constexpr double value_of(T x) noexcept {
    return static_cast<double>(x);
}

/// Plain value of an expression-template or AD scalar that exposes `.value()`.
template <class T>
requires(!std::is_arithmetic_v<T>) && requires(const T& t) {
    t.value();
}
[[nodiscard]] double value_of(const T& x) {
    return value_of(x.value());
}

}  // namespace manta::core
