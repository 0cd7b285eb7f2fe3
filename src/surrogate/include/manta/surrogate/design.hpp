#pragma once
/// @file design.hpp
/// Designs of experiments on the unit hypercube [0, 1]^d, and the maps between the unit cube and
/// a box of physical bounds. A design is an Eigen matrix with one point per row.

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

namespace manta::surrogate {

using Matrix = Eigen::MatrixXd;  ///< points in rows, dimensions in columns
using Vector = Eigen::VectorXd;

/// Box [lower, upper] in each dimension (lower < upper).
struct Bounds {
    Vector lower;
    Vector upper;
    [[nodiscard]] Eigen::Index dim() const { return lower.size(); }
};

/// Latin hypercube of `n` points in [0, 1]^dim, optimised for the maximin distance (the smallest
/// pairwise distance is made as large as the optimisation finds, by element exchanges within
/// columns). Deterministic for a given seed. `iterations` = 0 gives a plain random LHS.
[[nodiscard]] Matrix latin_hypercube(int n, int dim, std::uint64_t seed, int iterations = 2000);

/// Full factorial design with levels[k] equally spaced levels (>= 1; one level = 0.5) in each
/// dimension k, last dimension fastest.
[[nodiscard]] Matrix full_factorial(const std::vector<int>& levels);

/// Smallest Euclidean distance between two rows (infinity for fewer than two rows).
[[nodiscard]] double min_distance(const Matrix& points);

/// Unit cube -> bounds and back, row by row.
[[nodiscard]] Matrix to_bounds(const Matrix& unit, const Bounds& b);
[[nodiscard]] Matrix to_unit(const Matrix& x, const Bounds& b);

}  // namespace manta::surrogate
