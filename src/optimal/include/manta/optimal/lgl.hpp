#pragma once
/// @file lgl.hpp
/// Legendre–Gauss–Lobatto (LGL) points, quadrature weights, differentiation matrix and
/// barycentric Lagrange interpolation on [-1, 1] (docs/optimal-control.md#lgl).
///
/// With n = N - 1 the polynomial degree, the N LGL points are -1, +1 and the n - 1 roots of
/// P'_n; the weights are w_j = 2 / (n (n + 1) P_n(x_j)^2) and the quadrature is exact for
/// polynomials of degree 2N - 3; D_ij = P_n(x_i) / (P_n(x_j) (x_i - x_j)) for i != j is exact for
/// polynomials of degree n. Stable to several hundred points.

#include <Eigen/Core>

namespace manta::optimal {

/// Legendre polynomial P_n(x) and its derivative P'_n(x) by the three-term recurrence.
struct LegendreValue {
    double p = 0.0;    ///< P_n(x)
    double dp = 0.0;   ///< P'_n(x)
    double pm1 = 0.0;  ///< P_{n-1}(x)
};
/// P_n, P'_n and P_{n-1} at x (n >= 0; P'_n at x = ±1 by its closed form).
[[nodiscard]] LegendreValue legendre(int n, double x);

/// The LGL rule of N points.
struct LglRule {
    Eigen::VectorXd points;           ///< x_0 = -1 < x_1 < ... < x_{N-1} = 1, symmetric
    Eigen::VectorXd weights;          ///< quadrature weights, sum 2
    Eigen::VectorXd barycentric;      ///< barycentric interpolation weights (scaled 1 / P_n(x_j))
    Eigen::MatrixXd differentiation;  ///< D (N x N): (D f)_i = p'(x_i) for the interpolant p
    [[nodiscard]] int size() const { return static_cast<int>(points.size()); }
};

/// The LGL rule of `n_points` >= 2 points: interior points by Newton's method on
/// (1 - x^2) P'_n(x) started from the Chebyshev–Gauss–Lobatto points, symmetric by
/// construction; diagonal of D by the negative-sum rule (rows of D sum to zero).
/// Throws InputError for n_points < 2.
[[nodiscard]] LglRule lgl_rule(int n_points);

/// Row vector of Lagrange basis values ell_j(x) at x for `points` with barycentric weights
/// `bary` (second barycentric formula; exact 0/1 at the points themselves).
[[nodiscard]] Eigen::RowVectorXd lagrange_basis(const Eigen::VectorXd& points,
                                                const Eigen::VectorXd& bary, double x);

}  // namespace manta::optimal
