// Interior events (conditions at a mesh junction whose time is free): exact derivatives,
// a there-and-back double integrator with a known optimum, and input checks.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "manta/core/error.hpp"
#include "manta/optimal/model.hpp"
#include "manta/optimal/solve.hpp"

namespace {

using namespace manta::optimal;

/// x'' = u, |u| <= 1, from rest at x = 0 through x = `target` (an interior event at junction
/// `junction`) back to rest at x = 0 in least time. Without the interior event the optimum is
/// t_f = 0; with it the cart goes to rest at x = target and back, each leg bang-bang:
/// t_f = 4 sqrt(target), the event at t_f / 2, switches at t_f / 4 and 3 t_f / 4 (Kirk,
/// Optimal Control Theory, 1970, ch. 5, minimum-time double integrator, applied per leg).
struct ThereAndBack {
    double target = 1.0;
    int junction = 2;

    [[nodiscard]] ProblemInfo info() const {
        ProblemInfo p;
        p.name = "there and back";
        p.states = {{"x", -10.0, 10.0, 1.0}, {"v", -10.0, 10.0, 1.0}};
        p.controls = {{"u", -1.0, 1.0, 1.0}};
        p.initial_states = {fixed(0.0), fixed(0.0)};
        p.final_states = {fixed(0.0), fixed(0.0)};
        p.final_time = {0.1, 20.0};
        p.interior_events = {{{"x at the turn", target, target, 1.0}, junction}};
        return p;
    }
    template <class T>
    void dynamics(std::span<const T> x, std::span<const T> u, std::span<const T> /*p*/,
                  const T& /*t*/, std::span<T> xdot) const {
        xdot[0] = x[1];
        xdot[1] = u[0];
    }
    template <class T>
    void interior(int /*junction*/, std::span<const T> x, std::span<const T> /*p*/, const T& /*t*/,
                  std::span<T> e) const {
        e[0] = x[0];
    }
    template <class T>
    T mayer(std::span<const T> /*x0*/, std::span<const T> /*xf*/, std::span<const T> /*p*/,
            const T& /*t0*/, const T& tf) const {
        return tf;
    }
    [[nodiscard]] Guess guess(double tf) const {
        // a triangle in x: out to the target and back
        std::vector<double> t{0.0, 0.5 * tf, tf};
        Eigen::MatrixXd X(3, 2), U(3, 1);
        X << 0.0, 0.0, target, 0.0, 0.0, 0.0;
        U << 0.0, 0.0, 0.0;
        return Guess::from_history(t, X, U);
    }
};

/// The same with an event that depends on the time and the velocity too (derivative check).
struct TimedEvent : ThereAndBack {
    [[nodiscard]] ProblemInfo info() const {
        ProblemInfo p = ThereAndBack::info();
        p.interior_events.push_back({{"x v + t^2", -kInf, 50.0, 1.0}, 1});
        return p;
    }
    template <class T>
    void interior(int junction, std::span<const T> x, std::span<const T> /*p*/, const T& t,
                  std::span<T> e) const {
        using std::sin;
        if (junction == 1) {
            e[0] = x[0] * x[1] + t * t + sin(x[1] * t);
        } else {
            e[0] = x[0] * x[0] * x[1];
        }
    }
};

TEST(InteriorEvents, DerivativesMatchFiniteDifferences) {
    const TimedEvent p;
    const auto m = make_model(p);
    Mesh mesh = Mesh::uniform(4, 5);
    mesh.free_breaks = true;
    const DerivativeCheck d = check_derivatives(*m, mesh, p.guess(3.0));
    EXPECT_LT(d.gradient_error, 1e-7);
    EXPECT_LT(d.jacobian_error, 1e-6) << "row " << d.worst_row << " col " << d.worst_col;
    EXPECT_LT(d.hessian_error, 1e-5);
    // fixed breaks: the event's time is then not a variable
    const DerivativeCheck f = check_derivatives(*m, Mesh::uniform(4, 5), p.guess(3.0));
    EXPECT_LT(f.jacobian_error, 1e-6);
    EXPECT_LT(f.hessian_error, 1e-5);
}

TEST(InteriorEvents, ThereAndBackHitsTheAnalyticOptimum) {
    for (const double target : {1.0, 2.25}) {
        // (free breaks started far from the switches can settle elsewhere, optimal-control.md:
        // the second case starts them at the switches and the turn off by 0.05)
        ThereAndBack p;
        p.target = target;
        const auto m = make_model(p);
        // two segments per leg, all breaks free: they settle on the two control switches and the
        // turn, so every segment's control is smooth (constant)
        Mesh mesh = Mesh::uniform(4, 8);
        mesh.free_breaks = true;
        mesh.breaks = target == 1.0 ? std::vector<double>{0.0, 0.2, 0.5, 0.8, 1.0}
                                    : std::vector<double>{0.0, 0.25, 0.45, 0.75, 1.0};
        const Solution s = solve(*m, mesh, p.guess(5.0));
        ASSERT_TRUE(s.converged()) << s.status_text;
        const double tf = 4.0 * std::sqrt(target);
        EXPECT_NEAR(s.final_time, tf, 1e-6) << target;
        EXPECT_NEAR(s.breaks[2], 0.5 * tf, 1e-5) << "event time";
        EXPECT_NEAR(s.state(s.breaks[2])(0), target, 1e-7);
        EXPECT_NEAR(s.state(s.breaks[2])(1), 0.0, 1e-5) << "at rest at the turn";
        EXPECT_LT(s.max_violation, 1e-7);
    }
}

TEST(InteriorEvents, PhaseBreaksTieTheOtherBreaks) {
    // Mesh::phase_breaks: only the turn (break 2 of 4) is free; breaks 1 and 3 stay halfway
    // through their leg, where the bang-bang switches of this problem lie (t_f / 4, 3 t_f / 4)
    for (const double target : {1.0, 2.25}) {
        ThereAndBack p;
        p.target = target;
        const auto m = make_model(p);
        Mesh mesh = Mesh::uniform(4, 8);
        mesh.free_breaks = true;
        mesh.phase_breaks = {2};
        mesh.breaks = {0.0, 0.3, 0.6, 0.8, 1.0};  // the turn starts off its optimum
        const DerivativeCheck d = check_derivatives(*m, mesh, p.guess(5.0));
        EXPECT_LT(d.jacobian_error, 1e-6) << "row " << d.worst_row << " col " << d.worst_col;
        const Solution s = solve(*m, mesh, p.guess(5.0));
        ASSERT_TRUE(s.converged()) << s.status_text;
        const double tf = 4.0 * std::sqrt(target);
        EXPECT_NEAR(s.final_time, tf, 1e-6) << target;
        EXPECT_NEAR(s.breaks[2], 0.5 * tf, 1e-5) << "event time";
        // the tied breaks keep their fraction (0.5) of each leg
        EXPECT_NEAR(s.breaks[1], 0.5 * s.breaks[2], 1e-9);
        EXPECT_NEAR(s.breaks[3], 0.5 * (s.breaks[2] + s.final_time), 1e-9);
        EXPECT_LT(s.max_violation, 1e-7);
    }
    // an index outside 1..K-1 or out of order is an input error naming it
    ThereAndBack p;
    const auto m = make_model(p);
    for (const std::vector<int>& bad :
         {std::vector<int>{0}, std::vector<int>{4}, std::vector<int>{3, 1}}) {
        Mesh mesh = Mesh::uniform(4, 6);
        mesh.free_breaks = true;
        mesh.phase_breaks = bad;
        try {
            (void)solve(*m, mesh, p.guess(4.0));
            ADD_FAILURE() << "accepted phase break " << bad.front();
        } catch (const manta::InputError& e) {
            EXPECT_NE(std::string(e.what()).find("phase break"), std::string::npos) << e.what();
        }
    }
}

TEST(InteriorEvents, JunctionOutsideTheMeshIsAnInputError) {
    ThereAndBack p;
    p.junction = 3;
    const auto m = make_model(p);
    EXPECT_THROW((void)solve(*m, Mesh::uniform(3, 6), p.guess(4.0)), manta::InputError);
    p.junction = 0;
    EXPECT_THROW((void)make_model(p), manta::InputError);
}

}  // namespace
