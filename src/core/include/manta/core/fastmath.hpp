#pragma once
/// @file fastmath.hpp
/// Inline elementary functions for the plain-double hot paths (equations of motion, aero tables),
/// accurate to about one ulp and several times cheaper than the library calls they replace:
///  - `sin_cos(x, s, c)`: sine and cosine of one angle. |x| <= pi/4: polynomial kernels alone;
///    pi/4 < |x| <= `sin_cos_reduction_limit`: Cody-Waite reduction by pi/2 (W. J. Cody and
///    W. Waite, *Software Manual for the Elementary Functions*, Prentice-Hall 1980) into a
///    head-tail pair, with an exact extended reduction where the argument nearly cancels a
///    multiple of pi/2; beyond, and for infinities and NaN, std::sin and std::cos.
/// Only `double` is handled here; templated physics code keeps std::sin/std::cos for other
/// scalars (automatic differentiation) and calls these under `if constexpr`.

#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace manta::core {

/// Largest |x| reduced inline by `sin_cos`; larger arguments go to std::sin and std::cos.
inline constexpr double sin_cos_reduction_limit = 1e5;

namespace fastmath_detail {

// Minimax polynomials of fdlibm's __kernel_sin and __kernel_cos (Sun Microsystems, 1993; freely
// distributable), error below one ulp on |x| <= pi/4.
inline constexpr double S1 = -1.66666666666666324348e-01, S2 = 8.33333333332248946124e-03,
                        S3 = -1.98412698298579493134e-04, S4 = 2.75573137070700676789e-06,
                        S5 = -2.50507602534068634195e-08, S6 = 1.58969099521155010221e-10;
inline constexpr double C1 = 4.16666666666666019037e-02, C2 = -1.38888888888741095749e-03,
                        C3 = 2.48015872894767294178e-05, C4 = -2.75573143513906633035e-07,
                        C5 = 2.08757232129817482790e-09, C6 = -1.13596475577881948265e-11;

/// pi/2 split into pieces of 33, 33, 33 and 53 significant bits: n * P1, n * P2 and n * P3 are
/// exact for |n| < 2^20, and P1 + P2 + P3 + P4 equals pi/2 to about 2^-152.
inline constexpr double P1 = 0x1.921fb544p+0;             // 1.57079632673412561417
inline constexpr double P2 = 0x1.0b4611a6p-34;            // 6.07710050630396597660e-11
inline constexpr double P3 = 0x1.3198a2ep-69;             // 2.02226624871116645580e-21
inline constexpr double P4 = 0x1.b839a252049c1p-104;      // 8.47842766036889956997e-32
inline constexpr double P2_tail = 0x1.0b4611a626331p-34;  // pi/2 - P1 to double precision
inline constexpr double two_over_pi = 0x1.45f306dc9c883p-1;
/// Adding and subtracting 1.5 * 2^52 rounds a double of magnitude below 2^51 to an integer
/// (in the default rounding mode), which then sits in the low bits of the sum's significand.
inline constexpr double round_shift = 0x1.8p52;

/// sin and cos of |x| <= pi/4.
inline void kernel(double x, double& s, double& c) noexcept {
    if (std::abs(x) < 0x1p-27) {
        // sin x = x and cos x = 1 to rounding (and the sign of a zero survives).
        s = x;
        c = 1.0;
        return;
    }
    const double z = x * x;
    const double rs = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)));
    s = x + z * x * (S1 + z * rs);
    const double z2 = z * z;
    const double rc = z * (C1 + z * (C2 + z * C3)) + z2 * z2 * (C4 + z * (C5 + z * C6));
    const double hz = 0.5 * z;
    const double w = 1.0 - hz;
    c = w + (((1.0 - w) - hz) + z * rc);
}

