#pragma once
/// @file dense_lu.hpp
/// Private: a dense LU factorisation with partial pivoting through the kernel set of this
/// processor (detail/kernels.hpp), for the influence matrices of the steady and unsteady solvers:
/// in double precision, or in single precision with iterative refinement in double precision
/// (src/vlm/dense_lu.cpp).

#include <Eigen/Core>
#include <algorithm>
#include <cstdlib>
#include <memory>
#include <new>
#include <vector>

namespace manta::vlm::detail {

/// A copy of n values in storage aligned to 64 bytes (the widest vectors of the kernel sets).
/// Eigen's vector code in the kernels splits some loops by the alignment of the data, so the
/// same factors at another alignment could round differently; aligned factors keep the results
/// of repeated runs identical bit for bit (the unsteady solver's checkpoint tests).
template <typename T>
class AlignedCopy {
public:
    void assign(const T* src, std::size_t n) {
        const std::size_t bytes = (n * sizeof(T) + 63) / 64 * 64;
        p_.reset(static_cast<T*>(std::aligned_alloc(64, bytes > 0 ? bytes : 64)));
        if (!p_) throw std::bad_alloc();
        std::copy(src, src + n, p_.get());
    }
    void clear() { p_.reset(); }
    [[nodiscard]] T* data() { return p_.get(); }
    [[nodiscard]] const T* data() const { return p_.get(); }

private:
    struct Free {
        void operator()(T* p) const { std::free(p); }
    };
    std::unique_ptr<T[], Free> p_;
};

class DenseLU {
public:
    /// Factorise `a` (square) in double precision, keeping it as the factors.
    void compute(Eigen::MatrixXd a);

    /// Factorise the single-precision matrix `a` (square) in single precision (half the memory
    /// traffic and twice the vector width of `compute`), keeping `a` itself for the residuals of
    /// the iterative refinement in `solve`: the solutions are those of `a` to double precision.
    /// A probe solve (A x = A 1) measures how much one refinement step gains; where the
    /// single-precision factors reduce the error by less than a factor 1000 (an ill-conditioned
    /// matrix), `a` is factorised in double precision instead.
    void compute_single(Eigen::MatrixXf a);

    [[nodiscard]] Eigen::Index rows() const { return n_; }
    /// True when the factors are in single precision (`compute_single` kept them).
    [[nodiscard]] bool single_precision() const { return single_; }

    /// X with A X = B (B: rows() x k). With single-precision factors: X from the factors, then
    /// refinement steps X += LU^-1 (B - A X) with the residual in double precision until every
    /// column's correction is at most `tolerance` times the column's largest value (at most 10
    /// steps; NumericalError if they do not get there). Each step reduces the error by the
    /// probe's factor (at most 1e-3, typically 1e-5 for the lattices here), so the error left is
    /// at most 1e-3 `tolerance` (about 1e-13 with the default: 3 solves and 2 residuals for the
    /// Ranger 2000 and b737 lattices).
    [[nodiscard]] Eigen::MatrixXd solve(Eigen::MatrixXd b, double tolerance = 1e-8) const;
    [[nodiscard]] Eigen::VectorXd solve(Eigen::VectorXd b) const;
    /// X from the factors alone, without refinement (single-precision factors: relative error
    /// about the probe's factor, 1e-5 for the lattices here; double-precision factors: `solve`).
    [[nodiscard]] Eigen::MatrixXd solve_unrefined(Eigen::MatrixXd b) const;

private:
    Eigen::Index n_ = 0;
    AlignedCopy<double> lu_;  // double-precision factors (not single_), column-major
    Eigen::MatrixXf af_;      // the matrix (single_)
    AlignedCopy<float> luf_;  // its single-precision factors (single_), column-major
    std::vector<int> perm_;
    bool single_ = false;
};

}  // namespace manta::vlm::detail
