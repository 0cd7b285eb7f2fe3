/// @file test_design.cpp
/// Designs of experiments: Latin property, maximin improvement, determinism, full factorial,
/// unit-cube maps.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "manta/core/error.hpp"
#include "manta/surrogate/design.hpp"

namespace ms = manta::surrogate;

namespace {

/// True if each column has exactly one point in each of the n strata [i/n, (i+1)/n).
bool is_latin(const ms::Matrix& x) {
    const auto n = x.rows();
    for (Eigen::Index k = 0; k < x.cols(); ++k) {
        std::vector<int> count(static_cast<std::size_t>(n), 0);
        for (Eigen::Index i = 0; i < n; ++i) {
            const double v = x(i, k);
            if (!(v > 0.0 && v < 1.0)) return false;
            const auto s = static_cast<Eigen::Index>(std::floor(v * static_cast<double>(n)));
            if (s < 0 || s >= n || ++count[static_cast<std::size_t>(s)] != 1) return false;
        }
    }
    return true;
}

}  // namespace

TEST(LatinHypercube, EveryColumnHasOnePointPerStratum) {
    for (int n : {1, 2, 7, 65}) {
        for (int dim : {1, 3, 5}) {
            EXPECT_TRUE(is_latin(ms::latin_hypercube(n, dim, 42, 0))) << n << "x" << dim;
            EXPECT_TRUE(is_latin(ms::latin_hypercube(n, dim, 42, 500))) << n << "x" << dim;
        }
    }
}

TEST(LatinHypercube, MaximinOptimisationIncreasesMinimumDistance) {
    // Averaged over seeds: the optimised designs must beat the random ones clearly, and each
    // optimised design must be at least as good as its own starting design.
    for (auto [n, dim] : {std::pair{20, 2}, std::pair{65, 3}, std::pair{30, 5}}) {
        double plain = 0.0, optimised = 0.0;
        for (std::uint64_t seed = 1; seed <= 5; ++seed) {
            const double d0 = ms::min_distance(ms::latin_hypercube(n, dim, seed, 0));
            const double d1 = ms::min_distance(ms::latin_hypercube(n, dim, seed, 5000));
            EXPECT_GE(d1, d0) << n << "x" << dim << " seed " << seed;
            plain += d0;
            optimised += d1;
        }
        EXPECT_GT(optimised, 1.3 * plain) << n << "x" << dim;
    }
}

TEST(LatinHypercube, DeterministicPerSeed) {
    const ms::Matrix a = ms::latin_hypercube(30, 4, 7, 1000);
    const ms::Matrix b = ms::latin_hypercube(30, 4, 7, 1000);
    const ms::Matrix c = ms::latin_hypercube(30, 4, 8, 1000);
    EXPECT_EQ(a, b);
    EXPECT_NE(a, c);
}

TEST(LatinHypercube, RejectsBadSizes) {
    EXPECT_THROW((void)ms::latin_hypercube(0, 2, 1), manta::InputError);
    EXPECT_THROW((void)ms::latin_hypercube(5, 0, 1), manta::InputError);
    EXPECT_THROW((void)ms::latin_hypercube(5, 2, 1, -1), manta::InputError);
}

TEST(FullFactorial, CountsLevelsAndOrder) {
    const ms::Matrix x = ms::full_factorial({3, 1, 2});
    ASSERT_EQ(x.rows(), 6);
    ASSERT_EQ(x.cols(), 3);
    // Last dimension fastest.
    EXPECT_DOUBLE_EQ(x(0, 2), 0.0);
    EXPECT_DOUBLE_EQ(x(1, 2), 1.0);
    EXPECT_DOUBLE_EQ(x(0, 0), 0.0);
    EXPECT_DOUBLE_EQ(x(2, 0), 0.5);
    EXPECT_DOUBLE_EQ(x(5, 0), 1.0);
    for (Eigen::Index i = 0; i < 6; ++i) EXPECT_DOUBLE_EQ(x(i, 1), 0.5);  // one level: centre
    EXPECT_DOUBLE_EQ(ms::min_distance(x), 0.5);
    EXPECT_EQ(ms::full_factorial({5, 5, 5, 4}).rows(), 500);
    EXPECT_THROW((void)ms::full_factorial({3, 0}), manta::InputError);
    EXPECT_THROW((void)ms::full_factorial({}), manta::InputError);
}

TEST(MinDistance, SmallCases) {
    EXPECT_TRUE(std::isinf(ms::min_distance(ms::Matrix(1, 2))));
    ms::Matrix x(3, 2);
    x << 0, 0, 3, 4, 1, 1;
    EXPECT_DOUBLE_EQ(ms::min_distance(x), std::sqrt(2.0));
}

TEST(BoundsMaps, RoundTripAndCorners) {
    ms::Bounds b{ms::Vector(3), ms::Vector(3)};
    b.lower << -4.0 * std::numbers::pi / 180, 0.1, -8.0;
    b.upper << 12.0 * std::numbers::pi / 180, 0.6, 8.0;
    const ms::Matrix u = ms::latin_hypercube(17, 3, 3);
    const ms::Matrix x = ms::to_bounds(u, b);
    for (Eigen::Index i = 0; i < x.rows(); ++i)
        for (Eigen::Index k = 0; k < 3; ++k) {
            EXPECT_GE(x(i, k), b.lower[k]);
            EXPECT_LE(x(i, k), b.upper[k]);
        }
    EXPECT_LT((ms::to_unit(x, b) - u).cwiseAbs().maxCoeff(), 1e-15);
    const ms::Matrix corners = ms::to_bounds(ms::full_factorial({2, 2, 2}), b);
    EXPECT_EQ(corners.row(0), b.lower.transpose());
    EXPECT_LT((corners.row(7) - b.upper.transpose()).cwiseAbs().maxCoeff(), 1e-15);
    ms::Bounds bad = b;
    bad.upper[1] = bad.lower[1];
    EXPECT_THROW((void)ms::to_unit(x, bad), manta::InputError);
    EXPECT_THROW((void)ms::to_bounds(ms::Matrix(2, 2), b), manta::InputError);
}
