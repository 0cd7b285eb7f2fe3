/// @file problems.cpp
/// Data, bounds and guesses of the validation problems (problems.hpp).

#include "manta/optimal/problems.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "manta/core/error.hpp"

namespace manta::optimal {

namespace {
constexpr double deg = std::numbers::pi / 180.0;
}  // namespace

// ---- brachistochrone ------------------------------------------------------------------------

ProblemInfo Brachistochrone::info() const {
    ProblemInfo p;
    p.name = "brachistochrone";
    const double reach = 2.0 * std::max(x_final, y_final);
    p.states = {{"x", -reach, reach, 0.0},
                {"y", -reach, reach, 0.0},
                {"v", 0.0, 10.0 * std::sqrt(gravity * reach), 0.0}};
    p.controls = {{"theta", -0.5 * std::numbers::pi, std::numbers::pi, 0.0}};
    p.initial_time = fixed(0.0);
    p.final_time = {1e-3, 100.0};
    p.time_scale = std::sqrt(2.0 * y_final / gravity) + 1e-3;
    p.initial_states = {fixed(0.0), fixed(0.0), fixed(0.0)};
    p.final_states = {fixed(x_final), fixed(y_final), {0.0, kInf}};
    return p;
}

Guess Brachistochrone::guess() const {
    const double v_end = std::sqrt(2.0 * gravity * y_final);
    const double tf = 2.0 * std::hypot(x_final, y_final) / std::max(v_end, 1e-6);
    return Guess::linear(
        0.0, tf, Eigen::Vector3d(0.0, 0.0, 0.0), Eigen::Vector3d(x_final, y_final, v_end),
        Eigen::VectorXd::Constant(1, 0.0), Eigen::VectorXd::Constant(1, 0.5 * std::numbers::pi));
}

CycloidSolution brachistochrone_cycloid(double x_final, double y_final, double gravity) {
    if (!(x_final > 0.0) || !(y_final > 0.0) || !(gravity > 0.0)) {
        throw InputError(
            fmt::format("brachistochrone end point ({}, {}) with g = {}: expected "
                        "x_f > 0, y_f > 0 (below the start), g > 0",
                        x_final, y_final, gravity));
    }
    // r(phi) = (phi - sin phi) / (1 - cos phi) rises monotonically from 0 to infinity on (0, 2 pi)
    const double target = x_final / y_final;
    double lo = 1e-12;
    double hi = 2.0 * std::numbers::pi - 1e-12;
    for (int it = 0; it < 200 && hi - lo > 1e-16; ++it) {
        const double mid = 0.5 * (lo + hi);
        const double r = (mid - std::sin(mid)) / (1.0 - std::cos(mid));
        (r < target ? lo : hi) = mid;
    }
    CycloidSolution c;
    c.phi_final = 0.5 * (lo + hi);
    c.radius = y_final / (1.0 - std::cos(c.phi_final));
    c.final_time = c.phi_final * std::sqrt(c.radius / gravity);
    return c;
}

// ---- double integrator ----------------------------------------------------------------------

ProblemInfo DoubleIntegrator::info() const {
    ProblemInfo p;
    p.name = "double-integrator";
    p.states = {{"x", -10.0, 10.0, 0.0}, {"v", -10.0, 10.0, 0.0}};
    p.controls = {{"u", -1.0, 1.0, 0.0}};
    if (max_speed > 0.0) p.path = {{"speed_limit", -max_speed, max_speed, 0.0}};
    p.initial_time = fixed(0.0);
    p.final_time = {0.1, max_final_time};
    p.initial_states = {fixed(x0), fixed(v0)};
    p.final_states = {fixed(0.0), fixed(0.0)};
    return p;
}

Guess DoubleIntegrator::guess() const {
    return Guess::linear(0.0, std::min(3.0, max_final_time), Eigen::Vector2d(x0, v0),
                         Eigen::Vector2d(0.0, 0.0), Eigen::VectorXd::Zero(1),
                         Eigen::VectorXd::Zero(1));
}

BangBangSolution double_integrator_bang_bang(double x0, double v0) {
    if (!(x0 > -v0 * std::abs(v0) / 2.0)) {
        throw InputError(
            fmt::format("double integrator from ({}, {}): expected a start above the "
                        "switching curve x = -v|v|/2",
                        x0, v0));
    }
    const double root = std::sqrt(0.5 * v0 * v0 + x0);
    return {v0 + root, v0 + 2.0 * root};
}

// ---- splines ----------------------------------------------------------------------------------

NaturalSpline::NaturalSpline(std::vector<double> x, std::vector<double> y)
    : x_(std::move(x)), y_(std::move(y)) {
    if (x_.size() < 2 || x_.size() != y_.size()) {
        throw InputError(
            fmt::format("natural spline: {} knots and {} values, expected >= 2 each "
                        "and as many values as knots",
                        x_.size(), y_.size()));
    }
    for (std::size_t i = 1; i < x_.size(); ++i) {
        if (!(x_[i] > x_[i - 1])) {
            throw InputError(
                fmt::format("natural spline: knot {} = {} not above {}", i, x_[i], x_[i - 1]));
        }
    }
    m_ = second_derivatives(x_, y_);
}

std::vector<double> NaturalSpline::second_derivatives(const std::vector<double>& x,
                                                      const std::vector<double>& y) {
    // tridiagonal system h_{i-1} m_{i-1} + 2 (h_{i-1} + h_i) m_i + h_i m_{i+1} = 6 (slope diff),
    // m_0 = m_{n-1} = 0, by the Thomas algorithm
    const std::size_t n = x.size();
    std::vector<double> m(n, 0.0);
    if (n < 3) return m;
    std::vector<double> c(n, 0.0), d(n, 0.0);
    for (std::size_t i = 1; i + 1 < n; ++i) {
        const double h0 = x[i] - x[i - 1];
        const double h1 = x[i + 1] - x[i];
        const double rhs = 6.0 * ((y[i + 1] - y[i]) / h1 - (y[i] - y[i - 1]) / h0);
        const double diag = 2.0 * (h0 + h1) - h0 * c[i - 1];
        c[i] = h1 / diag;
        d[i] = (rhs - h0 * d[i - 1]) / diag;
    }
    for (std::size_t i = n - 2; i >= 1; --i) {
        m[i] = d[i] - c[i] * m[i + 1];
        if (i == 1) break;
    }
    return m;
}

int NaturalSpline::interval(double v) const {
    const auto it = std::upper_bound(x_.begin(), x_.end(), v);
    int k = static_cast<int>(it - x_.begin()) - 1;
    return std::clamp(k, 0, static_cast<int>(x_.size()) - 2);
}

RowColumnSpline::RowColumnSpline(std::vector<double> x, std::vector<double> y,
                                 const std::vector<std::vector<double>>& z) {
    if (z.size() != x.size()) {
        throw InputError(
            fmt::format("2-D spline: {} rows for {} first-coordinate knots", z.size(), x.size()));
    }
    for (const auto& row : z) rows_.emplace_back(y, row);
    column_ = NaturalSpline(x, std::vector<double>(x.size(), 0.0));
    const std::size_t n = x.size();
    map_.assign(n, std::vector<double>(n, 0.0));
    for (std::size_t j = 0; j < n; ++j) {
        std::vector<double> e(n, 0.0);
        e[j] = 1.0;
        const auto m = NaturalSpline::second_derivatives(x, e);
        for (std::size_t i = 0; i < n; ++i) map_[i][j] = m[i];
    }
}

// ---- minimum time to climb ---------------------------------------------------------------------

MinTimeToClimb::MinTimeToClimb() {
    // PSOPT climb example = Bryson, Desai & Hoffman (1969) tables
    const std::vector<double> m1{0.0, 0.4, 0.8, 0.9, 1.0, 1.2, 1.4, 1.6, 1.8};
    cl_alpha_ = NaturalSpline(m1, {3.44, 3.44, 3.44, 3.58, 4.44, 3.44, 3.01, 2.86, 2.44});
    cd0_ = NaturalSpline(m1, {0.013, 0.013, 0.013, 0.014, 0.031, 0.041, 0.039, 0.036, 0.035});
    eta_ = NaturalSpline(m1, {0.54, 0.54, 0.54, 0.75, 0.79, 0.78, 0.89, 0.93, 0.93});
    const std::vector<double> m2{0.0, 0.2, 0.4, 0.6, 0.8, 1.0, 1.2, 1.4, 1.6, 1.8};
    const std::vector<double> h1{0.0, 5e3, 10e3, 15e3, 20e3, 25e3, 30e3, 40e3, 50e3, 70e3};
    const std::vector<std::vector<double>> t{
        {24200., 24000., 20300., 17300., 14500., 12200., 10200., 5700., 3400., 100.},
        {28000., 24600., 21100., 18100., 15200., 12800., 10700., 6500., 3900., 200.},
        {28300., 25200., 21900., 18700., 15900., 13400., 11200., 7300., 4400., 400.},
        {30800., 27200., 23800., 20500., 17300., 14700., 12300., 8100., 4900., 800.},
        {34500., 30300., 26600., 23200., 19800., 16800., 14100., 9400., 5600., 1100.},
        {37900., 34300., 30400., 26800., 23300., 19800., 16800., 11200., 6800., 1400.},
        {36100., 38000., 34900., 31300., 27300., 23600., 20100., 13400., 8300., 1700.},
        {34300., 36600., 38500., 36100., 31600., 28100., 24200., 16200., 10000., 2200.},
        {32500., 35200., 42100., 38700., 35700., 32000., 28100., 19300., 11900., 2900.},
        {30700., 33800., 45700., 41300., 39800., 34600., 31100., 21700., 13300., 3100.}};
    thrust_ = RowColumnSpline(m2, h1, t);
}

ProblemInfo MinTimeToClimb::info() const {
    ProblemInfo p;
    p.name = "min-time-to-climb";
    p.states = {{"h_ft", 0.0, 69000.0, 0.0},
                {"v_ft_s", 1.0, 2000.0, 0.0},
                {"gamma", -89.0 * deg, 89.0 * deg, 0.0},
                {"w_lb", 0.0, 45000.0, 0.0}};
    p.controls = {{"alpha", -20.0 * deg, 20.0 * deg, 0.0}};
    p.initial_time = fixed(0.0);
    p.final_time = {200.0, 500.0};
    p.initial_states = {fixed(0.0), fixed(424.26), fixed(0.0), fixed(42000.0)};
    p.final_states = {fixed(65600.0), fixed(968.148), fixed(0.0), {0.0, 45000.0}};
    return p;
}

Guess MinTimeToClimb::guess() const {
    return Guess::linear(0.0, 300.0, Eigen::Vector4d(0.0, 424.26, 0.0, 42000.0),
                         Eigen::Vector4d(65600.0, 968.148, 0.0, 0.8 * 42000.0),
                         Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1));
}

}  // namespace manta::optimal