/// sin and cos of y0 + y1, |y0| <= pi/4 (plus rounding), |y1| <= ulp(y0): the kernels with the
/// first-order terms of the tail, sin(y0 + y1) = sin y0 + y1 cos y0 and
/// cos(y0 + y1) = cos y0 - y1 sin y0, with cos y0 ~ 1 - y0^2/2 and sin y0 ~ y0 in the tail terms.
inline void kernel_tail(double y0, double y1, double& s, double& c) noexcept {
    const double z = y0 * y0;
    const double v = z * y0;
    const double rs = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)));
    s = y0 + (v * (S1 + z * rs) + y1 * (1.0 - 0.5 * z));
    const double z2 = z * z;
    const double rc = z * (C1 + z * (C2 + z * C3)) + z2 * z2 * (C4 + z * (C5 + z * C6));
    const double hz = 0.5 * z;
    const double w = 1.0 - hz;
    c = w + (((1.0 - w) - hz) + (z * rc - y0 * y1));
}

/// a + b = s + e exactly (Knuth's two-sum, any magnitudes).
inline void two_sum(double a, double b, double& s, double& e) noexcept {
    s = a + b;
    const double bv = s - a;
    e = (a - (s - bv)) + (b - bv);
}

/// x - n pi/2 as y0 + y1 when the two-piece reduction cancels to |y0| < 2^-10: pi/2 to ~152 bits
/// (four pieces, the first three multiplied exactly) and exact two-sums.
[[gnu::noinline]] inline void reduce_extended(double x, double n, double& y0, double& y1) noexcept {
    const double r1 = x - n * P1;  // exact (Sterbenz: x and n P1 within a factor of two)
    double s1 = 0.0, e1 = 0.0, s2 = 0.0, e2 = 0.0;
    two_sum(r1, -(n * P2), s1, e1);
    two_sum(s1, -(n * P3), s2, e2);
    const double lo = (e1 + e2) - n * P4;
    y0 = s2 + lo;
    y1 = (s2 - y0) + lo;
}

/// Apply the quadrant q = n mod 4 of the reduction to sin and cos of the reduced argument:
/// (s, c) -> (s, c), (c, -s), (-s, -c), (-c, s) for q = 0, 1, 2, 3, without branches.
inline void quadrant(std::uint64_t q, double sr, double cr, double& s, double& c) noexcept {
    const std::uint64_t swap = -(q & 1u);  // all ones for odd quadrants
    const auto sb = std::bit_cast<std::uint64_t>(sr), cb = std::bit_cast<std::uint64_t>(cr);
    const std::uint64_t a = (sb & ~swap) | (cb & swap);
    const std::uint64_t b = (cb & ~swap) | (sb & swap);
    s = std::bit_cast<double>(a ^ ((q & 2u) << 62));
    c = std::bit_cast<double>(b ^ (((q + 1u) & 2u) << 62));
}

}  // namespace fastmath_detail

/// s = sin(x), c = cos(x), each within about one ulp of the correctly rounded value; the sign of
/// a zero argument is kept in s. NaN and infinities give NaN (through std::sin and std::cos).
inline void sin_cos(double x, double& s, double& c) noexcept {
    namespace d = fastmath_detail;
    const double ax = std::abs(x);
    if (ax <= std::numbers::pi / 4) {
        d::kernel(x, s, c);
        return;
    }
    if (!(ax <= sin_cos_reduction_limit)) [[unlikely]] {
        s = std::sin(x);
        c = std::cos(x);
        return;
    }
    const double t = x * d::two_over_pi + d::round_shift;
    const double n = t - d::round_shift;  // nearest integer to x 2/pi, |n| < 2^17
    const std::uint64_t q = std::bit_cast<std::uint64_t>(t) & 3u;  // n mod 4
    // x - n pi/2 with pi/2 = P1 + P2_tail (33 + 53 bits): x - n P1 is exact, and the result is
    // accurate to ~2^-70 absolute, ample unless the difference cancels to a tiny |y0|.
    const double r1 = x - n * d::P1;
    const double w = n * d::P2_tail;
    double y0 = r1 - w;
    double y1 = (r1 - y0) - w;
    if (std::abs(y0) < 0x1p-10) [[unlikely]] {
        d::reduce_extended(x, n, y0, y1);
    }
    double sr = 0.0, cr = 0.0;
    d::kernel_tail(y0, y1, sr, cr);
    d::quadrant(q, sr, cr, s, c);
}

}  // namespace manta::core
