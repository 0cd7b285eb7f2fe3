#pragma once
/// @file autodiff.hpp
/// Forward-mode automatic differentiation scalar used across MANTA (Eigen's AutoDiffScalar with
/// a dynamic derivative vector). Physics templates instantiated with `core::Dual` give exact
/// first derivatives.

#include <Eigen/Core>
#include <unsupported/Eigen/AutoDiff>

#include "manta/core/scalar.hpp"

namespace manta::core {

/// AD scalar with a run-time number of directional derivatives.
using Dual = Eigen::AutoDiffScalar<Eigen::VectorXd>;

/// Independent variable `value` that is the `index`-th of `n` seeds.
[[nodiscard]] inline Dual make_dual(double value, Eigen::Index n, Eigen::Index index) {
    return Dual(value, Eigen::VectorXd::Unit(n, index));
}

/// Constant (zero derivative) with `n` derivative slots.
[[nodiscard]] inline Dual make_constant(double value, Eigen::Index n) {
    return Dual(value, Eigen::VectorXd::Zero(n));
}

}  // namespace manta::core
