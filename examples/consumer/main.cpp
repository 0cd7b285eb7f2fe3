/// @file main.cpp
/// A program built against an installed MANTA (docs/tutorial-optimal.md): two textbook
/// optimal-control problems written against the `optimal` headers, solved, and checked against
/// their published optima; the exit status is 1 when either is off.
///
/// 1. Brachistochrone: a bead slides without friction from rest at the origin to
///    (x_f, y_f) = (10 m, 5 m), y downwards, g = 9.80665 m/s^2, in least time. The optimum is
///    the cycloid x = R (phi - sin phi), y = R (1 - cos phi) (Johann Bernoulli, Acta
///    Eruditorum, 1697), descended in t_f = phi_f sqrt(R / g) with
///    (phi_f - sin phi_f) / (1 - cos phi_f) = x_f / y_f: phi_f = 3.5083 rad, R = 2.5843 m,
///    t_f = 1.8016031 s. Solved on one segment of 30 Legendre-Gauss-Lobatto points.
/// 2. Minimum-time double integrator x'' = u, |u| <= 1, from (x, v) = (1, 1) to rest at the
///    origin: bang-bang, u = -1 until t_s = v0 + sqrt(v0^2/2 + x0) = 2.2247449 s, then +1 until
///    t_f = v0 + 2 sqrt(v0^2/2 + x0) = 3.4494897 s (Kirk, Optimal Control Theory, 1970, ch. 5,
///    minimum-time problems). Solved by error-driven mesh refinement from one segment of 6
///    points: the refinement finds the switch.

#include <cmath>
#include <cstdio>
#include <numbers>
#include <span>

#include "manta/optimal/model.hpp"
#include "manta/optimal/problem.hpp"
#include "manta/optimal/refine.hpp"
#include "manta/optimal/solve.hpp"

namespace opt = manta::optimal;

/// States x, y [m] (y down), v [m/s]; control theta [rad], the path angle from the downward
/// vertical. Every function is a template: MANTA evaluates it on double and on its AD scalars.
struct Brachistochrone {
    double g = 9.80665;  // [m/s^2]
    double xf = 10.0;    // [m]
    double yf = 5.0;     // [m]

    [[nodiscard]] opt::ProblemInfo info() const {
        opt::ProblemInfo p;
        p.name = "brachistochrone";
        p.states = {{"x", -20.0, 20.0}, {"y", -20.0, 20.0}, {"v", 0.0, 50.0}};
        p.controls = {{"theta", -0.5 * std::numbers::pi, std::numbers::pi}};
        p.initial_time = opt::fixed(0.0);
        p.final_time = {1e-3, 100.0};
        p.initial_states = {opt::fixed(0.0), opt::fixed(0.0), opt::fixed(0.0)};
        p.final_states = {opt::fixed(xf), opt::fixed(yf), {0.0, opt::kInf}};
        return p;
    }
    template <class T>
    void dynamics(std::span<const T> x, std::span<const T> u, std::span<const T> /*p*/,
                  const T& /*t*/, std::span<T> xdot) const {
        using std::cos;
        using std::sin;
        xdot[0] = x[2] * sin(u[0]);
        xdot[1] = x[2] * cos(u[0]);
        xdot[2] = g * cos(u[0]);
    }
    template <class T>
    T mayer(std::span<const T> /*x0*/, std::span<const T> /*xf*/, std::span<const T> /*p*/,
            const T& /*t0*/, const T& tf) const {
        return tf;  // least time
    }
};

