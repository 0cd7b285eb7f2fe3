#pragma once
/// @file kriging_linalg.hpp
/// Private dense kernels of the Kriging likelihood: in-place Cholesky factorisation and the
/// inverse of a symmetric positive-definite matrix from its Cholesky factor.

#include <Eigen/Dense>

namespace manta::surrogate::detail {

/// Cholesky factorisation A = L L^T in place: reads the lower triangle of `a` (the strict upper
/// triangle is ignored and may hold anything), writes L there. False if `a` is not numerically
/// positive definite.
[[nodiscard]] bool cholesky_in_place(Eigen::MatrixXd& a);

/// Lower triangle (with the diagonal) of (L L^T)^-1 from the lower-triangular factor L; the strict
/// upper triangle of `inverse` is unspecified.
void inverse_from_cholesky(const Eigen::MatrixXd& L, Eigen::MatrixXd& inverse);

}  // namespace manta::surrogate::detail
