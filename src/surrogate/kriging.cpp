/// @file kriging.cpp
/// Kriging: correlation models, the concentrated likelihood with its analytic gradient, the
/// multi-start maximum-likelihood fit (NLopt L-BFGS), predictions with the universal-Kriging MSE
/// and closed-form leave-one-out residuals. Theory and references: docs/kriging.md.

#include "manta/surrogate/kriging.hpp"

#include <fmt/format.h>
#include <nlopt.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "kriging_detail.hpp"
#include "kriging_linalg.hpp"
#include "manta/core/error.hpp"

namespace manta::surrogate {

namespace {

constexpr double kLog2Pi = 1.83787706640934548356;
/// Points per block in batch prediction (keeps the n x block correlation matrix in cache-sized
/// pieces and bounds the memory of a large batch).
constexpr Eigen::Index kPredictBlock = 256;
/// Screening: how many of the subset's optima are polished on all samples, and how far apart
/// (max-norm in log theta, log nugget) two optima must be to count as distinct.
constexpr std::size_t kPolished = 2;
constexpr double kDistinct = 0.2;
/// Evaluations of the trial polish of each pick before the better one is continued.
constexpr int kPolishTrial = 12;

// ------------------------------------------------------------------------------ correlation

/// Correlation values c(s) and h(s) = -dc/ds of the scaled squared distance
/// s = sum_k theta_k d_k^2, evaluated element-wise (vectorised by Eigen).
///  Gaussian:   c = exp(-s),                                  h = c.
///  Matern 5/2: c = (1 + a + a^2/3) exp(-a) with a = sqrt(5 s), h = (5/6) (1 + a) exp(-a)
/// (the latter from dc/dr = -(5/3) r (1 + sqrt5 r) exp(-sqrt5 r) and dr/ds = 1/(2r); it is
/// finite at s = 0).
void correlation(Correlation model, const Eigen::Ref<const Eigen::ArrayXd>& s,
                 Eigen::Ref<Eigen::ArrayXd> c, Eigen::ArrayXd* h) {
    if (model == Correlation::gaussian) {
        c = (-s).exp();
        if (h) *h = c;
        return;
    }
    const Eigen::ArrayXd a = (5.0 * s).sqrt();
    const Eigen::ArrayXd e = (-a).exp();
    c = (1.0 + a + a.square() / 3.0) * e;
    if (h) *h = (5.0 / 6.0) * (1.0 + a) * e;
}

/// Number of regressors of the trend.
Eigen::Index n_regressors(const KrigingOptions& o, Eigen::Index dim, Eigen::Index n_extra) {
    Eigen::Index p = n_extra;
    if (o.trend == Trend::constant) p += 1;
    if (o.trend == Trend::linear) p += 1 + dim;
    return p;
}

/// Regressor row f(x) (constant, linear terms, extra regressors).
void regressors(const KrigingOptions& o, const Vector& x, Eigen::Index p,
                Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>> f) {
    Eigen::Index j = 0;
    if (o.trend == Trend::constant || o.trend == Trend::linear) f[j++] = 1.0;
    if (o.trend == Trend::linear)
        for (Eigen::Index k = 0; k < x.size(); ++k) f[j++] = x[k];
    if (o.extra_regressors) {
        const Vector e = o.extra_regressors(x);
        if (e.size() != p - j)
            throw InputError(
                fmt::format("Kriging: extra regressors returned {} values at a point; "
                            "expected {} (the count at the first sample)",
                            e.size(), p - j));
        if (!e.allFinite())
            throw InputError("Kriging: extra regressors returned NaN or Inf at a point");
        f.tail(p - j) = e.transpose();
    }
}

// ------------------------------------------------------------------------------ likelihood

/// Everything fixed during one likelihood optimisation: standardised outputs, the regression
/// matrix and the squared coordinate differences of every pair of samples.
struct Problem {
    Correlation model = Correlation::gaussian;
    Eigen::Index n = 0, dim = 0;
    Vector ys;  ///< standardised outputs
    Matrix F;   ///< n x p regressors
    /// Squared differences of pair (i < j) in dimension k, pairs ordered column by column of the
    /// strict lower triangle: pair (j, i) for i = 0..n-2, j = i+1..n-1.
    Matrix dsq;
};

/// Offset of column i's first pair in Problem::dsq.
Eigen::Index pair_offset(Eigen::Index n, Eigen::Index i) {
    return i * (n - 1) - i * (i - 1) / 2;
}

/// The model at given hyper-parameters: Cholesky factor, GLS trend and concentrated likelihood.
struct Factor {
    Matrix L;   ///< lower triangle: Cholesky factor of R = C + nugget I
    Matrix Ft;  ///< L^-1 F
    /// Cholesky of F^T R^-1 F = Ft^T Ft; built from an empty matrix so that its status is set
    /// even without a trend (a default-constructed LLT leaves it uninitialised, and moving it reads
    /// it).
    Eigen::LLT<Matrix> gram{Matrix(0, 0)};
    Vector beta;   ///< GLS coefficients (standardised units)
    Vector rt;     ///< L^-1 (ys - F beta)
    Vector alpha;  ///< R^-1 (ys - F beta)
    double sigma2 = 0.0;
    double loglik = 0.0;  ///< concentrated log-likelihood of the standardised outputs
};

/// Workspace of one optimisation (not shared between threads).
struct Workspace {
    Eigen::ArrayXd s, c, h, w;
    Matrix inverse;
};

/// Factorises R(theta, nugget) and evaluates the concentrated log-likelihood
///   l = -n/2 log(2 pi sigma^2) - 1/2 log|R| - n/2,  sigma^2 = (y - F b)^T R^-1 (y - F b) / n,
/// with the GLS b. Returns false when R is not numerically positive definite. `h` (= -dc/ds per
/// pair) is kept in the workspace when `keep_h`.
bool factorise(const Problem& pb, const Vector& theta, double nugget, Factor& out, Workspace& ws,
               bool keep_h) {
    const Eigen::Index n = pb.n;
    const Eigen::Index n_pairs = pb.dsq.rows();
    ws.s.resize(n_pairs);
    ws.c.resize(n_pairs);
    ws.s.matrix().noalias() = pb.dsq * theta;
    correlation(pb.model, ws.s, ws.c, keep_h ? &ws.h : nullptr);
    out.L.resize(n, n);
    for (Eigen::Index i = 0; i < n; ++i) {
        out.L(i, i) = 1.0 + nugget;
        const Eigen::Index len = n - 1 - i;
        if (len > 0) out.L.col(i).tail(len) = ws.c.segment(pair_offset(n, i), len).matrix();
    }
    if (!detail::cholesky_in_place(out.L)) return false;
    double log_det_half = 0.0;
    for (Eigen::Index i = 0; i < n; ++i) log_det_half += std::log(out.L(i, i));

    const auto Lt = out.L.triangularView<Eigen::Lower>();
    out.rt = Lt.solve(pb.ys);
    const Eigen::Index p = pb.F.cols();
    if (p > 0) {
        out.Ft = Lt.solve(pb.F);
        out.gram.compute(out.Ft.transpose() * out.Ft);
        if (out.gram.info() != Eigen::Success) return false;
        out.beta = out.gram.solve(out.Ft.transpose() * out.rt);
        out.rt -= out.Ft * out.beta;
    } else {
        out.Ft.resize(n, 0);
        out.beta.resize(0);
    }
    out.sigma2 =
        std::max(out.rt.squaredNorm() / static_cast<double>(n), std::numeric_limits<double>::min());
    out.loglik =
        -0.5 * static_cast<double>(n) * (kLog2Pi + std::log(out.sigma2) + 1.0) - log_det_half;
    if (!std::isfinite(out.loglik)) return false;
    out.alpha = out.L.triangularView<Eigen::Lower>().transpose().solve(out.rt);
    return true;
}

/// Gradient of the concentrated log-likelihood with respect to log theta_k (and log nugget when
/// `with_nugget`), after factorise(..., keep_h = true):
///   dl/dpsi = 1/2 sum_ij W_ij dR_ij/dpsi,  W = alpha alpha^T / sigma^2 - R^-1
/// (the GLS coefficients and sigma^2 are stationary, so only R's derivative enters). With
/// dR_ij/dlog theta_k = -h_ij theta_k d_ijk^2 and W symmetric this is
///   dl/dlog theta_k = -theta_k sum_{i<j} W_ij h_ij d_ijk^2,   dl/dlog nugget = nugget/2 tr W.
void gradient(const Problem& pb, const Vector& theta, double nugget, bool with_nugget,
              const Factor& f, Workspace& ws, double* grad) {
    const Eigen::Index n = pb.n;
    detail::inverse_from_cholesky(f.L, ws.inverse);  // lower triangle of R^-1
    const double inv_s2 = 1.0 / f.sigma2;
    ws.w.resize(pb.dsq.rows());
    double trace_w = 0.0;
    for (Eigen::Index i = 0; i < n; ++i) {
        const double ai = f.alpha[i] * inv_s2;
        trace_w += ai * f.alpha[i] - ws.inverse(i, i);
        const Eigen::Index len = n - 1 - i;
        if (len == 0) continue;
        const Eigen::Index off = pair_offset(n, i);
        ws.w.segment(off, len) =
            (ai * f.alpha.tail(len).array() - ws.inverse.col(i).tail(len).array()) *
            ws.h.segment(off, len);
    }
    const Vector g = pb.dsq.transpose() * ws.w.matrix();
    for (Eigen::Index k = 0; k < pb.dim; ++k) grad[k] = -theta[k] * g[k];
    if (with_nugget) grad[pb.dim] = 0.5 * nugget * trace_w;
}

/// NLopt objective context: minimises -l over psi = (log theta, [log nugget]).
struct Objective {
    const Problem* pb = nullptr;
    bool with_nugget = false;
    double fixed_nugget = 0.0;
    Factor factor;
    Workspace ws;
    Vector theta;
    double best_value = std::numeric_limits<double>::infinity();
    std::vector<double> best_x;
    int evaluations = 0;
};

/// Value returned where R is not positive definite: worse than any likelihood, with a zero
/// gradient, so the line search backs off.
constexpr double kInfeasible = 1e300;

double objective(unsigned dim, const double* x, double* grad, void* data) {
    auto& o = *static_cast<Objective*>(data);
    ++o.evaluations;
    const Eigen::Index d = o.pb->dim;
    for (Eigen::Index k = 0; k < d; ++k) o.theta[k] = std::exp(x[k]);
    const double nugget = o.with_nugget ? std::exp(x[d]) : o.fixed_nugget;
    if (!factorise(*o.pb, o.theta, nugget, o.factor, o.ws, grad != nullptr)) {
        if (grad)
            for (unsigned k = 0; k < dim; ++k) grad[k] = 0.0;
        return kInfeasible;
    }
    const double value = -o.factor.loglik;
    if (grad) {
        gradient(*o.pb, o.theta, nugget, o.with_nugget, o.factor, o.ws, grad);
        for (unsigned k = 0; k < dim; ++k) grad[k] = -grad[k];
    }
    if (value < o.best_value) {
        o.best_value = value;
        o.best_x.assign(x, x + dim);
    }
    return value;
}

}  // namespace

// ------------------------------------------------------------------------------ the model

struct Kriging::Impl {
    Matrix X;
    Vector y;
    KrigingOptions options;
    Hyperparameters h;
    double centre = 0.0;  ///< y = centre + scale * ys
    double scale = 1.0;
    Eigen::Index p = 0;  ///< number of regressors
    Factor f;

