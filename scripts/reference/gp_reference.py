#!/usr/bin/python3
"""Reference values for MANTA's Kriging (tests/surrogate/test_kriging_reference_validation.cpp).

Two independent computations on fixed data and fixed hyper-parameters:

1. scikit-learn's GaussianProcessRegressor (Pedregosa et al., "Scikit-learn: Machine Learning in
   Python", JMLR 12, 2011; version 1.2.1 from Debian's python3-sklearn) with a fixed kernel
   ConstantKernel(c) * RBF(l) or ConstantKernel(c) * Matern(l, nu=2.5), optimizer=None,
   normalize_y=False and alpha = nugget * c: the posterior of a zero-mean process, which is MANTA's
   Trend::none. c is set to the concentrated-likelihood estimate sigma^2 = y^T R^-1 y / n, so that
   sklearn's log-marginal likelihood equals the concentrated log-likelihood and its predictive
   variance is sigma^2 (1 - r^T R^-1 r); MANTA's MSE adds sigma^2 * nugget (the variance of a new
   noisy observation), which the test adds back.
2. Generalised-least-squares ordinary and universal (linear-trend) Kriging written out with numpy
   (LU solves, not Cholesky): trend coefficients, sigma^2, concentrated log-likelihood, mean and
   MSE sigma^2 (1 + nugget - r^T R^-1 r + u^T (F^T R^-1 F)^-1 u) with u = F^T R^-1 r - f, and the
   leave-one-out residuals by brute-force refitting without each sample (same hyper-parameters).

Parameter relations: RBF exp(-d^2 / (2 l^2)) -> theta_k = 1 / (2 l_k^2); Matern 5/2 with
r = |d / l| -> theta_k = 1 / l_k^2.

Run:  /usr/bin/python3 scripts/reference/gp_reference.py tests/data/surrogate
"""

import os
import sys

import numpy as np
import sklearn
from sklearn.gaussian_process import GaussianProcessRegressor
from sklearn.gaussian_process.kernels import RBF, ConstantKernel, Matern


def correlation(kind, theta, a, b):
    d2 = ((a[:, None, :] - b[None, :, :]) ** 2 * theta).sum(axis=2)
    if kind == "gaussian":
        return np.exp(-d2)
    r5 = np.sqrt(5.0 * d2)
    return (1.0 + r5 + r5 * r5 / 3.0) * np.exp(-r5)


def regressors(trend, x):
    if trend == "none":
        return np.zeros((x.shape[0], 0))
    if trend == "constant":
        return np.ones((x.shape[0], 1))
    return np.hstack([np.ones((x.shape[0], 1)), x])


def gls(kind, trend, theta, nugget, X, y, T):
    """Kriging with the GLS trend at fixed hyper-parameters (numpy, LU solves)."""
    n = X.shape[0]
    R = correlation(kind, theta, X, X) + nugget * np.eye(n)
    F = regressors(trend, X)
    Ri_y = np.linalg.solve(R, y)
    if F.shape[1]:
        Ri_F = np.linalg.solve(R, F)
        G = F.T @ Ri_F
        beta = np.linalg.solve(G, F.T @ Ri_y)
    else:
        Ri_F = np.zeros((n, 0))
        G = np.zeros((0, 0))
        beta = np.zeros(0)
    res = y - F @ beta
    alpha = np.linalg.solve(R, res)
    sigma2 = res @ alpha / n
    sign, logdet = np.linalg.slogdet(R)
    assert sign > 0
    loglik = -0.5 * n * (np.log(2.0 * np.pi * sigma2) + 1.0) - 0.5 * logdet
    r = correlation(kind, theta, X, T)  # n x m
    f = regressors(trend, T)
    mean = f @ beta + r.T @ alpha
    Ri_r = np.linalg.solve(R, r)
    var = 1.0 + nugget - (r * Ri_r).sum(axis=0)
    if F.shape[1]:
        u = F.T @ Ri_r - f.T
        var += (u * np.linalg.solve(G, u)).sum(axis=0)
    mse = sigma2 * np.maximum(var, 0.0)
    return beta, sigma2, loglik, mean, mse


def loo_brute_force(kind, trend, theta, nugget, X, y):
    e = np.empty(len(y))
    for i in range(len(y)):
        keep = np.arange(len(y)) != i
        _, _, _, m, _ = gls(kind, trend, theta, nugget, X[keep], y[keep], X[i:i + 1])
        e[i] = y[i] - m[0]
    return e


def sklearn_zero_mean(kind, length, nugget, X, y, T, sigma2):
    base = RBF(length_scale=length, length_scale_bounds="fixed") if kind == "gaussian" else \
        Matern(length_scale=length, length_scale_bounds="fixed", nu=2.5)
    kernel = ConstantKernel(sigma2, constant_value_bounds="fixed") * base
    gp = GaussianProcessRegressor(kernel=kernel, alpha=nugget * sigma2, optimizer=None,
                                  normalize_y=False)
    gp.fit(X, y)
    mean, std = gp.predict(T, return_std=True)
    return mean, std, gp.log_marginal_likelihood_value_


