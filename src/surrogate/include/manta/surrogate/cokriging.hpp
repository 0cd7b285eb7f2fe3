#pragma once
/// @file cokriging.hpp
/// Co-Kriging of two fidelity levels by the recursive (autoregressive) formulation of Kennedy &
/// O'Hagan (2000) in the recursive form of Le Gratiet & Garnier (2014):
///   y_expensive(x) = rho * y_cheap(x) + delta(x),
/// with y_cheap any predictor (a Kriging of dense cheap samples, or a table) and delta a Kriging
/// whose trend carries the cheap prediction as an extra regressor, so that rho is a regression
/// coefficient given by generalised least squares at the maximum-likelihood hyper-parameters of
/// delta. MSE: rho^2 mse_cheap(x) + mse_delta(x). Theory and validation:
/// docs/cokriging-and-infill.md.

#include <functional>

#include "manta/surrogate/kriging.hpp"

namespace manta::surrogate {

/// The cheap level: mean and MSE at a point (MSE 0 for a deterministic source such as a table).
using CheapModel = std::function<Prediction(const Vector& x)>;

/// Two-level recursive co-Kriging. Immutable after fit; the predictions are const (thread-safe if
/// the cheap model is).
class CoKriging {
public:
    /// Fit on the expensive samples (Xe, ye) with the cheap model evaluated at them. `options` is
    /// that of the delta Kriging (its extra_regressors are replaced by the cheap prediction; with
    /// Trend::linear the trend is 1, x_1..x_d, y_cheap(x)). InputError on bad shapes, an empty
    /// cheap model, or cheap values at Xe that the rest of the trend already spans (rho not
    /// identifiable); NumericalError if the cheap model returns NaN/Inf at a sample.
    [[nodiscard]] static CoKriging fit(CheapModel cheap, const Matrix& Xe, const Vector& ye,
                                       const KrigingOptions& options);
    /// Convenience: cheap level a Kriging fitted on (Xc, yc) with `cheap_options`.
    [[nodiscard]] static CoKriging fit(const Matrix& Xc, const Vector& yc,
                                       const KrigingOptions& cheap_options, const Matrix& Xe,
                                       const Vector& ye, const KrigingOptions& options);

    /// Scale factor between the levels, in units of y_expensive per unit of y_cheap.
    [[nodiscard]] double rho() const;
    /// Predicted expensive value at x.
    [[nodiscard]] double predict(const Vector& x) const;
    /// Predicted expensive value and its MSE rho^2 mse_cheap(x) + mse_delta(x).
    [[nodiscard]] Prediction predict_with_mse(const Vector& x) const;
    /// The Kriging of the expensive samples whose trend holds rho * y_cheap(x): its predict() is
    /// the co-Kriging mean, its MSE the delta part only. This is the model to hand to the infill
    /// functions (infill.hpp) when the cheap level is exact (a table).
    [[nodiscard]] const Kriging& difference_model() const;
    /// The cheap level as given to fit().
    [[nodiscard]] const CheapModel& cheap_model() const;

private:
    CoKriging(CheapModel cheap, Kriging delta, double rho);
    CheapModel cheap_;
    Kriging delta_;
    double rho_ = 1.0;
};

}  // namespace manta::surrogate