    /// Regressor rows and correlations of a block of points (rows of P).
    void block(const Matrix& P, Eigen::Index start, Eigen::Index m, Matrix& Fm, Matrix& Rm) const {
        const Eigen::Index n = X.rows(), d = X.cols();
        Fm.resize(m, p);
        Rm.resize(n, m);
        Eigen::ArrayXd s(n);
        for (Eigen::Index j = 0; j < m; ++j) {
            s.setZero();
            for (Eigen::Index k = 0; k < d; ++k)
                s += h.theta[k] * (X.col(k).array() - P(start + j, k)).square();
            correlation(options.correlation, s, Rm.col(j).array(), nullptr);
            if (p > 0) regressors(options, P.row(start + j).transpose(), p, Fm.row(j));
        }
    }
};

Kriging::Kriging(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Kriging::Kriging(const Kriging& o) : impl_(std::make_unique<Impl>(*o.impl_)) {}
Kriging& Kriging::operator=(const Kriging& o) {
    if (this != &o) impl_ = std::make_unique<Impl>(*o.impl_);
    return *this;
}
Kriging::Kriging(Kriging&&) noexcept = default;
Kriging& Kriging::operator=(Kriging&&) noexcept = default;
Kriging::~Kriging() = default;

namespace {

void validate_options(const KrigingOptions& o) {
    if (!(o.theta_min > 0.0 && o.theta_max > o.theta_min && std::isfinite(o.theta_max)))
        throw InputError(
            fmt::format("Kriging: theta range [{}, {}]; expected 0 < theta_min < "
                        "theta_max < inf",
                        o.theta_min, o.theta_max));
    if (!(o.nugget >= 0.0 && std::isfinite(o.nugget)))
        throw InputError(fmt::format("Kriging: nugget {}; expected a finite value >= 0", o.nugget));
    if (o.estimate_nugget &&
        !(o.nugget_min > 0.0 && o.nugget_max > o.nugget_min && std::isfinite(o.nugget_max)))
        throw InputError(
            fmt::format("Kriging: nugget range [{}, {}]; expected 0 < nugget_min < "
                        "nugget_max < inf",
                        o.nugget_min, o.nugget_max));
    if (o.restarts < 1)
        throw InputError(fmt::format("Kriging: restarts = {}; expected >= 1", o.restarts));
    if (o.screening_points < 0 || (o.screening_points > 0 && o.screening_points < 10))
        throw InputError(fmt::format("Kriging: screening_points = {}; expected 0 (off) or >= 10",
                                     o.screening_points));
}

/// Checks the data and builds the likelihood problem and the model shell (standardisation).
std::unique_ptr<Kriging::Impl> prepare(const Matrix& X, const Vector& y,
                                       const KrigingOptions& options, Problem& pb) {
    validate_options(options);
    const Eigen::Index n = X.rows(), d = X.cols();
    if (d < 1) throw InputError("Kriging: the sample matrix has no columns; expected >= 1");
    if (y.size() != n)
        throw InputError(
            fmt::format("Kriging: {} sample points but {} values; expected equal", n, y.size()));
    for (Eigen::Index i = 0; i < n; ++i) {
        if (!X.row(i).allFinite())
            throw InputError(fmt::format("Kriging: sample row {} has NaN or Inf coordinates", i));
        if (!std::isfinite(y[i]))
            throw InputError(
                fmt::format("Kriging: sample value {} is {}; expected finite", i, y[i]));
    }
    Eigen::Index n_extra = 0;
    if (options.extra_regressors && n > 0)
        n_extra = options.extra_regressors(X.row(0).transpose()).size();
    const Eigen::Index p = n_regressors(options, d, n_extra);
    if (n < std::max<Eigen::Index>(p + 1, 2))
        throw InputError(
            fmt::format("Kriging: {} samples for a trend of {} regressors; expected "
                        ">= {}",
                        n, p, std::max<Eigen::Index>(p + 1, 2)));

    auto impl = std::make_unique<Kriging::Impl>();
    impl->X = X;
    impl->y = y;
    impl->options = options;
    impl->p = p;
    // Standardise the outputs: centred (unless the process has zero mean) and scaled to unit
    // spread. Predictions, sigma^2 and the likelihood are returned in the units of y.
    impl->centre = options.trend == Trend::none ? 0.0 : y.mean();
    const double spread = std::sqrt((y.array() - impl->centre).square().mean());
    impl->scale = spread > 0.0 ? spread : 1.0;

    pb.model = options.correlation;
    pb.n = n;
    pb.dim = d;
    pb.ys = (y.array() - impl->centre) / impl->scale;
    pb.F.resize(n, p);
    for (Eigen::Index i = 0; i < n; ++i) regressors(options, X.row(i).transpose(), p, pb.F.row(i));
    pb.dsq.resize(n * (n - 1) / 2, d);
    std::vector<std::pair<Eigen::Index, Eigen::Index>> duplicates;
    for (Eigen::Index i = 0; i + 1 < n; ++i) {
        const Eigen::Index off = pair_offset(n, i), len = n - 1 - i;
        for (Eigen::Index k = 0; k < d; ++k)
            pb.dsq.col(k).segment(off, len) = (X.col(k).tail(len).array() - X(i, k)).square();
        for (Eigen::Index j = 0; j < len; ++j)
            if (pb.dsq.row(off + j).maxCoeff() == 0.0) duplicates.emplace_back(i, i + 1 + j);
    }
    if (!duplicates.empty()) {
        std::string rows;
        for (std::size_t m = 0; m < std::min<std::size_t>(duplicates.size(), 5); ++m)
            rows += fmt::format("{}({} and {})", m ? ", " : "", duplicates[m].first,
                                duplicates[m].second);
        throw InputError(
            fmt::format("Kriging: {} pair(s) of duplicate sample points, rows {}{}; "
                        "expected distinct points (merge or drop repeats)",
                        duplicates.size(), rows, duplicates.size() > 5 ? ", ..." : ""));
    }
    return impl;
}

}  // namespace

Kriging Kriging::with_hyperparameters(const Matrix& X, const Vector& y,
                                      const KrigingOptions& options, const Hyperparameters& h) {
    Problem pb;
    auto impl = prepare(X, y, options, pb);
    if (h.theta.size() != X.cols())
        throw InputError(
            fmt::format("Kriging: {} correlation parameters for {} dimensions; "
                        "expected one per dimension",
                        h.theta.size(), X.cols()));
    if (!(h.theta.array() > 0.0).all() || !h.theta.allFinite())
        throw InputError("Kriging: correlation parameters must be finite and > 0");
    if (!(h.nugget >= 0.0 && std::isfinite(h.nugget)))
        throw InputError(fmt::format("Kriging: nugget {}; expected a finite value >= 0", h.nugget));
    Factor f;
    Workspace ws;
    if (!factorise(pb, h.theta, h.nugget, f, ws, false))
        throw NumericalError(
            fmt::format("Kriging: the correlation matrix of {} samples is not "
                        "positive definite at the given hyper-parameters (add a "
                        "nugget or increase theta)",
                        X.rows()));
    impl->h = h;
    impl->f = std::move(f);
    return Kriging(std::move(impl));
}

namespace {

/// Indices of a well-spread subset of m rows of X: greedy farthest-point (maximin) selection,
/// starting from the row nearest the centroid. Deterministic.
std::vector<Eigen::Index> spread_subset(const Matrix& X, Eigen::Index m) {
    const Eigen::RowVectorXd centre = X.colwise().mean();
    Eigen::Index first = 0;
    (X.rowwise() - centre).rowwise().squaredNorm().minCoeff(&first);
    std::vector<Eigen::Index> chosen{first};
    Vector gap = (X.rowwise() - X.row(first)).rowwise().squaredNorm();
    while (static_cast<Eigen::Index>(chosen.size()) < m) {
        Eigen::Index next = 0;
        gap.maxCoeff(&next);
        chosen.push_back(next);
        gap = gap.cwiseMin((X.rowwise() - X.row(next)).rowwise().squaredNorm());
    }
    std::sort(chosen.begin(), chosen.end());
    return chosen;
}

/// The likelihood problem restricted to some samples.
Problem sub_problem(const Problem& pb, const Matrix& X, const std::vector<Eigen::Index>& rows) {
    Problem sub;
    sub.model = pb.model;
    sub.n = static_cast<Eigen::Index>(rows.size());
    sub.dim = pb.dim;
    sub.ys.resize(sub.n);
    sub.F.resize(sub.n, pb.F.cols());
    Matrix Xs(sub.n, pb.dim);
    for (Eigen::Index i = 0; i < sub.n; ++i) {
        const Eigen::Index r = rows[static_cast<std::size_t>(i)];
        sub.ys[i] = pb.ys[r];
        sub.F.row(i) = pb.F.row(r);
        Xs.row(i) = X.row(r);
    }
    sub.dsq.resize(sub.n * (sub.n - 1) / 2, sub.dim);
    for (Eigen::Index i = 0; i + 1 < sub.n; ++i) {
        const Eigen::Index off = pair_offset(sub.n, i), len = sub.n - 1 - i;
        for (Eigen::Index k = 0; k < sub.dim; ++k)
            sub.dsq.col(k).segment(off, len) = (Xs.col(k).tail(len).array() - Xs(i, k)).square();
    }
    return sub;
}

/// Local maximisation of the likelihood (L-BFGS with analytic gradient, bounds) from `x`;
/// returns the best point seen and its value (-l) in `x` and the return value.
double local_optimum(Objective& obj, std::vector<double>& x, const std::vector<double>& lo,
                     const std::vector<double>& hi, double xtol, int max_evaluations) {
    const auto n_par = static_cast<unsigned>(x.size());
    nlopt_opt opt = nlopt_create(NLOPT_LD_LBFGS, n_par);
    nlopt_set_lower_bounds(opt, lo.data());
    nlopt_set_upper_bounds(opt, hi.data());
    nlopt_set_min_objective(opt, objective, &obj);
    nlopt_set_ftol_abs(opt, 1e-6);
    nlopt_set_xtol_abs1(opt, xtol);
    nlopt_set_maxeval(opt, max_evaluations);
    obj.best_value = std::numeric_limits<double>::infinity();
    obj.best_x = x;
    double fx = 0.0;
    // Failure codes (round-off limited, forced stop) still leave a usable best point.
    (void)nlopt_optimize(opt, x.data(), &fx);
    nlopt_destroy(opt);
    x = obj.best_x;
    return obj.best_value;
}

}  // namespace

Kriging Kriging::fit(const Matrix& X, const Vector& y, const KrigingOptions& options) {
    Problem pb;
    auto impl = prepare(X, y, options, pb);
    const Eigen::Index n = X.rows(), d = X.cols();
    const bool with_nugget = options.estimate_nugget;
    const auto n_par = static_cast<std::size_t>(d + (with_nugget ? 1 : 0));

    // Bounds of psi = (log theta, [log nugget]).
    std::vector<double> lo(n_par), hi(n_par);
    for (Eigen::Index k = 0; k < d; ++k) {
        lo[k] = std::log(options.theta_min);
        hi[k] = std::log(options.theta_max);
    }
    if (with_nugget) {
        lo[d] = std::log(options.nugget_min);
        hi[d] = std::log(options.nugget_max);
    }

    // Stage 1, the multi-start search, runs on a well-spread subset of the samples when there are
    // more than options.screening_points of them (the optimum of the likelihood moves little with
    // the sampling density, and each evaluation costs O(n^3)); stage 2 polishes the best optimum
    // on all samples.
    const bool screen = options.screening_points > 0 && n > options.screening_points;
    Problem sub;
    if (screen) sub = sub_problem(pb, X, spread_subset(X, options.screening_points));
    const Problem& search = screen ? sub : pb;

    // Candidate starts: one heuristic point (theta_k = 1 / range_k^2, a correlation of exp(-1)
    // across the whole range for the Gaussian, clipped to the bounds), then log-uniform random
    // points. Each candidate costs one factorisation; the `restarts` best become the starts of
    // the local optimisations (so starts in flat or ill-conditioned corners are pruned cheaply).
    detail::Rng rng(options.seed);
    const int n_candidates = 3 * options.restarts;
    std::vector<std::vector<double>> candidates;
    {
        std::vector<double> x0(n_par);
        for (Eigen::Index k = 0; k < d; ++k) {
            const double range = X.col(k).maxCoeff() - X.col(k).minCoeff();
            const double guess = range > 0.0 ? 1.0 / (range * range) : 1.0;
            x0[k] = std::clamp(std::log(guess), lo[k], hi[k]);
        }
        if (with_nugget) x0[d] = std::clamp(std::log(1e-4), lo[d], hi[d]);
        candidates.push_back(x0);
    }
    while (static_cast<int>(candidates.size()) < n_candidates) {
        std::vector<double> x(n_par);
        for (std::size_t k = 0; k < n_par; ++k) x[k] = lo[k] + (hi[k] - lo[k]) * rng.uniform();
        candidates.push_back(std::move(x));
    }

    Objective obj;
    obj.pb = &search;
    obj.with_nugget = with_nugget;
    obj.fixed_nugget = options.nugget;
    obj.theta.resize(d);
    std::vector<std::pair<double, int>> ranked;
    for (int c = 0; c < n_candidates; ++c) {
        const double v =
            objective(static_cast<unsigned>(n_par), candidates[c].data(), nullptr, &obj);
        if (v < kInfeasible) ranked.emplace_back(v, c);
    }
    if (ranked.empty())
        throw ConvergenceError(fmt::format(
            "Kriging: the correlation matrix of {} samples is not positive definite at any of {} "
            "likelihood starts (theta in [{}, {}]); raise theta_min or the nugget",
            search.n, n_candidates, options.theta_min, options.theta_max));
    std::stable_sort(ranked.begin(), ranked.end());
    ranked.resize(std::min<std::size_t>(ranked.size(), static_cast<std::size_t>(options.restarts)));

    std::vector<double> best;
    double best_value = kInfeasible;
    std::vector<std::vector<double>> optima;
    for (const auto& entry : ranked) {
        std::vector<double> x = candidates[static_cast<std::size_t>(entry.second)];
        const double v = local_optimum(obj, x, lo, hi, screen ? 1e-3 : 1e-5, 200);
        optima.push_back(x);
        if (v < best_value) {
            best_value = v;
            best = x;
        }
    }
    if (screen) {
        // Rank the subset's optima on all samples (one factorisation each) and polish the two
        // best distinct ones there (the subset may rank two close basins the other way round).
        obj.pb = &pb;
        std::vector<std::pair<double, std::size_t>> order;
        for (std::size_t i = 0; i < optima.size(); ++i) {
            const double v =
                objective(static_cast<unsigned>(n_par), optima[i].data(), nullptr, &obj);
            if (v < kInfeasible) order.emplace_back(v, i);
        }
        if (order.empty())
            throw ConvergenceError(fmt::format(
                "Kriging: the correlation matrix of all {} samples is not positive definite at "
                "the likelihood optima of a {}-sample subset; add a nugget",
                n, search.n));
        std::stable_sort(order.begin(), order.end());
        std::vector<std::size_t> picks{order.front().second};
        for (const auto& entry : order) {
            if (picks.size() >= kPolished) break;
            bool distinct = true;
            for (std::size_t q : picks) {
                double gap = 0.0;
                for (std::size_t k = 0; k < n_par; ++k)
                    gap = std::max(gap, std::abs(optima[entry.second][k] - optima[q][k]));
                distinct = distinct && gap > kDistinct;
            }
            if (distinct) picks.push_back(entry.second);
        }
        // A few L-BFGS steps from each pick, then only the better one is run to convergence.
        best_value = kInfeasible;
        for (std::size_t q : picks) {
            std::vector<double> x = optima[q];
            const double v = local_optimum(obj, x, lo, hi, 1e-5, kPolishTrial);
            if (v < best_value) {
                best_value = v;
                best = x;
            }
        }
        (void)local_optimum(obj, best, lo, hi, 1e-4, 200);
    }
    if (best.empty())
        throw ConvergenceError("Kriging: no likelihood optimisation reached a finite value");

    Hyperparameters h;
    h.theta.resize(d);
    for (Eigen::Index k = 0; k < d; ++k) h.theta[k] = std::exp(best[k]);
    h.nugget = with_nugget ? std::exp(best[d]) : options.nugget;
    Factor f;
    Workspace ws;
    if (!factorise(pb, h.theta, h.nugget, f, ws, false))
        throw ConvergenceError("Kriging: the best likelihood point lost positive definiteness");
    impl->h = h;
    impl->f = std::move(f);
    return Kriging(std::move(impl));
}

// ------------------------------------------------------------------------------ predictions

double Kriging::predict(const Vector& x) const {
    return predict_with_mse(x).mean;
}

Prediction Kriging::predict_with_mse(const Vector& x) const {
    Matrix P = x.transpose();
    Vector mean, mse;
    predict(P, mean, &mse);
    return {mean[0], mse[0]};
}

void Kriging::predict(const Matrix& points, Vector& mean, Vector* mse) const {
    const Impl& m = *impl_;
    if (points.cols() != m.X.cols())
        throw InputError(
            fmt::format("Kriging: prediction points have {} columns; the model has {} "
                        "dimensions",
                        points.cols(), m.X.cols()));
    const Eigen::Index n_points = points.rows();
    mean.resize(n_points);
    if (mse) mse->resize(n_points);
    Matrix Fm, Rm, U;
    const auto Lt = m.f.L.triangularView<Eigen::Lower>();
    const double s2 = m.f.sigma2 * m.scale * m.scale;
    for (Eigen::Index start = 0; start < n_points; start += kPredictBlock) {
        const Eigen::Index b = std::min(kPredictBlock, n_points - start);
        m.block(points, start, b, Fm, Rm);
        auto mb = mean.segment(start, b);
        mb = Rm.transpose() * m.f.alpha;
        if (m.p > 0) mb += Fm * m.f.beta;
        mb = (m.centre + m.scale * mb.array()).matrix();
        if (!mse) continue;
        // MSE = sigma^2 (1 + nugget - r^T R^-1 r + u^T (F^T R^-1 F)^-1 u), u = F^T R^-1 r - f.
        Lt.solveInPlace(Rm);  // V = L^-1 r
        Eigen::ArrayXd var = (1.0 + m.h.nugget) - Rm.colwise().squaredNorm().transpose().array();
        if (m.p > 0) {
            U = m.f.Ft.transpose() * Rm - Fm.transpose();
            const Matrix GU = m.f.gram.solve(U);
            var += (U.array() * GU.array()).colwise().sum().transpose();
        }
        mse->segment(start, b) = (s2 * var.max(0.0)).matrix();
    }
}

// ------------------------------------------------------------------------------ diagnostics

Vector Kriging::loo_residuals() const {
    // Dubrule (1983): with Q = R^-1 - R^-1 F (F^T R^-1 F)^-1 F^T R^-1, the residual of the
    // model refitted without sample i (same hyper-parameters, GLS trend re-estimated) is
    // e_i = [Q y]_i / Q_ii, and Q y = alpha.
    const Impl& m = *impl_;
    Matrix inverse;
    detail::inverse_from_cholesky(m.f.L, inverse);
    Vector q = inverse.diagonal();
    if (m.p > 0) {
        // R^-1 F = L^-T Ft.
        const Matrix A = m.f.L.triangularView<Eigen::Lower>().transpose().solve(m.f.Ft);
        const Matrix GA = m.f.gram.solve(A.transpose());
        q -= (A.transpose().array() * GA.array()).colwise().sum().transpose().matrix();
    }
    return (m.scale * m.f.alpha.array() / q.array()).matrix();
}

double Kriging::loo_rmse() const {
    const Vector e = loo_residuals();
    return std::sqrt(e.squaredNorm() / static_cast<double>(e.size()));
}

const Hyperparameters& Kriging::hyperparameters() const {
    return impl_->h;
}
double Kriging::process_variance() const {
    return impl_->f.sigma2 * impl_->scale * impl_->scale;
}
Vector Kriging::trend_coefficients() const {
    Vector beta = impl_->scale * impl_->f.beta;
    if (impl_->options.trend != Trend::none) beta[0] += impl_->centre;
    return beta;
}
double Kriging::log_likelihood() const {
    return impl_->f.loglik - static_cast<double>(impl_->X.rows()) * std::log(impl_->scale);
}
const Matrix& Kriging::points() const {
    return impl_->X;
}
const Vector& Kriging::values() const {
    return impl_->y;
}
const KrigingOptions& Kriging::options() const {
    return impl_->options;
}

}  // namespace manta::surrogate
