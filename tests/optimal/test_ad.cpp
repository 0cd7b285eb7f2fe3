// Forward-mode AD scalars: first and second derivatives against closed forms, branches followed
// at each evaluation, Eigen vector algebra.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "manta/core/scalar.hpp"
#include "manta/optimal/ad.hpp"
#include "manta/optimal/hyper.hpp"

namespace {

using namespace manta::optimal;
using AdHyper = Hyper<8>;

template <class T>
T f(const T& x, const T& y) {
    using std::atan2;
    using std::exp;
    using std::log;
    using std::pow;
    using std::sin;
    using std::sqrt;
    return sin(x) * y + pow(x, 3.0) + exp(x * y) + sqrt(y) / x + atan2(y, x) + log(y) * 2;
}

TEST(Ad, FirstAndSecondDerivativesMatchClosedForms) {
    const double x = 0.7;
    const double y = 1.3;
    const Ad1 a = f(Ad1::variable(x, 2, 0), Ad1::variable(y, 2, 1));
    const double fx = std::cos(x) * y + 3 * x * x + y * std::exp(x * y) - std::sqrt(y) / (x * x) -
                      y / (x * x + y * y);
    const double fy = std::sin(x) + x * std::exp(x * y) + 0.5 / (std::sqrt(y) * x) +
                      x / (x * x + y * y) + 2.0 / y;
    EXPECT_NEAR(a.value(), f(x, y), 1e-14);
    EXPECT_NEAR(a.derivative(0), fx, 1e-12);
    EXPECT_NEAR(a.derivative(1), fy, 1e-12);

    const Ad2 vx = Ad2::variable(Ad1::variable(x, 2, 0), 2, 0);
    const Ad2 vy = Ad2::variable(Ad1::variable(y, 2, 1), 2, 1);
    const Ad2 b = f(vx, vy);
    const double r2 = x * x + y * y;
    const double fxx = -std::sin(x) * y + 6 * x + y * y * std::exp(x * y) +
                       2 * std::sqrt(y) / (x * x * x) + 2 * x * y / (r2 * r2);
    const double fxy = std::cos(x) + std::exp(x * y) * (1 + x * y) - 0.5 / (std::sqrt(y) * x * x) +
                       (y * y - x * x) / (r2 * r2);
    EXPECT_NEAR(b.derivative(0).value(), fx, 1e-12);
    EXPECT_NEAR(b.derivative(0).derivative(0), fxx, 1e-11);
    EXPECT_NEAR(b.derivative(0).derivative(1), fxy, 1e-11);
    EXPECT_NEAR(b.derivative(1).derivative(0), fxy, 1e-11);
}

/// Every elementary function of the scalars, in three variables, with constants mixed in.
template <class T>
T g(const T& x, const T& y, const T& z) {
    using std::acos;
    using std::asin;
    using std::atan;
    using std::atan2;
    using std::cbrt;
    using std::cos;
    using std::cosh;
    using std::exp;
    using std::hypot;
    using std::log;
    using std::log10;
    using std::pow;
    using std::sin;
    using std::sinh;
    using std::sqrt;
    using std::tan;
    using std::tanh;
    T r = sin(x) * cos(y) + tan(0.3 * z) + asin(T(0.4 * x)) + acos(T(0.2 * y)) + atan(x * z);
    r += atan2(y, x) + atan2(2.0, z) + atan2(x, 1.5) + sinh(0.5 * y) + cosh(0.3 * z) + tanh(x);
    r += exp(x * y) / z + log(y) * log10(z) + sqrt(x * y * z) + cbrt(z + 1.0) + pow(x, 2.5);
    r += pow(y, 3) + pow(z, x) + pow(2.0, y) + hypot(x, z) + 3.0 / (x + y) - (2.0 - z) * x;
    T t = x;
    t *= y;
    t /= z;
    t += 1.0;
    t -= y;
    return r + t * t;
}

TEST(Ad, HyperGivesTheForwardOverForwardHessian) {
    // Hyper (packed symmetric Hessian) against Fwd<Fwd> on every elementary function
    const double v[3] = {0.7, 1.3, 0.9};
    Ad2 a2[3];
    AdHyper ah[3];
    for (int i = 0; i < 3; ++i) {
        a2[i] = Ad2::variable(Ad1::variable(v[i], 3, i), 3, i);
        ah[i] = AdHyper::variable(v[i], 3, i);
    }
    const Ad2 r2 = g(a2[0], a2[1], a2[2]);
    const AdHyper rh = g(ah[0], ah[1], ah[2]);
    EXPECT_NEAR(rh.value(), g(v[0], v[1], v[2]), 1e-13);
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(rh.gradient(i), r2.derivative(i).value(), 1e-12) << i;
        for (int j = 0; j < 3; ++j) {
            EXPECT_NEAR(rh.hessian(i, j), r2.derivative(i).derivative(j), 1e-11) << i << j;
        }
    }
    // a constant mixed with a function of fewer directions keeps zero rows
    const AdHyper c = AdHyper(2.0) * ah[0] + AdHyper::variable(1.0, 2, 1) * ah[0];
    EXPECT_DOUBLE_EQ(c.hessian(0, 1), 1.0);
    EXPECT_DOUBLE_EQ(c.hessian(2, 2), 0.0);
    EXPECT_DOUBLE_EQ(c.gradient(2), 0.0);
}

template <class T>
T piecewise(const T& x) {
    // a branch on the plain value: each evaluation follows its own piece
    return manta::core::value_of(x) < 1.0 ? T(2.0 * x) : T(x * x * 5.0);
}

TEST(Ad, BranchesAreFollowedAtEveryEvaluation) {
    EXPECT_DOUBLE_EQ(piecewise(Ad1::variable(0.5, 1, 0)).derivative(0), 2.0);
    EXPECT_DOUBLE_EQ(piecewise(Ad1::variable(2.0, 1, 0)).derivative(0), 20.0);
    EXPECT_DOUBLE_EQ(piecewise(Ad1::variable(0.25, 1, 0)).derivative(0), 2.0);
}

TEST(Ad, EigenVectorAlgebra) {
    using V3 = Eigen::Matrix<Ad1, 3, 1>;
    const Ad1 x = Ad1::variable(2.0, 1, 0);
    V3 a(x, Ad1(1.0), x * x);
    V3 b(Ad1(0.0), x, Ad1(3.0));
    const Ad1 n = a.cross(b).norm();
    // |a x b|^2 = (3 - x^3)^2 + 9 x^2 + x^4, at x = 2: 25 + 36 + 16 = 77
    EXPECT_NEAR(n.value(), std::sqrt(77.0), 1e-14);
    const double dn2 = 2 * (3 - 8.0) * (-12.0) + 18 * 2.0 + 4 * 8.0;  // d|.|^2/dx
    EXPECT_NEAR(n.derivative(0), dn2 / (2 * std::sqrt(77.0)), 1e-13);
    const V3 c = a * 2.0;
    EXPECT_DOUBLE_EQ(c(2).derivative(0), 8.0);
}

}  // namespace
