/// @file test_kriging.cpp
/// Kriging properties: interpolation, nugget estimation, hyper-parameter recovery from a sampled
/// Gaussian process, closed-form leave-one-out against refitting, MSE, universal trend, errors,
/// concurrency.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include "manta/core/error.hpp"
#include "manta/surrogate/design.hpp"
#include "manta/surrogate/kriging.hpp"

namespace ms = manta::surrogate;

namespace {

/// Smooth 2-D test function on the unit square.
double smooth(const ms::Vector& x) {
    return std::sin(3.0 * x[0]) + 0.5 * std::cos(5.0 * x[1]) + x[0] * x[1];
}

ms::Vector evaluate(const ms::Matrix& X, double (*f)(const ms::Vector&)) {
    ms::Vector y(X.rows());
    for (Eigen::Index i = 0; i < X.rows(); ++i) y[i] = f(X.row(i).transpose());
    return y;
}

/// Deterministic standard normal numbers (Box-Muller on a 64-bit LCG), for noise and GP draws.
class Normal {
public:
    explicit Normal(std::uint64_t seed) : state_(seed) {}
    double operator()() {
        const double u1 = uniform(), u2 = uniform();
        return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
    }

private:
    double uniform() {
        state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
        return (static_cast<double>(state_ >> 11) + 0.5) * 0x1.0p-53;
    }
    std::uint64_t state_;
};

/// Correlation of the model between rows i and j of X, for sampling GP draws.
double corr(ms::Correlation c, const ms::Vector& theta, const ms::Matrix& X, Eigen::Index i,
            Eigen::Index j) {
    double s = 0.0;
    for (Eigen::Index k = 0; k < X.cols(); ++k) s += theta[k] * std::pow(X(i, k) - X(j, k), 2);
    if (c == ms::Correlation::gaussian) return std::exp(-s);
    const double r5 = std::sqrt(5.0 * s);
    return (1.0 + r5 + r5 * r5 / 3.0) * std::exp(-r5);
}

ms::KrigingOptions options(ms::Correlation c, ms::Trend t = ms::Trend::constant) {
    ms::KrigingOptions o;
    o.correlation = c;
    o.trend = t;
    return o;
}

class BothCorrelations : public ::testing::TestWithParam<ms::Correlation> {};

}  // namespace

INSTANTIATE_TEST_SUITE_P(Kriging, BothCorrelations,
                         ::testing::Values(ms::Correlation::gaussian, ms::Correlation::matern52),
                         [](const auto& info) {
                             return info.param == ms::Correlation::gaussian ? "gaussian"
                                                                            : "matern52";
                         });

TEST_P(BothCorrelations, InterpolatesSamplesWithoutNugget) {
    const ms::Matrix X = ms::latin_hypercube(30, 2, 11);
    const ms::Vector y = evaluate(X, smooth);
    auto o = options(GetParam());
    o.nugget = 0.0;
    const auto model = ms::Kriging::fit(X, y, o);
    ms::Vector mean, mse;
    model.predict(X, mean, &mse);
    const double range = y.maxCoeff() - y.minCoeff();
    EXPECT_LT((mean - y).cwiseAbs().maxCoeff(), 1e-8 * range);
    // MSE vanishes at the samples (up to round-off of 1 - r^T R^-1 r) and not elsewhere.
    EXPECT_LT(mse.maxCoeff(), 1e-8 * model.process_variance());
    // (Outside the square: a smooth function fitted with the Gaussian correlation is so well
    // determined inside that the MSE there may be only ~1e-10 sigma^2.)
    ms::Vector away(2);
    away << 1.3, -0.2;
    EXPECT_GT(model.predict_with_mse(away).mse, 1e-4 * model.process_variance());
    EXPECT_GE(mse.minCoeff(), 0.0);
    // and predicts the function between samples.
    const ms::Matrix T = ms::latin_hypercube(200, 2, 99, 0);
    model.predict(T, mean, nullptr);
    EXPECT_LT((mean - evaluate(T, smooth)).cwiseAbs().maxCoeff(), 0.02 * range);
}

TEST_P(BothCorrelations, DefaultTinyNuggetStillInterpolates) {
    const ms::Matrix X = ms::latin_hypercube(40, 3, 5);
    ms::Vector y(X.rows());
    for (Eigen::Index i = 0; i < X.rows(); ++i)
        y[i] = std::exp(-X(i, 0)) * std::sin(4.0 * X(i, 1)) + X(i, 2) * X(i, 2);
    const auto model = ms::Kriging::fit(X, y, options(GetParam(), ms::Trend::linear));
    ms::Vector mean;
    model.predict(X, mean, nullptr);
    // The residual at sample i is nugget * sigma^2 * [R^-1 (y - F beta)]_i: small, not round-off.
    EXPECT_LT((mean - y).cwiseAbs().maxCoeff(), 1e-5 * (y.maxCoeff() - y.minCoeff()));
}

