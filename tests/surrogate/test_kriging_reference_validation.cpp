/// @file test_kriging_reference_validation.cpp
/// MANTA's Kriging against an independent implementation on the same data and the same fixed
/// hyper-parameters, to 1e-8 relative.
///
/// Reference: scikit-learn 1.2.1 GaussianProcessRegressor (F. Pedregosa et al., "Scikit-learn:
/// Machine Learning in Python", Journal of Machine Learning Research 12, 2825-2830, 2011),
/// zero-mean process with a fixed ConstantKernel * RBF or * Matern(nu = 2.5) kernel: posterior
/// mean, standard deviation and log-marginal likelihood; and generalised-least-squares ordinary and
/// universal Kriging written out in numpy (LU solves), with leave-one-out residuals by brute-force
/// refitting. The values were computed once by scripts/reference/gp_reference.py (its docstring
/// says how each quantity maps to MANTA's) and are stored in tests/data/surrogate/.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "manta/surrogate/kriging.hpp"

namespace ms = manta::surrogate;

namespace {

constexpr double kTolerance = 1e-8;

/// The records of a reference file: key -> rows of numbers (and the correlation name).
struct Reference {
    std::string correlation;
    std::map<std::string, std::vector<std::vector<double>>> rows;
    [[nodiscard]] const std::vector<std::vector<double>>& at(const std::string& key) const {
        const auto it = rows.find(key);
        if (it == rows.end()) throw std::runtime_error("reference file has no record " + key);
        return it->second;
    }
};

Reference read_reference(const std::string& name) {
    const std::string path =
        std::string(MANTA_SOURCE_DIR) + "/tests/data/surrogate/gp_reference_" + name + ".csv";
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot open " + path);
    Reference ref;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::stringstream ss(line);
        std::string key, field;
        std::getline(ss, key, ',');
        if (key == "correlation") {
            std::getline(ss, ref.correlation);
            continue;
        }
        std::vector<double> values;
        while (std::getline(ss, field, ',')) values.push_back(std::stod(field));
        ref.rows[key].push_back(std::move(values));
    }
    return ref;
}

/// Largest |a - b| / max(|b|, floor) over a column.
double worst_relative(const ms::Vector& a, const std::vector<double>& b, double floor) {
    double worst = 0.0;
    for (Eigen::Index i = 0; i < a.size(); ++i)
        worst = std::max(worst, std::abs(a[i] - b[static_cast<std::size_t>(i)]) /
                                    std::max(std::abs(b[static_cast<std::size_t>(i)]), floor));
    return worst;
}

double relative(double a, double b) {
    return std::abs(a - b) / std::abs(b);
}

std::vector<double> column(const std::vector<std::vector<double>>& rows, std::size_t c) {
    std::vector<double> out;
    for (const auto& r : rows) out.push_back(r.at(c));
    return out;
}

struct Case {
    Reference ref;
    ms::Matrix X, T;
    ms::Vector y;
    ms::Hyperparameters h;
    ms::KrigingOptions options;
};

Case load(const std::string& name) {
    Case c;
    c.ref = read_reference(name);
    const auto& train = c.ref.at("train");
    const auto& test = c.ref.at("test");
    const auto d = static_cast<Eigen::Index>(train.front().size() - 1);
    c.X.resize(static_cast<Eigen::Index>(train.size()), d);
    c.y.resize(c.X.rows());
    for (Eigen::Index i = 0; i < c.X.rows(); ++i) {
        for (Eigen::Index k = 0; k < d; ++k) c.X(i, k) = train[i][k];
        c.y[i] = train[i][d];
    }
    c.T.resize(static_cast<Eigen::Index>(test.size()), d);
    for (Eigen::Index i = 0; i < c.T.rows(); ++i)
        for (Eigen::Index k = 0; k < d; ++k) c.T(i, k) = test[i][k];
    const auto& theta = c.ref.at("theta").front();
    c.h.theta = Eigen::Map<const ms::Vector>(theta.data(), static_cast<Eigen::Index>(theta.size()));
    c.h.nugget = c.ref.at("nugget").front().front();
    c.options.correlation =
        c.ref.correlation == "gaussian" ? ms::Correlation::gaussian : ms::Correlation::matern52;
    return c;
}

