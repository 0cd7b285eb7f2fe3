#pragma once
/// @file check.hpp
/// Private: the finite-difference derivative check of an NLP (a single-phase Transcription or
/// a MultiTranscription) at the starting point z, perturbed (check_derivatives, solve.hpp).

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "manta/optimal/solve.hpp"

namespace manta::optimal::detail {

template <class Tr>
DerivativeCheck check_nlp(Tr& tr, std::vector<double> z, double perturbation, unsigned seed) {
    const int n = tr.n_vars();
    const int m = tr.n_rows();
    std::vector<double> xl(n), xu(n), gl(m), gu(m);
    tr.bounds(xl.data(), xu.data(), gl.data(), gu.data());
    Eigen::VectorXd vs, rs;
    double os = 1.0;
    tr.scaling(z.data(), vs, rs, os);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    // Perturb every free variable, kept inside its bounds: a margin of 1e-3 of the interval
    // from a bound when both are finite, of 1e-3 of the variable's scale from a bound that is
    // alone (an absent bound is a sentinel of 1e20 here, and IPOPT takes 1e19 and beyond as none).
    for (int c = 0; c < n; ++c) {
        if (xl[c] == xu[c]) continue;
        const bool has_lo = xl[c] > -1e19, has_hi = xu[c] < 1e19;  // IPOPT: beyond 1e19 none
        const double margin =
            has_lo && has_hi ? 1e-3 * (xu[c] - xl[c]) : 1e-3 * std::max(vs(c), 1e-12);
        const double lo = has_lo ? xl[c] + margin : -kInf;
        const double hi = has_hi ? xu[c] - margin : kInf;
        z[c] =
            std::clamp(z[c] + perturbation * vs(c) * uni(rng), std::min(lo, hi), std::max(lo, hi));
    }
    DerivativeCheck res;
    res.n_variables = n;
    // analytic
    std::vector<double> grad(n), jac(tr.nnz_jacobian());
    std::vector<int> jr(tr.nnz_jacobian()), jc(tr.nnz_jacobian());
    tr.gradient(z.data(), grad.data());
    tr.jacobian(z.data(), jac.data());
    tr.jacobian_structure(jr.data(), jc.data());
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(m, n);
    for (std::size_t k = 0; k < jac.size(); ++k) J(jr[k], jc[k]) += jac[k];
    std::vector<double> lambda(m);
    for (auto& l : lambda) l = uni(rng) / std::max(1e-12, 1.0);
    for (int r = 0; r < m; ++r) lambda[r] /= rs(r);
    const double sigma = 1.0 / os;
    std::vector<double> hv(tr.nnz_hessian());
    std::vector<int> hr(tr.nnz_hessian()), hc(tr.nnz_hessian());
    tr.hessian(z.data(), sigma, lambda.data(), hv.data());
    tr.hessian_structure(hr.data(), hc.data());
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
    for (std::size_t k = 0; k < hv.size(); ++k) {
        H(hr[k], hc[k]) += hv[k];
        if (hr[k] != hc[k]) H(hc[k], hr[k]) += hv[k];
    }
    // Lagrangian gradient sigma grad f + J^T lambda at a point
    auto lag_grad = [&](std::vector<double>& zz) {
        std::vector<double> g(n), jj(tr.nnz_jacobian());
        tr.gradient(zz.data(), g.data());
        tr.jacobian(zz.data(), jj.data());
        Eigen::VectorXd out = Eigen::Map<Eigen::VectorXd>(g.data(), n) * sigma;
        for (std::size_t k = 0; k < jj.size(); ++k) out(jc[k]) += lambda[jr[k]] * jj[k];
        return out;
    };
    std::vector<double> gp(m), gm(m);
    for (int c = 0; c < n; ++c) {
        const double h = 1e-6 * vs(c);
        std::vector<double> zp = z, zm = z;
        zp[c] += h;
        zm[c] -= h;
        const double fd_f = (tr.objective(zp.data()) - tr.objective(zm.data())) / (2.0 * h);
        res.gradient_error = std::max(res.gradient_error, std::abs(grad[c] - fd_f) * vs(c) / os /
                                                              (1.0 + std::abs(fd_f) * vs(c) / os));
        tr.constraints(zp.data(), gp.data());
        tr.constraints(zm.data(), gm.data());
        for (int r = 0; r < m; ++r) {
            const double fd = (gp[r] - gm[r]) / (2.0 * h) * vs(c) / rs(r);
            const double an = J(r, c) * vs(c) / rs(r);
            const double e = std::abs(an - fd) / (1.0 + std::abs(fd));
            if (e > res.jacobian_error) {
                res.jacobian_error = e;
                res.worst_row = r;
                res.worst_col = c;
            }
        }
        const Eigen::VectorXd lp = lag_grad(zp);
        const Eigen::VectorXd lm = lag_grad(zm);
        for (int r = 0; r < n; ++r) {
            const double fd = (lp(r) - lm(r)) / (2.0 * h) * vs(c) * vs(r);
            const double an = H(r, c) * vs(c) * vs(r);
            res.hessian_error =
                std::max(res.hessian_error, std::abs(an - fd) / (1.0 + std::abs(fd)));
        }
    }
    return res;
}

}  // namespace manta::optimal::detail