/// States x, v; control u in [-1, 1]; from (1, 1) to (0, 0) in least time.
struct DoubleIntegrator {
    [[nodiscard]] opt::ProblemInfo info() const {
        opt::ProblemInfo p;
        p.name = "double-integrator";
        p.states = {{"x", -10.0, 10.0}, {"v", -10.0, 10.0}};
        p.controls = {{"u", -1.0, 1.0}};
        p.initial_time = opt::fixed(0.0);
        p.final_time = {0.1, 20.0};
        p.initial_states = {opt::fixed(1.0), opt::fixed(1.0)};
        p.final_states = {opt::fixed(0.0), opt::fixed(0.0)};
        return p;
    }
    template <class T>
    void dynamics(std::span<const T> x, std::span<const T> u, std::span<const T> /*p*/,
                  const T& /*t*/, std::span<T> xdot) const {
        xdot[0] = x[1];
        xdot[1] = u[0];
    }
    template <class T>
    T mayer(std::span<const T> /*x0*/, std::span<const T> /*xf*/, std::span<const T> /*p*/,
            const T& /*t0*/, const T& tf) const {
        return tf;
    }
};

/// The cycloid's descent time through (xf, yf): phi_f by bisection (the ratio rises
/// monotonically on (0, 2 pi)), then R and t_f.
double cycloid_time(double xf, double yf, double g) {
    double lo = 1e-12, hi = 2.0 * std::numbers::pi - 1e-12;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        ((mid - std::sin(mid)) / (1.0 - std::cos(mid)) < xf / yf ? lo : hi) = mid;
    }
    const double phi = 0.5 * (lo + hi);
    const double radius = yf / (1.0 - std::cos(phi));
    return phi * std::sqrt(radius / g);
}

int main() {
    int failures = 0;

    // 1. brachistochrone: one solve on a fixed mesh, from a straight-line guess
    const Brachistochrone b;
    const auto bmodel = opt::make_model(b);
    const double v_end = std::sqrt(2.0 * b.g * b.yf);
    const opt::Guess bguess = opt::Guess::linear(
        0.0, 2.0, Eigen::Vector3d(0.0, 0.0, 0.0), Eigen::Vector3d(b.xf, b.yf, v_end),
        Eigen::VectorXd::Constant(1, 0.0), Eigen::VectorXd::Constant(1, 0.5 * std::numbers::pi));
    const opt::Solution bs = opt::solve(*bmodel, opt::Mesh::uniform(1, 30), bguess);
    const double t_cycloid = cycloid_time(b.xf, b.yf, b.g);
    std::printf("brachistochrone: %s, %d IPOPT iterations\n", opt::to_string(bs.status).c_str(),
                bs.iterations);
    std::printf("  t_f %.9f s, cycloid %.9f s (published 1.8016031 s), error %.2e s\n",
                bs.final_time, t_cycloid, bs.final_time - t_cycloid);
    if (!bs.resolved() || std::abs(bs.final_time - t_cycloid) > 1e-6 ||
        std::abs(t_cycloid - 1.8016031) > 1e-7) {
        std::printf("  FAILED: expected a resolved solution within 1e-6 s of the cycloid\n");
        ++failures;
    }

    // 2. double integrator: error-driven refinement from a mesh that cannot resolve the switch
    const DoubleIntegrator d;
    const auto dmodel = opt::make_model(d);
    const opt::Guess dguess =
        opt::Guess::linear(0.0, 3.0, Eigen::Vector2d(1.0, 1.0), Eigen::Vector2d(0.0, 0.0),
                           Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1));
    const opt::AdaptiveSolution ds = opt::solve_adaptive(*dmodel, opt::Mesh::uniform(1, 6), dguess);
    const double t_bang_bang = 1.0 + 2.0 * std::sqrt(1.5);
    std::printf("double integrator: %s\n%s", opt::to_string(ds.status).c_str(),
                opt::refinement_report(ds).c_str());
    std::printf("  t_f %.9f s, bang-bang %.9f s (published 3.4494897 s), error %.2e s\n",
                ds.solution.final_time, t_bang_bang, ds.solution.final_time - t_bang_bang);
    if (!ds.solution.converged() || std::abs(ds.solution.final_time - t_bang_bang) > 1e-6) {
        std::printf("  FAILED: expected a converged solution within 1e-6 s of the bang-bang\n");
        ++failures;
    }
    return failures == 0 ? 0 : 1;
}