TEST_P(BothCorrelations, LeaveOneOutClosedFormEqualsRefitting) {
    // Dubrule (1983): e_i = [Q y]_i / Q_ii with the GLS projection; must equal refitting without
    // sample i at the same hyper-parameters (trend re-estimated) for every trend.
    const ms::Matrix X = ms::latin_hypercube(25, 2, 3);
    const ms::Vector y = evaluate(X, smooth);
    ms::Hyperparameters h;
    h.theta = ms::Vector::Constant(2, 4.0);
    h.theta[1] = 9.0;
    h.nugget = 1e-6;
    for (ms::Trend t : {ms::Trend::constant, ms::Trend::linear, ms::Trend::none}) {
        auto o = options(GetParam(), t);
        if (t == ms::Trend::none)  // a zero-mean process with one extra regressor
            o.extra_regressors = [](const ms::Vector& x) {
                return ms::Vector::Constant(1, std::cos(x[0]));
            };
        const auto model = ms::Kriging::with_hyperparameters(X, y, o, h);
        const ms::Vector e = model.loo_residuals();
        double worst = 0.0;
        for (Eigen::Index i = 0; i < X.rows(); ++i) {
            ms::Matrix Xi(X.rows() - 1, 2);
            ms::Vector yi(X.rows() - 1);
            for (Eigen::Index j = 0, r = 0; j < X.rows(); ++j)
                if (j != i) {
                    Xi.row(r) = X.row(j);
                    yi[r++] = y[j];
                }
            const auto sub = ms::Kriging::with_hyperparameters(Xi, yi, o, h);
            const double brute = y[i] - sub.predict(X.row(i).transpose());
            worst = std::max(worst, std::abs(e[i] - brute) / std::max(std::abs(brute), 1e-3));
        }
        EXPECT_LT(worst, 1e-8) << "trend " << static_cast<int>(t);
        EXPECT_NEAR(model.loo_rmse(), std::sqrt(e.squaredNorm() / 25.0), 1e-14);
    }
}

TEST_P(BothCorrelations, RecoversHyperparametersOfAGaussianProcessDraw) {
    // Sample one realisation of a GP with known theta at 150 points, fit, compare. The maximum
    // likelihood estimate from one draw has a spread of roughly 10-20 % at this size; the stated
    // tolerance is 35 % (seeds fixed, so the test is deterministic).
    const auto c = GetParam();
    ms::Vector theta(2);
    theta << (c == ms::Correlation::gaussian ? 3.0 : 10.0),
        (c == ms::Correlation::gaussian ? 12.0 : 40.0);
    const ms::Matrix X = ms::latin_hypercube(150, 2, 21);
    const Eigen::Index n = X.rows();
    ms::Matrix K(n, n);
    for (Eigen::Index i = 0; i < n; ++i)
        for (Eigen::Index j = 0; j < n; ++j)
            K(i, j) = corr(c, theta, X, i, j) + (i == j ? 1e-10 : 0.0);
    const Eigen::LLT<ms::Matrix> llt(K);
    ASSERT_EQ(llt.info(), Eigen::Success);
    Normal normal(1234);
    ms::Vector z(n);
    for (Eigen::Index i = 0; i < n; ++i) z[i] = normal();
    const ms::Vector y = 3.0 + 2.0 * (llt.matrixL() * z).array();  // mean 3, sigma^2 = 4
    auto o = options(c);
    o.restarts = 5;
    const auto model = ms::Kriging::fit(X, y, o);
    for (Eigen::Index k = 0; k < 2; ++k)
        EXPECT_NEAR(std::log(model.hyperparameters().theta[k] / theta[k]), 0.0, std::log(1.35))
            << "theta " << k << " = " << model.hyperparameters().theta[k] << ", true " << theta[k];
    EXPECT_NEAR(model.process_variance() / 4.0, 1.0, 0.6);
}

