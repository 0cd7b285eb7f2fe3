/// @file dense_lu.cpp
/// The dense LU factorisation of the vortex-lattice solvers (detail/dense_lu.hpp).

#include "manta/vlm/detail/dense_lu.hpp"

#include <fmt/format.h>

#include <utility>

#include "manta/core/error.hpp"
#include "manta/vlm/detail/kernels.hpp"

namespace manta::vlm::detail {

void DenseLU::compute(Eigen::MatrixXd a) {
    single_ = false;
    luf_.clear();
    af_.resize(0, 0);
    n_ = a.rows();
    lu_.assign(a.data(), static_cast<std::size_t>(a.size()));
    a.resize(0, 0);
    perm_.resize(static_cast<std::size_t>(n_));
    kernels().lu_factor(lu_.data(), n_, perm_.data());
}

void DenseLU::compute_single(Eigen::MatrixXf a) {
    const Eigen::Index n = a.rows();
    lu_.clear();
    n_ = n;
    luf_.assign(a.data(), static_cast<std::size_t>(a.size()));
    perm_.resize(static_cast<std::size_t>(n));
    kernels().lu_factor_f(luf_.data(), n, perm_.data());
    af_ = std::move(a);
    single_ = true;
    // Probe: the error of one single-precision solve of A x = A 1 is the factor by which each
    // refinement step reduces the error.
    const Eigen::VectorXd ones = Eigen::VectorXd::Ones(n);
    Eigen::VectorXd b(n);
    kernels().gemm_fd(af_.data(), n, n, ones.data(), 1, b.data());
    Eigen::VectorXf xf = b.cast<float>();
    kernels().lu_solve_f(luf_.data(), n, perm_.data(), xf.data(), 1);
    const double err = (xf.cast<double>() - ones).cwiseAbs().maxCoeff();
    if (!(err <= 1e-3)) {
        Eigen::MatrixXd ad = af_.cast<double>();
        compute(std::move(ad));
    }
}

Eigen::MatrixXd DenseLU::solve(Eigen::MatrixXd b, double tolerance) const {
    const Eigen::Index n = rows(), k = b.cols();
    if (!single_) {
        kernels().lu_solve(lu_.data(), n, perm_.data(), b.data(), k);
        return b;
    }
    Eigen::MatrixXf df = b.cast<float>();
    kernels().lu_solve_f(luf_.data(), n, perm_.data(), df.data(), k);
    Eigen::MatrixXd x = df.cast<double>();
    Eigen::MatrixXd ax(n, k);
    for (int step = 0;; ++step) {
        kernels().gemm_fd(af_.data(), n, n, x.data(), k, ax.data());
        df = (b - ax).cast<float>();
        kernels().lu_solve_f(luf_.data(), n, perm_.data(), df.data(), k);
        bool done = true;
        for (Eigen::Index c = 0; c < k; ++c) {
            const auto dmax = static_cast<double>(df.col(c).cwiseAbs().maxCoeff());
            x.col(c) += df.col(c).cast<double>();
            if (dmax > tolerance * x.col(c).cwiseAbs().maxCoeff()) done = false;
        }
        if (done) break;
        if (step == 9)
            throw NumericalError(
                fmt::format("vlm: iterative refinement of a {} x {} single-precision LU solve did "
                            "not reach a relative correction of {} in 10 steps",
                            n, n, tolerance));
    }
    return x;
}

Eigen::MatrixXd DenseLU::solve_unrefined(Eigen::MatrixXd b) const {
    const Eigen::Index n = rows(), k = b.cols();
    if (!single_) {
        kernels().lu_solve(lu_.data(), n, perm_.data(), b.data(), k);
        return b;
    }
    Eigen::MatrixXf df = b.cast<float>();
    kernels().lu_solve_f(luf_.data(), n, perm_.data(), df.data(), k);
    return df.cast<double>();
}

Eigen::VectorXd DenseLU::solve(Eigen::VectorXd b) const {
    const Eigen::MatrixXd x = solve(Eigen::MatrixXd(std::move(b)));
    return x.col(0);
}

}  // namespace manta::vlm::detail
