// The NLP's exact first and second derivatives (forward AD per node, constant differentiation
// matrix part) against central finite differences, dense, on every validation problem, with
// one and several segments and free segment breaks.

#include <gtest/gtest.h>

#include "manta/optimal/problems.hpp"

namespace {

using namespace manta::optimal;

void expect_derivatives(const Model& model, const Mesh& mesh, const Guess& guess, double tol) {
    const DerivativeCheck c = check_derivatives(model, mesh, guess, 0.02, 7);
    EXPECT_LT(c.gradient_error, tol);
    EXPECT_LT(c.jacobian_error, tol) << "worst row " << c.worst_row << " column " << c.worst_col;
    EXPECT_LT(c.hessian_error, tol);
}

Mesh free_mesh(std::vector<int> nodes, std::vector<double> breaks) {
    Mesh m;
    m.nodes = std::move(nodes);
    m.breaks = std::move(breaks);
    m.free_breaks = true;
    return m;
}

TEST(NlpDerivatives, Brachistochrone) {
    const Brachistochrone p;
    const auto m = make_model(p);
    expect_derivatives(*m, Mesh::uniform(1, 12), p.guess(), 2e-6);
    expect_derivatives(*m, free_mesh({6, 7, 5}, {0.0, 0.3, 0.7, 1.0}), p.guess(), 2e-6);
}

TEST(NlpDerivatives, DoubleIntegratorWithPathConstraint) {
    DoubleIntegrator p;
    p.max_speed = 2.0;
    const auto m = make_model(p);
    expect_derivatives(*m, Mesh::uniform(2, 8), p.guess(), 2e-6);
    expect_derivatives(*m, free_mesh({8, 8}, {0.0, 0.6, 1.0}), p.guess(), 2e-6);
}

TEST(NlpDerivatives, MinTimeToClimbBothAtmospheres) {
    for (const auto atm :
         {MinTimeToClimb::Atmosphere::us1976, MinTimeToClimb::Atmosphere::troposphere_only}) {
        MinTimeToClimb p;
        p.atmosphere = atm;
        const auto m = make_model(p);
        expect_derivatives(*m, Mesh::uniform(1, 10), p.guess(), 1e-5);
        expect_derivatives(*m, free_mesh({6, 6}, {0.0, 0.4, 1.0}), p.guess(), 1e-5);
    }
}

/// A problem with a Lagrange cost, a static parameter, events and a free initial time
/// exercises every block of the transcription.
struct AllFeatures {
    ProblemInfo info() const {
        ProblemInfo p;
        p.name = "all-features";
        p.states = {{"a", -5, 5, 0}, {"b", -5, 5, 0}};
        p.controls = {{"c", -2, 2, 0}};
        p.parameters = {{"k", 0.1, 3.0, 0}};
        p.path = {{"mix", -10, 1.5, 0}};
        p.events = {{"end_sum", 1.0, 1.0, 0}, {"start_a", 0.5, 0.5, 0}};
        p.initial_time = {-1.0, 1.0};
        p.final_time = {1.5, 4.0};
        return p;
    }
    template <class T>
    void dynamics(std::span<const T> x, std::span<const T> u, std::span<const T> p, const T& t,
                  std::span<T> xd) const {
        using std::sin;
        xd[0] = x[1] * p[0] + sin(t);
        xd[1] = u[0] * u[0] - x[0] * x[1];
    }
    template <class T>
    void path(std::span<const T> x, std::span<const T> u, std::span<const T>, const T& t,
              std::span<T> g) const {
        g[0] = x[0] * u[0] + t * x[1];
    }
    template <class T>
    T lagrange(std::span<const T> x, std::span<const T> u, std::span<const T> p, const T& t) const {
        return u[0] * u[0] + p[0] * x[0] * x[0] + t * x[1];
    }
    template <class T>
    void events(std::span<const T> x0, std::span<const T> xf, std::span<const T> p, const T& t0,
                const T& tf, std::span<T> e) const {
        e[0] = xf[0] + xf[1] * p[0] + tf * t0;
        e[1] = x0[0];
    }
    template <class T>
    T mayer(std::span<const T> x0, std::span<const T> xf, std::span<const T>, const T& t0,
            const T& tf) const {
        return xf[0] * xf[1] + x0[1] * tf + t0 * t0;
    }
};

TEST(NlpDerivatives, LagrangeParametersEventsFreeInitialTime) {
    const auto m = make_model(AllFeatures{});
    const Guess g =
        Guess::linear(0.1, 2.5, Eigen::Vector2d(0.5, 0.2), Eigen::Vector2d(0.8, 0.3),
                      Eigen::VectorXd::Constant(1, 0.3), Eigen::VectorXd::Constant(1, -0.4),
                      Eigen::VectorXd::Constant(1, 1.1));
    expect_derivatives(*m, Mesh::uniform(1, 9), g, 2e-6);
    expect_derivatives(*m, free_mesh({5, 6, 4}, {0.0, 0.25, 0.6, 1.0}), g, 2e-6);
}

/// The same problem with bounds on one side only (states, control, parameter, final time): the
/// check's test point must stay near the guess, not move to the absent bound's sentinel.
struct OneSidedBounds : AllFeatures {
    ProblemInfo info() const {
        ProblemInfo p = AllFeatures::info();
        p.name = "one-sided-bounds";
        p.states = {{"a", 0.0, kInf, 0}, {"b", -kInf, 5, 0}};
        p.controls = {{"c", -kInf, 2, 0}};
        p.parameters = {{"k", 0.1, kInf, 0}};
        p.final_time = {1.5, kInf};
        return p;
    }
};

TEST(NlpDerivatives, BoundsOnOneSideOnlyGiveNoFalseAlarm) {
    const auto m = make_model(OneSidedBounds{});
    const Guess g =
        Guess::linear(0.1, 2.5, Eigen::Vector2d(0.5, 0.2), Eigen::Vector2d(0.8, 0.3),
                      Eigen::VectorXd::Constant(1, 0.3), Eigen::VectorXd::Constant(1, -0.4),
                      Eigen::VectorXd::Constant(1, 1.1));
    expect_derivatives(*m, Mesh::uniform(1, 9), g, 2e-6);
    expect_derivatives(*m, free_mesh({5, 6, 4}, {0.0, 0.25, 0.6, 1.0}), g, 2e-6);
}

}  // namespace
