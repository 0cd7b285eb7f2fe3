#pragma once
/// @file dense_lu.hpp
/// Private: a dense LU factorisation with partial pivoting through the kernel set of this
/// processor (detail/kernels.hpp), for the influence matrices of the steady and unsteady solvers.

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "manta/vlm/detail/kernels.hpp"

namespace manta::vlm::detail {

class DenseLU {
public:
    /// Factorise `a` (square), keeping it as the factors.
    void compute(Eigen::MatrixXd a) {
        lu_ = std::move(a);
        perm_.resize(static_cast<std::size_t>(lu_.rows()));
        kernels().lu_factor(lu_.data(), lu_.rows(), perm_.data());
    }
    [[nodiscard]] Eigen::Index rows() const { return lu_.rows(); }
    /// X with A X = B (B: rows() x k).
    [[nodiscard]] Eigen::MatrixXd solve(Eigen::MatrixXd b) const {
        kernels().lu_solve(lu_.data(), lu_.rows(), perm_.data(), b.data(), b.cols());
        return b;
    }
    [[nodiscard]] Eigen::VectorXd solve(Eigen::VectorXd b) const {
        kernels().lu_solve(lu_.data(), lu_.rows(), perm_.data(), b.data(), 1);
        return b;
    }

private:
    Eigen::MatrixXd lu_;
    std::vector<int> perm_;
};

}  // namespace manta::vlm::detail