TEST_P(BothCorrelations, LikelihoodIsStationaryAtTheFittedHyperparameters) {
    // Checks the analytic gradient indirectly: L-BFGS stops where the finite-difference
    // derivative of the likelihood (with respect to log theta and log nugget) vanishes or points
    // out of the bounds.
    const ms::Matrix X = ms::latin_hypercube(40, 2, 8);
    ms::Vector y = evaluate(X, smooth);
    Normal normal(5);
    for (Eigen::Index i = 0; i < y.size(); ++i) y[i] += 0.05 * normal();
    auto o = options(GetParam());
    o.estimate_nugget = true;
    const auto model = ms::Kriging::fit(X, y, o);
    const ms::Hyperparameters h = model.hyperparameters();
    const double l0 = model.log_likelihood();
    const double step = 1e-4;
    for (int k = 0; k < 3; ++k) {
        auto hp = h, hm = h;
        if (k < 2) {
            hp.theta[k] *= std::exp(step);
            hm.theta[k] *= std::exp(-step);
        } else {
            hp.nugget *= std::exp(step);
            hm.nugget *= std::exp(-step);
        }
        const double lp = ms::Kriging::with_hyperparameters(X, y, o, hp).log_likelihood();
        const double lm = ms::Kriging::with_hyperparameters(X, y, o, hm).log_likelihood();
        EXPECT_NEAR((lp - lm) / (2 * step), 0.0, 2e-3) << "parameter " << k;
        EXPECT_LE(std::max(lp, lm), l0 + 1e-8);
    }
}

TEST(Kriging, EstimatesTheNuggetOfNoisyData) {
    const ms::Matrix X = ms::latin_hypercube(120, 2, 17);
    ms::Vector y = evaluate(X, smooth);
    Normal normal(77);
    const double noise_sd = 0.1;
    for (Eigen::Index i = 0; i < y.size(); ++i) y[i] += noise_sd * normal();
    auto o = options(ms::Correlation::gaussian);
    o.estimate_nugget = true;
    const auto model = ms::Kriging::fit(X, y, o);
    const double noise_var = model.hyperparameters().nugget * model.process_variance();
    EXPECT_GT(model.hyperparameters().nugget, 1e-4);
    EXPECT_NEAR(noise_var / (noise_sd * noise_sd), 1.0, 0.5) << "noise variance " << noise_var;
    // Without the nugget the model interpolates the noise: worse leave-one-out error.
    o.estimate_nugget = false;
    const auto interp = ms::Kriging::fit(X, y, o);
    EXPECT_LT(model.loo_rmse(), interp.loo_rmse());
}

TEST(Kriging, UniversalTrendReproducesALinearFunction) {
    const ms::Matrix X = ms::latin_hypercube(12, 2, 4);
    ms::Vector y(X.rows());
    for (Eigen::Index i = 0; i < X.rows(); ++i) y[i] = 1.0 + 2.0 * X(i, 0) - 3.0 * X(i, 1);
    ms::Hyperparameters h{ms::Vector::Constant(2, 5.0), 1e-10};
    const auto model = ms::Kriging::with_hyperparameters(
        X, y, options(ms::Correlation::matern52, ms::Trend::linear), h);
    const ms::Vector beta = model.trend_coefficients();
    ASSERT_EQ(beta.size(), 3);
    EXPECT_NEAR(beta[0], 1.0, 1e-10);
    EXPECT_NEAR(beta[1], 2.0, 1e-10);
    EXPECT_NEAR(beta[2], -3.0, 1e-10);
    for (double a : {-0.5, 0.3, 1.7}) {
        ms::Vector x(2);
        x << a, 1.0 - a;
        EXPECT_NEAR(model.predict(x), 1.0 + 2.0 * a - 3.0 * (1.0 - a), 1e-10);
    }
    // The trend term of the MSE grows far outside the data.
    ms::Vector near(2), far(2);
    near << 0.5, 0.5;
    far << 5.0, 5.0;
    EXPECT_GT(model.predict_with_mse(far).mse, model.predict_with_mse(near).mse);
}

