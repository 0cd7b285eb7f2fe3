#pragma once
/// @file drift_model.hpp
/// A one-state test model of the multi-phase tests (test_multiphase.cpp,
/// test_multiphase_links.cpp): x' = u on [t0, t0 + 1] with a shared static parameter p, the event
/// x(tf) = share p, min the integral of u^2/2; x(t0) = 0 when `start`.

#include <span>
#include <string>

#include "manta/optimal/problem.hpp"

namespace manta::optimal::test {

struct Drift {
    std::string name;
    double t0 = 0.0;
    double share = 0.25;  // x(tf) = share * p
    bool start = true;    // x(t0) = 0 given
    [[nodiscard]] ProblemInfo info() const {
        ProblemInfo p;
        p.name = name;
        p.states = {{"x", -10.0, 10.0, 1.0}};
        p.controls = {{"u", -10.0, 10.0, 1.0}};
        p.parameters = {{"p", -5.0, 5.0, 1.0}};
        p.initial_time = fixed(t0);
        p.final_time = fixed(t0 + 1.0);
        if (start) p.set_initial("x", 0.0);
        p.events = {{"x(tf) = share p", 0.0, 0.0, 1.0}};
        return p;
    }
    template <class T>
    void dynamics(std::span<const T> /*x*/, std::span<const T> u, std::span<const T> /*p*/,
                  const T& /*t*/, std::span<T> xdot) const {
        xdot[0] = u[0];
    }
    template <class T>
    void events(std::span<const T> /*x0*/, std::span<const T> xf, std::span<const T> p,
                const T& /*t0*/, const T& /*tf*/, std::span<T> e) const {
        e[0] = xf[0] - share * p[0];
    }
    template <class T>
    T lagrange(std::span<const T> /*x*/, std::span<const T> u, std::span<const T> /*p*/,
               const T& /*t*/) const {
        return 0.5 * u[0] * u[0];
    }
};

}  // namespace manta::optimal::test
