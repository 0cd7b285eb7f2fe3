// Legendre–Gauss–Lobatto rule: symmetry, quadrature exactness (degree 2N - 3), exact
// differentiation of polynomials of degree N - 1, stability to several hundred points.
// Reference properties: Canuto, Hussaini, Quarteroni & Zang, "Spectral Methods: Fundamentals in
// Single Domains", 2006, section 2.2.3 (LGL formulas).

#include <gtest/gtest.h>

#include <cmath>

#include "manta/core/error.hpp"
#include "manta/optimal/lgl.hpp"

namespace {

using namespace manta::optimal;

class LglRuleTest : public ::testing::TestWithParam<int> {};

TEST_P(LglRuleTest, PointsAreSymmetricSortedAndRootsOfLegendreDerivative) {
    const int N = GetParam();
    const LglRule r = lgl_rule(N);
    ASSERT_EQ(r.size(), N);
    EXPECT_EQ(r.points(0), -1.0);
    EXPECT_EQ(r.points(N - 1), 1.0);
    for (int j = 0; j < N; ++j) {
        EXPECT_EQ(r.points(j), -r.points(N - 1 - j)) << j;
        EXPECT_DOUBLE_EQ(r.weights(j), r.weights(N - 1 - j)) << j;
        if (j > 0) {
            EXPECT_GT(r.points(j), r.points(j - 1));
        }
        if (j > 0 && j < N - 1) {
            // residual of P'_n at an interior point, relative to the size of P'_n nearby
            const LegendreValue L = legendre(N - 1, r.points(j));
            const double size = 0.5 * N * N;  // |P'_n| <= n(n+1)/2
            EXPECT_LT(std::abs(L.dp) / size, 1e-12) << "N " << N << " point " << j;
        }
    }
    EXPECT_NEAR(r.weights.sum(), 2.0, 1e-13);
    EXPECT_NEAR(r.weights(0), 2.0 / (N * (N - 1.0)), 1e-15);
}

TEST_P(LglRuleTest, QuadratureIsExactToDegree2NMinus3) {
    const int N = GetParam();
    const LglRule r = lgl_rule(N);
    for (int k = 0; k <= 2 * N - 3; ++k) {
        const double exact = k % 2 == 1 ? 0.0 : 2.0 / (k + 1.0);
        double q = 0.0;
        for (int j = 0; j < N; ++j) q += r.weights(j) * std::pow(r.points(j), k);
        EXPECT_NEAR(q, exact, 1e-13) << "N " << N << " degree " << k;
    }
    // degree 2N - 2 is not integrated exactly (the order is sharp): the rule gives 2/n for
    // the integral of P_n^2, which is 2/(2n + 1)
    const int n = N - 1;
    double q = 0.0;
    for (int j = 0; j < N; ++j) q += r.weights(j) * std::pow(legendre(n, r.points(j)).p, 2);
    EXPECT_NEAR(q, 2.0 / n, 1e-12 * N);
}

TEST_P(LglRuleTest, DifferentiationIsExactToDegreeNMinus1) {
    const int N = GetParam();
    const LglRule r = lgl_rule(N);
    const int n = N - 1;
    // monomials are badly conditioned at high degree: use Legendre polynomials P_k, whose
    // derivatives are known from the recurrence, bounded by k(k+1)/2
    for (int k = 0; k <= n; ++k) {
        Eigen::VectorXd f(N), df(N);
        for (int j = 0; j < N; ++j) {
            const LegendreValue L = legendre(k, r.points(j));
            f(j) = L.p;
            df(j) = L.dp;
        }
        const Eigen::VectorXd d = r.differentiation * f;
        const double scale = 0.5 * k * (k + 1.0) + 1.0;
        EXPECT_LT((d - df).cwiseAbs().maxCoeff() / scale, 5e-14 * N * N)
            << "N " << N << " degree " << k;
    }
    EXPECT_LT((r.differentiation * Eigen::VectorXd::Ones(N)).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_NEAR(r.differentiation(0, 0), -0.25 * n * (n + 1.0), 1e-9 * N * N);
    EXPECT_NEAR(r.differentiation(N - 1, N - 1), 0.25 * n * (n + 1.0), 1e-9 * N * N);
}

TEST_P(LglRuleTest, LagrangeInterpolationReproducesPolynomials) {
    const int N = GetParam();
    const LglRule r = lgl_rule(N);
    const int k = N - 1;
    Eigen::VectorXd f(N);
    for (int j = 0; j < N; ++j) f(j) = legendre(k, r.points(j)).p;
    for (const double x : {-0.999, -0.37, 0.0, 0.123456, 0.8, 1.0}) {
        const double p = lagrange_basis(r.points, r.barycentric, x) * f;
        EXPECT_NEAR(p, legendre(k, x).p, 1e-12 * N) << "N " << N << " x " << x;
    }
}

INSTANTIATE_TEST_SUITE_P(Sizes, LglRuleTest, ::testing::Values(2, 3, 4, 5, 10, 41, 80, 200, 301));

TEST(LglRule, RejectsFewerThanTwoPoints) {
    EXPECT_THROW((void)lgl_rule(1), manta::InputError);
}

TEST(LglRule, KnownFivePointRule) {
    // N = 5: points 0, ±sqrt(3/7), ±1; weights 32/45, 49/90, 1/10 (Abramowitz & Stegun 25.4.32)
    const LglRule r = lgl_rule(5);
    EXPECT_NEAR(r.points(3), std::sqrt(3.0 / 7.0), 1e-15);
    EXPECT_NEAR(r.weights(2), 32.0 / 45.0, 1e-15);
    EXPECT_NEAR(r.weights(1), 49.0 / 90.0, 1e-15);
    EXPECT_NEAR(r.weights(0), 0.1, 1e-15);
}

}  // namespace
