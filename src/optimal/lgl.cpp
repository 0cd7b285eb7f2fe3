/// @file lgl.cpp
/// Legendre–Gauss–Lobatto rule (see lgl.hpp).

#include "manta/optimal/lgl.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "manta/core/error.hpp"

namespace manta::optimal {

LegendreValue legendre(int n, double x) {
    LegendreValue r;
    if (n == 0) {
        r.p = 1.0;
        r.pm1 = 0.0;
        r.dp = 0.0;
        return r;
    }
    double p0 = 1.0;
    double p1 = x;
    for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    r.p = p1;
    r.pm1 = p0;
    const double one_minus_x2 = 1.0 - x * x;
    if (one_minus_x2 == 0.0) {
        // P'_n(±1) = (±1)^(n-1) n (n + 1) / 2
        const double sign = (x > 0.0 || n % 2 == 1) ? 1.0 : -1.0;
        r.dp = sign * 0.5 * n * (n + 1.0);
    } else {
        r.dp = n * (p0 - x * p1) / one_minus_x2;
    }
    return r;
}

LglRule lgl_rule(int n_points) {
    if (n_points < 2) {
        throw InputError("LGL rule: " + std::to_string(n_points) +
                         " points requested, expected at least 2");
    }
    const int N = n_points;
    const int n = N - 1;  // polynomial degree
    LglRule rule;
    rule.points.resize(N);
    rule.points(0) = -1.0;
    rule.points(N - 1) = 1.0;
    // Newton on q(x) = (1 - x^2) P'_n(x) = n (P_{n-1} - x P_n), q'(x) = -n (n + 1) P_n(x);
    // only the right half is iterated, the left half is its mirror image (exact symmetry).
    for (int j = 1; j <= n / 2; ++j) {
        double x = std::cos(std::numbers::pi * j / n);  // CGL point, descending from +1
        for (int it = 0; it < 100; ++it) {
            const LegendreValue L = legendre(n, x);
            const double dx = (x * L.p - L.pm1) / ((n + 1.0) * L.p);
            x -= dx;
            if (std::abs(dx) < 1e-16) break;
        }
        rule.points(N - 1 - j) = x;
        rule.points(j) = -x;
    }
    if (n % 2 == 0) rule.points(n / 2) = 0.0;
    rule.weights.resize(N);
    rule.barycentric.resize(N);
    Eigen::VectorXd pn(N);
    for (int j = 0; j < N; ++j) {
        pn(j) = legendre(n, rule.points(j)).p;
        rule.weights(j) = 2.0 / (n * (n + 1.0) * pn(j) * pn(j));
        // the nodal polynomial is c (1 - x^2) P'_n with derivative -c n (n + 1) P_n at the points
        rule.barycentric(j) = 1.0 / pn(j);
    }
    rule.differentiation = Eigen::MatrixXd::Zero(N, N);
    for (int i = 0; i < N; ++i) {
        double sum = 0.0;
        for (int j = 0; j < N; ++j) {
            if (i == j) continue;
            const double d = pn(i) / (pn(j) * (rule.points(i) - rule.points(j)));
            rule.differentiation(i, j) = d;
            sum += d;
        }
        // negative-sum rule: exact differentiation of constants, smaller round-off
        // (Baltensperger & Trummer 2003); equals -n(n+1)/4, 0, ..., 0, n(n+1)/4 in exact arithmetic
        rule.differentiation(i, i) = -sum;
    }
    return rule;
}

Eigen::RowVectorXd lagrange_basis(const Eigen::VectorXd& points, const Eigen::VectorXd& bary,
                                  double x) {
    const Eigen::Index N = points.size();
    Eigen::RowVectorXd ell = Eigen::RowVectorXd::Zero(N);
    double den = 0.0;
    for (Eigen::Index j = 0; j < N; ++j) {
        const double dx = x - points(j);
        if (dx == 0.0) {
            ell.setZero();
            ell(j) = 1.0;
            return ell;
        }
        ell(j) = bary(j) / dx;
        den += ell(j);
    }
    return ell / den;
}

}  // namespace manta::optimal
