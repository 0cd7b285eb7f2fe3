// Infill criteria: expected improvement values, maximum MSE, Kriging-believer batches, exclusion
// of sampled candidates, the combined multi-model criterion and the box search.
// Reference: Jones, Schonlau & Welch, "Efficient global optimization of expensive black-box
// functions", J. Global Optim. 13 (1998) 455-492, eq. (15) for the expected improvement.

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "manta/core/error.hpp"
#include "manta/surrogate/cokriging.hpp"
#include "manta/surrogate/design.hpp"
#include "manta/surrogate/infill.hpp"
#include "manta/surrogate/kriging.hpp"

namespace {

using namespace manta::surrogate;

/// 1-D Kriging through (x, f(x)) with a fixed Gaussian correlation parameter (no likelihood
/// search: the tests then depend on the geometry of the samples only).
template <class F>
Kriging line_model(const std::vector<double>& xs, F f, double theta = 20.0) {
    Matrix X(static_cast<Eigen::Index>(xs.size()), 1);
    Vector y(X.rows());
    for (Eigen::Index i = 0; i < X.rows(); ++i) {
        X(i, 0) = xs[static_cast<std::size_t>(i)];
        y(i) = f(X(i, 0));
    }
    Hyperparameters h;
    h.theta = Vector::Constant(1, theta);
    h.nugget = 1e-10;
    return Kriging::with_hyperparameters(X, y, KrigingOptions{}, h);
}

/// Candidates 0, 0.01, ..., 1 as rows.
Matrix grid_101() {
    Matrix c(101, 1);
    for (int i = 0; i <= 100; ++i) c(i, 0) = 0.01 * i;
    return c;
}

double wave(double x) {
    return std::sin(6.0 * x) + 0.5 * x;
}

TEST(ExpectedImprovement, HandComputedValues) {
    // Zero MSE: the limit of the closed form is the plain improvement, max(y_best - mean, 0).
    EXPECT_DOUBLE_EQ(expected_improvement({1.0, 0.0}, 3.0), 2.0);
    EXPECT_DOUBLE_EQ(expected_improvement({3.0, 0.0}, 1.0), 0.0);
    // (y_best - m) Phi(z) + s phi(z), values from the same formula evaluated with erfc in Python.
    EXPECT_NEAR(expected_improvement({0.0, 1.0}, 0.0), 0.3989422804014327, 1e-15);  // phi(0)
    EXPECT_NEAR(expected_improvement({0.0, 4.0}, 1.0), 1.3955931148026122, 1e-14);
    EXPECT_NEAR(expected_improvement({2.0, 0.25}, 1.0), 0.004245351308414812, 1e-16);
    EXPECT_NEAR(expected_improvement({-1.0, 9.0}, 1.0), 2.453358941473211, 1e-14);
    // Far below y_best with a small MSE it tends to the improvement; far above, to 0.
    EXPECT_NEAR(expected_improvement({-10.0, 1e-4}, 0.0), 10.0, 1e-12);
    EXPECT_GE(expected_improvement({50.0, 1.0}, 0.0), 0.0);
    EXPECT_LT(expected_improvement({50.0, 1.0}, 0.0), 1e-300);
}

TEST(ExpectedImprovement, GrowsWithUncertaintyAndImprovement) {
    double previous = 0.0;
    for (double mse : {0.01, 0.1, 1.0, 10.0}) {
        const double ei = expected_improvement({1.0, mse}, 0.5);
        EXPECT_GT(ei, previous);
        previous = ei;
    }
    EXPECT_GT(expected_improvement({0.0, 1.0}, 0.5), expected_improvement({0.2, 1.0}, 0.5));
}

TEST(MaxMse, PicksThePointFarthestFromTheSamples) {
    const Kriging k = line_model({0.0, 0.1, 0.2, 0.3}, wave);
    InfillOptions o;
    o.criterion = Criterion::max_mse;
    const auto picks = propose_from({&k}, grid_101(), o);
    ASSERT_EQ(picks.size(), 1u);
    EXPECT_EQ(picks.front(), 100);
    // The same in the box: the far end of [0, 1].
    const Matrix p = propose_in({&k}, Bounds{Vector::Zero(1), Vector::Ones(1)}, o);
    ASSERT_EQ(p.rows(), 1);
    EXPECT_NEAR(p(0, 0), 1.0, 1e-6);
}

TEST(MaxMse, BatchSpreadsOut) {
    const Kriging k = line_model({0.0, 0.5, 1.0}, wave);
    InfillOptions o;
    o.batch = 4;
    const auto picks = propose_from({&k}, grid_101(), o);
    ASSERT_EQ(picks.size(), 4u);
    // Without the believer update all four would be the same gap; with it they fill the gaps.
    for (std::size_t a = 0; a < picks.size(); ++a) {
        for (std::size_t b = a + 1; b < picks.size(); ++b) {
            EXPECT_GE(std::abs(picks[a] - picks[b]), 10) << picks[a] << " " << picks[b];
        }
    }
    // The first pick is in the middle of a gap.
    EXPECT_TRUE(std::abs(picks[0] - 25) <= 2 || std::abs(picks[0] - 75) <= 2) << picks[0];
}

TEST(Infill, BatchInTheBoxIsDistinctInBoundsAndDeterministic) {
    const Matrix X = latin_hypercube(8, 2, 7);
    Vector y(X.rows());
    for (Eigen::Index i = 0; i < X.rows(); ++i)
        y(i) = std::sin(4 * X(i, 0)) * std::cos(3 * X(i, 1));
    Hyperparameters h;
    h.theta = Vector::Constant(2, 5.0);
    const Kriging k = Kriging::with_hyperparameters(X, y, KrigingOptions{}, h);
    const Bounds box{Vector::Zero(2), Vector::Ones(2)};
    for (Criterion c : {Criterion::max_mse, Criterion::expected_improvement}) {
        InfillOptions o;
        o.criterion = c;
        o.batch = 5;
        o.search_points = 500;
        o.seed = 3;
        const Matrix p = propose_in({&k}, box, o);
        ASSERT_EQ(p.rows(), 5);
        EXPECT_TRUE((p.array() >= 0.0).all() && (p.array() <= 1.0).all());
        EXPECT_GT(min_distance(p), 0.05);
        // Not at a sample either.
        for (Eigen::Index i = 0; i < p.rows(); ++i) {
            EXPECT_GT((X.rowwise() - p.row(i)).rowwise().norm().minCoeff(), 1e-3);
        }
        EXPECT_EQ(p, propose_in({&k}, box, o));  // same seed, same points
    }
}

TEST(Infill, SampledCandidatesAreNeverChosen) {
    const std::vector<double> xs{0.0, 0.2, 0.45, 0.7, 1.0};
    const Kriging k = line_model(xs, wave);
    Matrix sampled(5, 1);
    for (int i = 0; i < 5; ++i) sampled(i, 0) = xs[static_cast<std::size_t>(i)];
    for (Criterion c : {Criterion::max_mse, Criterion::expected_improvement}) {
        InfillOptions o;
        o.criterion = c;
        o.batch = 3;
        EXPECT_TRUE(propose_from({&k}, sampled, o).empty());
        // Two samples and two new points, one of them closer than min_separation to a sample.
        Matrix mixed(4, 1);
        mixed << 0.2, 0.45 + 0.5 * o.min_separation, 0.33, 0.85;
        const auto picks = propose_from({&k}, mixed, o);
        const std::set<Eigen::Index> got(picks.begin(), picks.end());
        EXPECT_EQ(got, (std::set<Eigen::Index>{2, 3}));
    }
}

TEST(Infill, CombinedCriterionIsTheSumOfNormalisedMse) {
    // A lacks samples near 1, B near 0; A's gap is the larger one.
    const Kriging a = line_model({0.0, 0.2, 0.4, 0.6}, wave);
    const Kriging b = line_model({0.3, 0.5, 0.7, 0.9, 1.0}, wave);
    const Kriging b_scaled =
        line_model({0.3, 0.5, 0.7, 0.9, 1.0}, [](double x) { return 1e4 * wave(x); });
    const Matrix c = grid_101();
    const Vector va = criterion_values({&a}, c, Criterion::max_mse);
    const Vector vb = criterion_values({&b}, c, Criterion::max_mse);
    const Vector vab = criterion_values({&a, &b}, c, Criterion::max_mse);
    for (Eigen::Index i = 0; i < c.rows(); i += 7) {
        const Vector x = c.row(i).transpose();
        EXPECT_NEAR(va(i), a.predict_with_mse(x).mse / a.process_variance(), 1e-12);
        EXPECT_NEAR(vab(i), va(i) + vb(i), 1e-12);
    }
    InfillOptions o;
    const auto pick = propose_from({&a, &b}, c, o);
    const auto pick_scaled = propose_from({&a, &b_scaled}, c, o);
    ASSERT_EQ(pick.size(), 1u);
    EXPECT_GT(pick[0], 60);  // A's gap wins: near x = 1
    // B's outputs 1e4 times larger (MSE 1e8 times) do not change the choice.
    EXPECT_EQ(pick, pick_scaled);
    EXPECT_EQ(propose_from({&b_scaled}, c, o).front(), 0);  // alone, B wants x = 0
}

TEST(ExpectedImprovement, PicksNearThePredictedMinimum) {
    const Kriging k = line_model(
        {0.0, 0.25, 0.5, 0.75, 1.0}, [](double x) { return (x - 0.37) * (x - 0.37); }, 5.0);
    InfillOptions o;
    o.criterion = Criterion::expected_improvement;
    const Matrix p = propose_in({&k}, Bounds{Vector::Zero(1), Vector::Ones(1)}, o);
    EXPECT_NEAR(p(0, 0), 0.37, 0.05);
    const auto picks = propose_from({&k}, grid_101(), o);
    EXPECT_NEAR(0.01 * static_cast<double>(picks.front()), 0.37, 0.05);
}

TEST(Infill, BatchOnACoKrigingDifferenceModel) {
    // The control-table use: an exact cheap level (a table) and a few expensive samples; the
    // difference model's trend holds rho * cheap(x), and the believer refit keeps it.
    const CheapModel table = [](const Vector& x) { return Prediction{wave(x(0)), 0.0}; };
    Matrix Xe(4, 1);
    Xe << 0.0, 0.3, 0.6, 1.0;
    Vector ye(4);
    for (int i = 0; i < 4; ++i) ye(i) = 1.5 * wave(Xe(i, 0)) + std::cos(3.0 * Xe(i, 0));
    // With four samples the likelihood otherwise runs to theta_min = 1e-3, where the MSE is flat
    // at round-off level (1e-10 of sigma^2) and its maximum meaningless.
    KrigingOptions ko;
    ko.theta_min = 1.0;
    const CoKriging ck = CoKriging::fit(table, Xe, ye, ko);
    InfillOptions o;
    o.batch = 3;
    const auto picks = propose_from({&ck.difference_model()}, grid_101(), o);
    ASSERT_EQ(picks.size(), 3u);
    const std::set<Eigen::Index> distinct(picks.begin(), picks.end());
    EXPECT_EQ(distinct.size(), 3u);
    for (Eigen::Index i : picks) {
        EXPECT_GT((Xe.array() - 0.01 * static_cast<double>(i)).abs().minCoeff(), 0.05);
    }
}

TEST(Infill, RejectsBadInput) {
    const Kriging k = line_model({0.0, 0.5, 1.0}, wave);
    InfillOptions o;
    EXPECT_THROW((void)propose_from({}, grid_101(), o), manta::InputError);
    EXPECT_THROW((void)propose_from({nullptr}, grid_101(), o), manta::InputError);
    EXPECT_THROW((void)propose_from({&k}, Matrix::Zero(3, 2), o), manta::InputError);
    o.batch = 0;
    EXPECT_THROW((void)propose_from({&k}, grid_101(), o), manta::InputError);
    o.batch = 1;
    EXPECT_THROW((void)propose_in({&k}, Bounds{Vector::Ones(1), Vector::Zero(1)}, o),
                 manta::InputError);
}

}  // namespace
