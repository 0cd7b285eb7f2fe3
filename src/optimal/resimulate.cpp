/// @file resimulate.cpp
/// A-posteriori check of a solution: its controls integrated by an adaptive Dormand–Prince 5(4)
/// method (Boost.Odeint, dense output) from x(t0), compared with the collocated states.

#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <exception>
#include <vector>

#include "manta/optimal/lgl.hpp"
#include "manta/optimal/solve.hpp"

namespace manta::optimal {

Resimulation resimulate(const Model& model, const Solution& sol, double tolerance) {
    namespace ode = boost::numeric::odeint;
    using State = std::vector<double>;
    Resimulation res;
    const ProblemInfo& info = model.info();
    const int nx = info.n_states();
    const int nu = info.n_controls();
    res.max_abs_error = Eigen::VectorXd::Zero(nx);
    if (sol.segments.empty()) {
        res.message = "no solution to re-simulate";
        return res;
    }
    // state scales for the scaled error: the user's scale, else the largest |x| on the solution
    Eigen::VectorXd scale(nx);
    for (int r = 0; r < nx; ++r) {
        double m = info.states[r].scale;
        if (!(m > 0.0)) {
            for (const auto& s : sol.segments)
                m = std::max(m, s.states.col(r).cwiseAbs().maxCoeff());
        }
        scale(r) = m > 0.0 ? m : 1.0;
    }
    const std::vector<double> p(sol.parameters.data(),
                                sol.parameters.data() + sol.parameters.size());
    State x(static_cast<std::size_t>(nx));
    for (int r = 0; r < nx; ++r) x[r] = sol.segments.front().states(0, r);
    try {
        for (std::size_t k = 0; k < sol.segments.size(); ++k) {
            const SegmentSolution& seg = sol.segments[k];
            const double a = sol.breaks[k];
            const double b = sol.breaks[k + 1];
            if (!(b > a)) continue;
            std::vector<double> u(static_cast<std::size_t>(nu));
            auto rhs = [&](const State& xs, State& dxdt, double t) {
                const double tau = std::clamp(2.0 * (t - a) / (b - a) - 1.0, -1.0, 1.0);
                const Eigen::RowVectorXd ell = lagrange_basis(seg.tau, seg.bary, tau);
                for (int j = 0; j < nu; ++j) {
                    // the interpolating polynomial may overshoot between nodes: clamp to bounds
                    u[j] = std::clamp(ell.dot(seg.controls.col(j)), info.controls[j].lower,
                                      info.controls[j].upper);
                }
                dxdt.resize(xs.size());
                model.dynamics(xs, u, p, t, dxdt);
            };
            std::vector<double> times(seg.time.data(), seg.time.data() + seg.time.size());
            times.front() = a;
            times.back() = b;
            int node = 0;
            auto observe = [&](const State& xs, double /*t*/) {
                for (int r = 0; r < nx; ++r) {
                    const double e = std::abs(xs[r] - seg.states(node, r));
                    res.max_abs_error(r) = std::max(res.max_abs_error(r), e);
                    res.max_scaled_error = std::max(res.max_scaled_error, e / scale(r));
                }
                ++node;
            };
            auto stepper =
                ode::make_dense_output(tolerance, tolerance, ode::runge_kutta_dopri5<State>());
            ode::integrate_times(stepper, rhs, x, times.begin(), times.end(),
                                 (b - a) / (10.0 * static_cast<double>(times.size())), observe);
        }
        res.final_state = Eigen::Map<const Eigen::VectorXd>(x.data(), nx);
        res.done = std::all_of(x.begin(), x.end(), [](double v) { return std::isfinite(v); });
        if (!res.done) res.message = "non-finite state during re-simulation";
    } catch (const std::exception& e) {
        res.done = false;
        res.message = std::string("re-simulation failed: ") + e.what();
    }
    return res;
}

}  // namespace manta::optimal
