/// @file kriging_linalg.cpp
/// Dense kernels of the Kriging likelihood on top of Eigen's blocked products.
///
/// The inverse of R = L L^T costs n^3/3 + n^3/3 flops here (recursive triangular inversion, then
/// the recursive product L^-T L^-1 of LAPACK's dlauum) instead of the 2 n^3 of two triangular
/// solves with the identity: it is the dominant cost of each likelihood-gradient evaluation.

#include "kriging_linalg.hpp"

#include <cmath>

namespace manta::surrogate::detail {

namespace {

using Block = Eigen::Ref<Eigen::MatrixXd>;

/// Below this size the recursions use plain triangular solves and products.
constexpr Eigen::Index kLeaf = 32;

/// In-place inverse of the lower-triangular block `a` (strict upper part untouched).
///   [A 0; B C]^-1 = [A^-1 0; -C^-1 B A^-1  C^-1].
void invert_lower(Block a) {
    const Eigen::Index n = a.rows();
    if (n <= kLeaf) {
        Eigen::MatrixXd inv = Eigen::MatrixXd::Identity(n, n);
        a.triangularView<Eigen::Lower>().solveInPlace(inv);
        a.triangularView<Eigen::Lower>() = inv;
        return;
    }
    const Eigen::Index m = n / 2;
    invert_lower(a.topLeftCorner(m, m));
    invert_lower(a.bottomRightCorner(n - m, n - m));
    auto b = a.bottomLeftCorner(n - m, m);
    Eigen::MatrixXd t = -(a.bottomRightCorner(n - m, n - m).triangularView<Eigen::Lower>() * b);
    b.noalias() = t * a.topLeftCorner(m, m).triangularView<Eigen::Lower>();
}

/// In place: the lower triangle of U^T U for the lower-triangular block `a` = U.
///   U = [P 0; Q S]:  U^T U = [P^T P + Q^T Q, Q^T S; S^T Q, S^T S].
void lower_gram(Block a) {
    const Eigen::Index n = a.rows();
    if (n <= kLeaf) {
        const Eigen::MatrixXd u = a.triangularView<Eigen::Lower>();
        a.noalias() = u.transpose() * u;
        return;
    }
    const Eigen::Index m = n / 2;
    auto q = a.bottomLeftCorner(n - m, m);
    auto s = a.bottomRightCorner(n - m, n - m);
    const Eigen::MatrixXd sq = s.triangularView<Eigen::Lower>().transpose() * q;  // S^T Q
    lower_gram(a.topLeftCorner(m, m));
    // A full product (GEMM) rather than Eigen's rank update: twice the flops of the lower half
    // but faster, and the strict upper triangle of the block is scratch anyway.
    a.topLeftCorner(m, m).noalias() += q.transpose() * q;
    lower_gram(s);
    q = sq;
}

}  // namespace

bool cholesky_in_place(Eigen::MatrixXd& a) {
    Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(a);
    if (llt.info() != Eigen::Success) return false;
    for (Eigen::Index i = 0; i < a.rows(); ++i)
        if (!(a(i, i) > 0.0) || !std::isfinite(a(i, i))) return false;
    return true;
}

void inverse_from_cholesky(const Eigen::MatrixXd& L, Eigen::MatrixXd& inverse) {
    inverse = L;
    const Eigen::Index n = L.rows();
    invert_lower(inverse.block(0, 0, n, n));
    lower_gram(inverse.block(0, 0, n, n));
}

}  // namespace manta::surrogate::detail