TEST(Kriging, BatchAndSinglePredictionsAgreeAcrossThreads) {
    const ms::Matrix X = ms::latin_hypercube(50, 3, 2);
    ms::Vector y(X.rows());
    for (Eigen::Index i = 0; i < X.rows(); ++i) y[i] = std::sin(X.row(i).sum() * 3.0);
    const auto model =
        ms::Kriging::fit(X, y, options(ms::Correlation::gaussian, ms::Trend::linear));
    const ms::Matrix T = ms::latin_hypercube(700, 3, 9, 0);  // more than one prediction block
    ms::Vector mean, mse;
    model.predict(T, mean, &mse);
    std::vector<ms::Vector> means(4, ms::Vector(T.rows())), mses(4, ms::Vector(T.rows()));
    std::vector<std::thread> pool;
    for (int t = 0; t < 4; ++t)
        pool.emplace_back([&, t] {
            for (Eigen::Index i = 0; i < T.rows(); ++i) {
                const auto p = model.predict_with_mse(T.row(i).transpose());
                means[t][i] = p.mean;
                mses[t][i] = p.mse;
            }
        });
    for (auto& th : pool) th.join();
    for (int t = 0; t < 4; ++t) {
        EXPECT_LT((means[t] - mean).cwiseAbs().maxCoeff(), 1e-12);
        EXPECT_LT((mses[t] - mse).cwiseAbs().maxCoeff(), 1e-12);
    }
}

TEST(Kriging, DeterministicPerSeed) {
    const ms::Matrix X = ms::latin_hypercube(30, 2, 1);
    const ms::Vector y = evaluate(X, smooth);
    const auto a = ms::Kriging::fit(X, y, options(ms::Correlation::gaussian));
    const auto b = ms::Kriging::fit(X, y, options(ms::Correlation::gaussian));
    EXPECT_EQ(a.hyperparameters().theta, b.hyperparameters().theta);
    const ms::Kriging c = a;  // copies are independent and equal
    EXPECT_EQ(c.predict(X.row(3).transpose()), a.predict(X.row(3).transpose()));
}

TEST(Kriging, RejectsBadInput) {
    const ms::Matrix X = ms::latin_hypercube(10, 2, 1);
    const ms::Vector y = evaluate(X, smooth);
    const auto o = options(ms::Correlation::gaussian);
    EXPECT_THROW((void)ms::Kriging::fit(X, y.head(9), o), manta::InputError);
    ms::Matrix Xn = X;
    Xn(4, 1) = std::nan("");
    EXPECT_THROW((void)ms::Kriging::fit(Xn, y, o), manta::InputError);
    ms::Vector yn = y;
    yn[2] = INFINITY;
    EXPECT_THROW((void)ms::Kriging::fit(X, yn, o), manta::InputError);
    ms::Matrix Xd = X;
    Xd.row(7) = X.row(2);
    try {
        (void)ms::Kriging::fit(Xd, y, o);
        FAIL() << "duplicates accepted";
    } catch (const manta::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("2 and 7"), std::string::npos) << e.what();
    }
    EXPECT_THROW((void)ms::Kriging::fit(X.topRows(2), y.head(2),
                                        options(ms::Correlation::gaussian, ms::Trend::linear)),
                 manta::InputError);
    auto bad = o;
    bad.theta_min = -1.0;
    EXPECT_THROW((void)ms::Kriging::fit(X, y, bad), manta::InputError);
    EXPECT_THROW((void)ms::Kriging::with_hyperparameters(X, y, o, {ms::Vector::Ones(3), 0.0}),
                 manta::InputError);
    const auto model = ms::Kriging::fit(X, y, o);
    EXPECT_THROW((void)model.predict(ms::Vector::Zero(3)), manta::InputError);
    // An almost constant correlation (tiny theta) without nugget is singular at every start.
    auto flat = o;
    flat.theta_min = 1e-12;
    flat.theta_max = 1e-11;
    flat.nugget = 0.0;
    EXPECT_THROW((void)ms::Kriging::fit(X, y, flat), manta::ConvergenceError);
}

TEST(Kriging, ScreeningOnASubsetReachesTheFullMultiStartOptimum) {
    // With more samples than screening_points, the starts run on a spread subset and the best
    // optimum is polished on all samples: the likelihood reached must match the plain multi-start.
    const ms::Matrix X = ms::latin_hypercube(160, 3, 12);
    ms::Vector y(X.rows());
    for (Eigen::Index i = 0; i < X.rows(); ++i)
        y[i] = std::sin(4.0 * X(i, 0)) * std::exp(-X(i, 1)) + 0.3 * X(i, 2) * X(i, 2);
    auto o = options(ms::Correlation::gaussian);
    o.screening_points = 60;
    const auto screened = ms::Kriging::fit(X, y, o);
    o.screening_points = 0;
    const auto full = ms::Kriging::fit(X, y, o);
    EXPECT_GT(screened.log_likelihood(), full.log_likelihood() - 1e-3);
    for (Eigen::Index k = 0; k < 3; ++k)
        EXPECT_NEAR(screened.hyperparameters().theta[k] / full.hyperparameters().theta[k], 1.0,
                    1e-2);
}
