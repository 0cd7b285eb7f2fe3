// core::sin_cos against the library sine and cosine (and, where long double is wider than double,
// against a long double reference): within one ulp over the kernel range, the reduced range
// (quadrant boundaries, near multiples of pi/2, negative arguments) and at the special values.

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "manta/core/fastmath.hpp"

namespace {

using manta::core::sin_cos;

/// Doubles mapped to integers in the same order (-0 and +0 both to 0): ulps between two values.
std::int64_t ordered(double a) {
    const auto i = std::bit_cast<std::int64_t>(a);
    return i < 0 ? std::numeric_limits<std::int64_t>::min() - i : i;
}
std::int64_t ulps(double a, double b) {
    return std::abs(ordered(a) - ordered(b));
}

constexpr bool wide_long_double = std::numeric_limits<long double>::digits >= 64;

/// Error of `got` in ulps of the reference value `ref` (fractional; long double reference).
double ulp_error(double got, long double ref) {
    const double r = static_cast<double>(ref);
    const double ulp =
        std::nextafter(std::abs(r), std::numeric_limits<double>::infinity()) - std::abs(r);
    return static_cast<double>(std::abs(static_cast<long double>(got) - ref) / ulp);
}

struct Worst {
    std::int64_t vs_library = 0;  ///< integer ulps from std::sin / std::cos
    double vs_reference = 0.0;    ///< fractional ulps from the long double reference
    double at = 0.0;
};

void check(double x, Worst& w) {
    double s = 0.0, c = 0.0;
    sin_cos(x, s, c);
    const std::int64_t lib = std::max(ulps(s, std::sin(x)), ulps(c, std::cos(x)));
    if (lib > w.vs_library) {
        w.vs_library = lib;
        w.at = x;
    }
    if constexpr (wide_long_double) {
        const long double xl = x;
        w.vs_reference =
            std::max({w.vs_reference, ulp_error(s, std::sin(xl)), ulp_error(c, std::cos(xl))});
    }
}

}  // namespace

TEST(FastSinCos, WithinOneUlpOverTheReducedRange) {
    std::mt19937_64 rng(2024);
    for (const double limit : {std::numbers::pi / 4, 2.0, 7.0, 100.0, 1e4, 1e5}) {
        SCOPED_TRACE("|x| < " + std::to_string(limit));
        std::uniform_real_distribution<double> u(-limit, limit);
        Worst w;
        for (int n = 0; n < 200000; ++n) check(u(rng), w);
        EXPECT_LE(w.vs_library, 1) << "at x = " << w.at;
        if constexpr (wide_long_double) {
            EXPECT_LT(w.vs_reference, 1.0);
        }
    }
}

TEST(FastSinCos, QuadrantBoundariesAndNearMultiplesOfHalfPi) {
    // Around k pi/4 (where the reduction changes quadrant or kernel) and k pi/2 (where the
    // reduced argument cancels to tiny values and the extended reduction takes over).
    Worst w;
    for (int k = -127324; k <= 127324; k += (std::abs(k) < 200 ? 1 : 97)) {
        const double x0 = k * (std::numbers::pi / 4);
        if (!(std::abs(x0) <= manta::core::sin_cos_reduction_limit)) continue;
        double x = x0;
        for (int j = 0; j < 8; ++j) x = std::nextafter(x, -1e300);
        for (int j = 0; j < 17; ++j) {
            check(x, w);
            x = std::nextafter(x, 1e300);
        }
    }
    EXPECT_LE(w.vs_library, 1) << "at x = " << w.at;
    if constexpr (wide_long_double) {
        EXPECT_LT(w.vs_reference, 1.0);
    }
    // Arguments nearest multiples of pi/2 give tiny results that must keep full relative accuracy.
    for (const double x :
         {std::numbers::pi / 2, -std::numbers::pi / 2, std::numbers::pi, -std::numbers::pi,
          3 * std::numbers::pi / 2, 2 * std::numbers::pi, 1e5 * std::numbers::pi / 2 / 1.0000001}) {
        double s = 0.0, c = 0.0;
        sin_cos(x, s, c);
        EXPECT_LE(ulps(s, std::sin(x)), 1) << x;
        EXPECT_LE(ulps(c, std::cos(x)), 1) << x;
    }
}

TEST(FastSinCos, SpecialValuesAndTheLibraryBeyondTheLimit) {
    const double inf = std::numeric_limits<double>::infinity();
    for (const double x : {0.0, -0.0, 1e-300, -1e-300, 5e-324, 0x1p-27, -0x1p-28, 1e-9, -1e-9}) {
        double s = 1.0, c = 0.0;
        sin_cos(x, s, c);
        EXPECT_EQ(s, std::sin(x)) << x;
        EXPECT_EQ(c, std::cos(x)) << x;
        EXPECT_EQ(std::signbit(s), std::signbit(x)) << x;
    }
    // Beyond the inline reduction: exactly the library values.
    for (const double x : {1.0000001e5, -3e5, 1e9, -1e22, 1e300, std::nextafter(1e5, inf)}) {
        double s = 0.0, c = 0.0;
        sin_cos(x, s, c);
        EXPECT_EQ(s, std::sin(x)) << x;
        EXPECT_EQ(c, std::cos(x)) << x;
    }
    for (const double x : {std::numeric_limits<double>::quiet_NaN(), inf, -inf}) {
        double s = 0.0, c = 0.0;
        sin_cos(x, s, c);
        EXPECT_TRUE(std::isnan(s) && std::isnan(c)) << x;
    }
    // The reduced range up to the limit itself, and symmetry: sin odd, cos even.
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0.0, manta::core::sin_cos_reduction_limit);
    for (int n = 0; n < 10000; ++n) {
        const double x = n == 0 ? manta::core::sin_cos_reduction_limit : u(rng);
        double s1 = 0.0, c1 = 0.0, s2 = 0.0, c2 = 0.0;
        sin_cos(x, s1, c1);
        sin_cos(-x, s2, c2);
        EXPECT_EQ(s1, -s2) << x;
        EXPECT_EQ(c1, c2) << x;
    }
}
