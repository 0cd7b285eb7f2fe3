#pragma once
/// @file kriging.hpp
/// Kriging (Gaussian-process regression) with maximum-likelihood hyper-parameters.
///
/// Model: y(x) = f(x)^T beta + Z(x), Z a stationary Gaussian process with variance sigma^2 and
/// correlation R(x, x') (anisotropic Gaussian or Matern 5/2), plus an optional nugget (white noise
/// with variance nugget * sigma^2, for noisy data). The trend f is a constant (ordinary Kriging),
/// constant + linear terms (universal Kriging), optionally followed by user regressors (the
/// recursive Co-Kriging puts the cheap model's prediction there). beta and sigma^2 are given in
/// closed form (generalised least squares); the correlation parameters and the nugget maximise the
/// concentrated log-likelihood (NLopt, multi-start). The Cholesky factor of the correlation matrix
/// is kept and reused by every prediction.
///
/// Inputs are used as given (callers scale to the unit cube, see design.hpp); outputs are
/// standardised internally. Correlation parameters: Gaussian R = exp(-sum_k theta_k d_k^2);
/// Matern 5/2 with r = sqrt(sum_k theta_k d_k^2): R = (1 + sqrt5 r + 5 r^2 / 3) exp(-sqrt5 r).
/// (theta_k = 1 / (2 l_k^2) for the Gaussian and 1 / l_k^2 for Matern gives length scales l_k.)

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>

#include "manta/surrogate/design.hpp"

namespace manta::surrogate {

enum class Correlation { gaussian, matern52 };
/// Trend of the process: constant (ordinary Kriging), constant + linear terms (universal
/// Kriging), or none (simple Kriging of a zero-mean process: only the extra regressors, if any;
/// outputs are then scaled but not centred, which matches a zero-mean Gaussian process).
enum class Trend { constant, linear, none };

/// Extra regressors of the trend: maps a point to a row of regressor values (fixed length).
using Regressors = std::function<Vector(const Vector& x)>;

struct KrigingOptions {
    Correlation correlation = Correlation::gaussian;
    Trend trend = Trend::constant;
    Regressors extra_regressors;  ///< empty: none
    /// Estimate the nugget by maximum likelihood in [nugget_min, nugget_max] (relative to sigma^2);
    /// otherwise the fixed `nugget` is used (a tiny default keeps the factorisation stable).
    bool estimate_nugget = false;
    double nugget = 1e-10;
    double nugget_min = 1e-10;
    double nugget_max = 1e-1;
    double theta_min = 1e-3;  ///< search range of each theta_k (log-uniform starts)
    double theta_max = 1e3;
    int restarts = 5;  ///< likelihood optimisations from different starts; the best is kept
    /// With more samples than this, the multi-start search runs on a well-spread subset of this
    /// many samples and only the best optimum is polished on all of them (each likelihood
    /// evaluation costs O(n^3)); 0: every start uses all samples.
    int screening_points = 200;
    std::uint64_t seed = 1;
};

/// Hyper-parameters of a fitted model.
struct Hyperparameters {
    Vector theta;         ///< one per dimension
    double nugget = 0.0;  ///< relative to the process variance
};

/// Predictor mean and mean squared error (the Kriging variance, including the trend-uncertainty
/// term of universal Kriging).
struct Prediction {
    double mean = 0.0;
    double mse = 0.0;
};

class Kriging {
public:
    /// Fit by maximum likelihood. X: n x d (n >= trend size + 1), y: n. ConvergenceError if no
    /// start gives a positive-definite correlation matrix; InputError on bad shapes or NaN.
    [[nodiscard]] static Kriging fit(const Matrix& X, const Vector& y,
                                     const KrigingOptions& options);
    /// Fit with given hyper-parameters (no optimisation). InputError on bad data or parameters,
    /// NumericalError if the correlation matrix is not positive definite at them.
    [[nodiscard]] static Kriging with_hyperparameters(const Matrix& X, const Vector& y,
                                                      const KrigingOptions& options,
                                                      const Hyperparameters& h);

    [[nodiscard]] double predict(const Vector& x) const;
    [[nodiscard]] Prediction predict_with_mse(const Vector& x) const;
    /// Batch prediction of the rows of `points`; `mse` may be null.
    void predict(const Matrix& points, Vector& mean, Vector* mse) const;

    /// Leave-one-out residuals y_i - yhat_{-i}(x_i) in closed form (same hyper-parameters).
    [[nodiscard]] Vector loo_residuals() const;
    /// Root mean square of loo_residuals().
    [[nodiscard]] double loo_rmse() const;

    [[nodiscard]] const Hyperparameters& hyperparameters() const;
    [[nodiscard]] double process_variance() const;    ///< sigma^2 in the units of y^2
    [[nodiscard]] Vector trend_coefficients() const;  ///< beta in the units of y
    [[nodiscard]] double log_likelihood() const;      ///< concentrated, at the hyper-parameters
    [[nodiscard]] const Matrix& points() const;
    [[nodiscard]] const Vector& values() const;
    [[nodiscard]] const KrigingOptions& options() const;

    Kriging(const Kriging&);
    Kriging& operator=(const Kriging&);
    Kriging(Kriging&&) noexcept;
    Kriging& operator=(Kriging&&) noexcept;
    ~Kriging();

    struct Impl;

private:
    explicit Kriging(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace manta::surrogate
