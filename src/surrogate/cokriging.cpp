#include "manta/surrogate/cokriging.hpp"

#include <fmt/format.h>

#include <cmath>
#include <memory>
#include <utility>

#include "manta/core/error.hpp"

namespace manta::surrogate {

namespace {

/// Trend matrix of the delta Kriging without its Gaussian-process part: 1 (constant and linear
/// trends), the inputs (linear trend) and the cheap values. Only used to check that rho is
/// identifiable.
Matrix trend_matrix(const Matrix& X, const Vector& cheap_values, Trend trend) {
    const Eigen::Index n = X.rows();
    const Eigen::Index c = trend == Trend::none ? 0 : 1;
    const Eigen::Index d = trend == Trend::linear ? X.cols() : 0;
    Matrix F(n, c + d + 1);
    if (c > 0) F.col(0).setOnes();
    if (d > 0) F.middleCols(c, d) = X;
    F.col(c + d) = cheap_values;
    return F;
}

}  // namespace

CoKriging::CoKriging(CheapModel cheap, Kriging delta, double rho)
    : cheap_(std::move(cheap)), delta_(std::move(delta)), rho_(rho) {}

CoKriging CoKriging::fit(CheapModel cheap, const Matrix& Xe, const Vector& ye,
                         const KrigingOptions& options) {
    if (!cheap) throw InputError("co-Kriging: the cheap model is empty; expected a predictor");
    if (Xe.rows() != ye.size() || Xe.rows() == 0) {
        throw InputError(fmt::format(
            "co-Kriging: {} expensive points but {} values; expected as many, at least one",
            Xe.rows(), ye.size()));
    }
    Vector cheap_at_samples(Xe.rows());
    for (Eigen::Index i = 0; i < Xe.rows(); ++i) {
        cheap_at_samples(i) = cheap(Xe.row(i).transpose()).mean;
        if (!std::isfinite(cheap_at_samples(i))) {
            throw NumericalError(
                fmt::format("co-Kriging: the cheap model gives {} at expensive sample {}; expected "
                            "a finite value",
                            cheap_at_samples(i), i));
        }
    }
    // rho is the coefficient of the cheap values in the trend; it is undetermined when those
    // values are (numerically) a combination of the other trend columns, e.g. a constant.
    const Matrix F = trend_matrix(Xe, cheap_at_samples, options.trend);
    Eigen::ColPivHouseholderQR<Matrix> qr(F);
    qr.setThreshold(1e-10);
    if (qr.rank() < F.cols()) {
        throw InputError(fmt::format(
            "co-Kriging: the cheap model's values at the {} expensive samples are spanned by the "
            "rest of the trend (rank {} of {}); rho cannot be estimated, add expensive samples",
            Xe.rows(), qr.rank(), F.cols()));
    }

    KrigingOptions delta_options = options;
    delta_options.extra_regressors = [cheap](const Vector& x) {
        Vector r(1);
        r(0) = cheap(x).mean;
        return r;
    };
    Kriging delta = Kriging::fit(Xe, ye, delta_options);
    // The trend coefficients are in the units of y (kriging.hpp); the cheap regressor is the last.
    const Vector beta = delta.trend_coefficients();
    const double rho = beta(beta.size() - 1);
    return {std::move(cheap), std::move(delta), rho};
}

CoKriging CoKriging::fit(const Matrix& Xc, const Vector& yc, const KrigingOptions& cheap_options,
                         const Matrix& Xe, const Vector& ye, const KrigingOptions& options) {
    // Shared so that copies of the std::function do not copy the cheap Kriging.
    auto cheap_model = std::make_shared<const Kriging>(Kriging::fit(Xc, yc, cheap_options));
    CheapModel cheap = [cheap_model](const Vector& x) { return cheap_model->predict_with_mse(x); };
    return fit(std::move(cheap), Xe, ye, options);
}

double CoKriging::rho() const {
    return rho_;
}

double CoKriging::predict(const Vector& x) const {
    return delta_.predict(x);
}

Prediction CoKriging::predict_with_mse(const Vector& x) const {
    Prediction p = delta_.predict_with_mse(x);
    p.mse += rho_ * rho_ * cheap_(x).mse;
    return p;
}

const Kriging& CoKriging::difference_model() const {
    return delta_;
}

const CheapModel& CoKriging::cheap_model() const {
    return cheap_;
}

}  // namespace manta::surrogate
