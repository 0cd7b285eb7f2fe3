/// @file design.cpp
/// Latin hypercubes with maximin optimisation (Morris & Mitchell 1995), full factorials, and the
/// maps between the unit cube and physical bounds.

#include "manta/surrogate/design.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "kriging_detail.hpp"
#include "manta/core/error.hpp"

namespace manta::surrogate {

namespace {

/// Exponent of the Morris-Mitchell criterion phi_p = (sum_{i<j} d_ij^-p)^(1/p); large p makes
/// phi_p rank designs like the maximin distance while staying smooth in every pair (p = 15 is
/// large enough and keeps d^-p within double range for any design of up to ~10^4 points).
constexpr double kPhiExponent = 15.0;

/// d^-p from the squared distance.
double inverse_power(double d2) {
    return std::pow(d2, -0.5 * kPhiExponent);
}

void check_bounds(const Bounds& b, Eigen::Index cols, const char* what) {
    if (b.lower.size() != b.upper.size())
        throw InputError(fmt::format("{}: bounds have {} lower and {} upper values; expected equal",
                                     what, b.lower.size(), b.upper.size()));
    if (b.lower.size() != cols)
        throw InputError(fmt::format("{}: points have {} columns, bounds {} dimensions", what, cols,
                                     b.lower.size()));
    for (Eigen::Index k = 0; k < b.lower.size(); ++k)
        if (!(b.lower[k] < b.upper[k]))
            throw InputError(
                fmt::format("{}: bounds of dimension {} are [{}, {}]; expected lower "
                            "< upper",
                            what, k, b.lower[k], b.upper[k]));
}

}  // namespace

Matrix latin_hypercube(int n, int dim, std::uint64_t seed, int iterations) {
    if (n < 1 || dim < 1)
        throw InputError(
            fmt::format("latin_hypercube: n = {}, dim = {}; expected both >= 1", n, dim));
    if (iterations < 0)
        throw InputError(
            fmt::format("latin_hypercube: iterations = {}; expected >= 0", iterations));
    detail::Rng rng(seed);
    // Points sit at the centres of the strata: (permutation + 1/2) / n in each column.
    Matrix x(n, dim);
    std::vector<int> perm(static_cast<std::size_t>(n));
    for (int k = 0; k < dim; ++k) {
        std::iota(perm.begin(), perm.end(), 0);
        for (int i = n - 1; i > 0; --i) std::swap(perm[i], perm[rng.index(i + 1)]);
        for (int i = 0; i < n; ++i) x(i, k) = (perm[i] + 0.5) / n;
    }
    if (n < 3 || iterations == 0) return x;

    // Greedy column exchanges: swap x(i, k) and x(j, k) (which keeps every column a Latin
    // permutation) and keep the swap when phi_p decreases. Only the distances from rows i and j
    // change, so each trial costs O(n dim).
    Matrix d2(n, n);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) d2(i, j) = (x.row(i) - x.row(j)).squaredNorm();
    Vector new_i(n), new_j(n);
    for (int it = 0; it < iterations; ++it) {
        const int k = rng.index(dim);
        const int i = rng.index(n);
        int j = rng.index(n - 1);
        if (j >= i) ++j;
        const double delta = x(j, k) - x(i, k);  // row i gains +delta in column k, row j -delta
        double before = 0.0, after = 0.0;
        for (int m = 0; m < n; ++m) {
            if (m == i || m == j) continue;
            const double ai = x(i, k) - x(m, k), aj = x(j, k) - x(m, k);
            new_i[m] = d2(i, m) - ai * ai + (ai + delta) * (ai + delta);
            new_j[m] = d2(j, m) - aj * aj + (aj - delta) * (aj - delta);
            before += inverse_power(d2(i, m)) + inverse_power(d2(j, m));
            after += inverse_power(new_i[m]) + inverse_power(new_j[m]);
        }
        if (!(after < before)) continue;
        std::swap(x(i, k), x(j, k));
        for (int m = 0; m < n; ++m) {
            if (m == i || m == j) continue;
            d2(i, m) = d2(m, i) = new_i[m];
            d2(j, m) = d2(m, j) = new_j[m];
        }
    }
    return x;
}

Matrix full_factorial(const std::vector<int>& levels) {
    if (levels.empty())
        throw InputError("full_factorial: no dimensions; expected >= 1 level count");
    Eigen::Index total = 1;
    for (std::size_t k = 0; k < levels.size(); ++k) {
        if (levels[k] < 1)
            throw InputError(fmt::format(
                "full_factorial: dimension {} has {} levels; expected >= 1", k, levels[k]));
        total *= levels[k];
    }
    const auto dim = static_cast<Eigen::Index>(levels.size());
    Matrix x(total, dim);
    for (Eigen::Index row = 0; row < total; ++row) {
        Eigen::Index rest = row;
        for (Eigen::Index k = dim - 1; k >= 0; --k) {  // last dimension varies fastest
            const int m = levels[static_cast<std::size_t>(k)];
            const Eigen::Index l = rest % m;
            rest /= m;
            x(row, k) = m == 1 ? 0.5 : static_cast<double>(l) / (m - 1);
        }
    }
    return x;
}

double min_distance(const Matrix& points) {
    double best = std::numeric_limits<double>::infinity();
    for (Eigen::Index i = 0; i < points.rows(); ++i)
        for (Eigen::Index j = i + 1; j < points.rows(); ++j)
            best = std::min(best, (points.row(i) - points.row(j)).squaredNorm());
    return std::sqrt(best);
}

Matrix to_bounds(const Matrix& unit, const Bounds& b) {
    check_bounds(b, unit.cols(), "to_bounds");
    const Eigen::RowVectorXd span = (b.upper - b.lower).transpose();
    return (unit.array().rowwise() * span.array()).rowwise() + b.lower.transpose().array();
}

Matrix to_unit(const Matrix& x, const Bounds& b) {
    check_bounds(b, x.cols(), "to_unit");
    const Eigen::RowVectorXd span = (b.upper - b.lower).transpose();
    return (x.rowwise() - b.lower.transpose()).array().rowwise() / span.array();
}

}  // namespace manta::surrogate