def write_case(folder, name, kind, length, nugget, X, y, T, function_text):
    theta = 1.0 / (2.0 * length**2) if kind == "gaussian" else 1.0 / length**2
    rows = []
    fmt = lambda v: repr(float(v))
    rows.append(f"correlation,{kind}")
    rows.append("length_scale," + ",".join(fmt(v) for v in length))
    rows.append("theta," + ",".join(fmt(v) for v in theta))
    rows.append("nugget," + fmt(nugget))
    for x, v in zip(X, y):
        rows.append("train," + ",".join(fmt(c) for c in x) + "," + fmt(v))
    for x in T:
        rows.append("test," + ",".join(fmt(c) for c in x))
    # scikit-learn, zero-mean process (MANTA Trend::none)
    _, s2_zero, ll_zero, _, _ = gls(kind, "none", theta, nugget, X, y, T)
    mean, std, lml = sklearn_zero_mean(kind, length, nugget, X, y, T, s2_zero)
    rows.append(f"sklearn_summary,{fmt(s2_zero)},{fmt(lml)}")
    for m, s in zip(mean, std):
        rows.append(f"sklearn_pred,{fmt(m)},{fmt(s)}")
    # numpy GLS, zero mean (cross-check of the sklearn values), ordinary and universal Kriging
    for trend in ("none", "constant", "linear"):
        beta, sigma2, loglik, mean, mse = gls(kind, trend, theta, nugget, X, y, T)
        rows.append(f"gls_{trend}_summary,{fmt(sigma2)},{fmt(loglik)}" +
                    "".join("," + fmt(b) for b in beta))
        for m, s in zip(mean, mse):
            rows.append(f"gls_{trend}_pred,{fmt(m)},{fmt(s)}")
        for e in loo_brute_force(kind, trend, theta, nugget, X, y):
            rows.append(f"gls_{trend}_loo,{fmt(e)}")
    header = [
        f"# MANTA Kriging reference case '{name}': {kind} correlation, fixed hyper-parameters.",
        f"# Made by scripts/reference/gp_reference.py with scikit-learn {sklearn.__version__},",
        f"# numpy {np.__version__} (Debian python3-sklearn):",
        "#   /usr/bin/python3 scripts/reference/gp_reference.py tests/data/surrogate",
        f"# Data: y = {function_text} at a random Latin hypercube (numpy seed in the script).",
        "# Records: train,x...,y | test,x... | sklearn_summary,sigma2,log_marginal_likelihood |",
        "# sklearn_pred,mean,std (zero-mean GP, kernel sigma2 * k, alpha = nugget * sigma2) |",
        "# gls_<trend>_summary,sigma2,loglik,beta... | gls_<trend>_pred,mean,mse |",
        "# gls_<trend>_loo,residual (brute-force refit without the sample).",
    ]
    with open(os.path.join(folder, f"gp_reference_{name}.csv"), "w") as out:
        out.write("\n".join(header + rows) + "\n")


def lhs(rng, n, d):
    x = np.empty((n, d))
    for k in range(d):
        x[:, k] = (rng.permutation(n) + rng.uniform(size=n)) / n
    return x


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else "tests/data/surrogate"
    os.makedirs(folder, exist_ok=True)
    rng = np.random.default_rng(20240604)

    # 2-D, Gaussian correlation
    X = lhs(rng, 24, 2)
    f2 = lambda x: np.sin(6.0 * x[:, 0]) + np.cos(4.0 * x[:, 1]) + 2.0 * x[:, 0] * x[:, 1]
    T = np.vstack([lhs(rng, 12, 2), [[1.3, -0.2], [-0.5, 0.5], [0.5, 1.8]]])
    write_case(folder, "gaussian_2d", "gaussian", np.array([0.25, 0.4]), 1e-8, X, f2(X), T,
               "sin(6 x1) + cos(4 x2) + 2 x1 x2")

    # 3-D, Matern 5/2 correlation
    X = lhs(rng, 36, 3)
    f3 = lambda x: (1.0 + 2.0 * x[:, 0] - x[:, 1] + np.exp(-2.0 * x[:, 2]) * np.sin(5.0 * x[:, 0])
                    + 0.5 * x[:, 1] * x[:, 2])
    T = np.vstack([lhs(rng, 12, 3), [[1.4, 0.5, 0.5], [0.2, -0.6, 1.1], [0.5, 0.5, 2.0]]])
    write_case(folder, "matern52_3d", "matern52", np.array([0.5, 0.7, 0.9]), 1e-6, X, f3(X), T,
               "1 + 2 x1 - x2 + exp(-2 x3) sin(5 x1) + 0.5 x2 x3")

    # 3-D, Gaussian with an estimated-nugget-sized nugget (noisy data)
    X = lhs(rng, 40, 3)
    y = f3(X) + 0.05 * rng.standard_normal(40)
    T = lhs(rng, 12, 3)
    write_case(folder, "gaussian_3d_noisy", "gaussian", np.array([0.3, 0.5, 0.6]), 1e-2, X, y, T,
               "1 + 2 x1 - x2 + exp(-2 x3) sin(5 x1) + 0.5 x2 x3 + N(0, 0.05^2) noise")


if __name__ == "__main__":
    main()