class ReferenceCase : public ::testing::TestWithParam<std::string> {};

}  // namespace

INSTANTIATE_TEST_SUITE_P(Kriging, ReferenceCase,
                         ::testing::Values("gaussian_2d", "matern52_3d", "gaussian_3d_noisy"));

TEST_P(ReferenceCase, ZeroMeanProcessMatchesScikitLearn) {
    Case c = load(GetParam());
    c.options.trend = ms::Trend::none;
    const auto model = ms::Kriging::with_hyperparameters(c.X, c.y, c.options, c.h);
    ms::Vector mean, mse;
    model.predict(c.T, mean, &mse);
    const auto& pred = c.ref.at("sklearn_pred");
    const double sigma2 = c.ref.at("sklearn_summary")[0][0];
    const double lml = c.ref.at("sklearn_summary")[0][1];
    // sklearn's variance is sigma^2 (1 - r^T R^-1 r); MANTA's MSE adds the nugget's sigma^2 eta.
    std::vector<double> variance;
    for (const auto& r : pred) variance.push_back(r[1] * r[1] + sigma2 * c.h.nugget);
    const double scale = c.y.cwiseAbs().maxCoeff();
    const double e_mean = worst_relative(mean, column(pred, 0), 1e-6 * scale);
    const double e_mse = worst_relative(mse, variance, 0.0);
    const double e_s2 = relative(model.process_variance(), sigma2);
    const double e_ll = relative(model.log_likelihood(), lml);
    EXPECT_LT(e_mean, kTolerance);
    EXPECT_LT(e_mse, kTolerance);
    EXPECT_LT(e_s2, kTolerance);
    EXPECT_LT(e_ll, kTolerance);
    std::printf(
        "  %s vs scikit-learn: max rel. diff mean %.2e, mse %.2e, sigma2 %.2e, loglik %.2e\n",
        GetParam().c_str(), e_mean, e_mse, e_s2, e_ll);
}

TEST_P(ReferenceCase, GlsKrigingMatchesNumpy) {
    Case c = load(GetParam());
    const double scale = c.y.cwiseAbs().maxCoeff();
    for (auto [trend, key] :
         {std::pair{ms::Trend::none, "gls_none"}, std::pair{ms::Trend::constant, "gls_constant"},
          std::pair{ms::Trend::linear, "gls_linear"}}) {
        c.options.trend = trend;
        const auto model = ms::Kriging::with_hyperparameters(c.X, c.y, c.options, c.h);
        ms::Vector mean, mse;
        model.predict(c.T, mean, &mse);
        const std::string k(key);
        const auto& summary = c.ref.at(k + "_summary").front();
        const auto& pred = c.ref.at(k + "_pred");
        const double e_mean = worst_relative(mean, column(pred, 0), 1e-6 * scale);
        const double e_mse = worst_relative(mse, column(pred, 1), 0.0);
        const double e_s2 = relative(model.process_variance(), summary[0]);
        const double e_ll = relative(model.log_likelihood(), summary[1]);
        const std::vector<double> beta_ref(summary.begin() + 2, summary.end());
        const ms::Vector beta = model.trend_coefficients();
        ASSERT_EQ(static_cast<std::size_t>(beta.size()), beta_ref.size());
        const double e_beta = worst_relative(beta, beta_ref, 1e-6 * scale);
        const double e_loo =
            worst_relative(model.loo_residuals(), column(c.ref.at(k + "_loo"), 0), 1e-6 * scale);
        EXPECT_LT(e_mean, kTolerance) << k;
        EXPECT_LT(e_mse, kTolerance) << k;
        EXPECT_LT(e_s2, kTolerance) << k;
        EXPECT_LT(e_ll, kTolerance) << k;
        EXPECT_LT(e_beta, kTolerance) << k;
        EXPECT_LT(e_loo, kTolerance) << k;
        std::printf(
            "  %s %s vs numpy: max rel. diff mean %.2e, mse %.2e, sigma2 %.2e, loglik "
            "%.2e, beta %.2e, loo %.2e\n",
            GetParam().c_str(), key, e_mean, e_mse, e_s2, e_ll, e_beta, e_loo);
    }
}
