// Kriging benchmark (issue 4): maximum-likelihood fit with 5 restarts (Gaussian anisotropic
// correlation, ordinary Kriging) plus 5 000 predictions with MSE, on 3-D data of N = 65, 200 and
// 500 samples of a smooth aerodynamic-like function on the unit cube (a maximin Latin hypercube).
//
//   build/bench/surrogate/bench_kriging --benchmark_repetitions=5
//                                       --benchmark_report_aggregates_only=true
//
// Target: N = 500 in under 1 s CPU on one core. The fit and the predictions are also timed apart.

#include <benchmark/benchmark.h>

#include <cmath>

#include "manta/surrogate/design.hpp"
#include "manta/surrogate/kriging.hpp"

namespace {

namespace ms = manta::surrogate;

/// A lift-coefficient-like function of (alpha, Mach, beta) scaled to the unit cube: alpha in
/// -4..12 deg, Mach 0.1..0.6, beta -8..8 deg; Prandtl-Glauert lift slope, a soft stall, a beta^2
/// loss.
double lift_like(const Eigen::Ref<const Eigen::RowVectorXd>& u) {
    const double alpha = (-4.0 + 16.0 * u[0]) * 3.14159265358979 / 180.0;
    const double mach = 0.1 + 0.5 * u[1];
    const double beta = (-8.0 + 16.0 * u[2]) * 3.14159265358979 / 180.0;
    const double slope =
        2.0 * 3.14159265358979 * 8.0 / (2.0 + std::sqrt(64.0 * (1.0 - mach * mach) + 4.0));
    const double cl = slope * std::sin(alpha) - 1.5 * std::pow(std::max(alpha - 0.12, 0.0), 2);
    return (cl + 0.05) * std::cos(beta) * std::cos(beta) + 0.02 * std::sin(3.0 * beta) * alpha;
}

struct Data {
    ms::Matrix X, T;
    ms::Vector y;
};

Data make(int n) {
    Data d;
    d.X = ms::latin_hypercube(n, 3, 2024);
    d.y.resize(n);
    for (int i = 0; i < n; ++i) d.y[i] = lift_like(d.X.row(i));
    d.T = ms::latin_hypercube(5000, 3, 7, 0);
    return d;
}

ms::KrigingOptions bench_options() {
    ms::KrigingOptions o;
    o.correlation = ms::Correlation::gaussian;
    o.restarts = 5;
    return o;
}

void BM_fit_and_predict(benchmark::State& state) {
    const Data d = make(static_cast<int>(state.range(0)));
    ms::Vector mean, mse;
    double rmse = 0.0;
    for (auto _ : state) {
        const auto model = ms::Kriging::fit(d.X, d.y, bench_options());
        model.predict(d.T, mean, &mse);
        benchmark::DoNotOptimize(mse.data());
        double s = 0.0;
        for (Eigen::Index i = 0; i < d.T.rows(); ++i)
            s += std::pow(mean[i] - lift_like(d.T.row(i)), 2);
        rmse = std::sqrt(s / static_cast<double>(d.T.rows()));
    }
    state.counters["rmse"] = rmse;
}
BENCHMARK(BM_fit_and_predict)->Arg(65)->Arg(200)->Arg(500)->Unit(benchmark::kMillisecond);

void BM_fit(benchmark::State& state) {
    const Data d = make(static_cast<int>(state.range(0)));
    double loglik = 0.0;
    for (auto _ : state) loglik = ms::Kriging::fit(d.X, d.y, bench_options()).log_likelihood();
    state.counters["loglik"] = loglik;
}
BENCHMARK(BM_fit)->Arg(65)->Arg(200)->Arg(500)->Unit(benchmark::kMillisecond);

/// The same fit with every start on all samples (screening off), for the likelihood reached and
/// the time the screening saves.
void BM_fit_without_screening(benchmark::State& state) {
    const Data d = make(static_cast<int>(state.range(0)));
    auto o = bench_options();
    o.screening_points = 0;
    double loglik = 0.0;
    for (auto _ : state) loglik = ms::Kriging::fit(d.X, d.y, o).log_likelihood();
    state.counters["loglik"] = loglik;
}
BENCHMARK(BM_fit_without_screening)->Arg(200)->Arg(500)->Unit(benchmark::kMillisecond);

void BM_predict_5000_with_mse(benchmark::State& state) {
    const Data d = make(static_cast<int>(state.range(0)));
    const auto model = ms::Kriging::fit(d.X, d.y, bench_options());
    ms::Vector mean, mse;
    for (auto _ : state) {
        model.predict(d.T, mean, &mse);
        benchmark::DoNotOptimize(mse.data());
    }
}
BENCHMARK(BM_predict_5000_with_mse)->Arg(65)->Arg(200)->Arg(500)->Unit(benchmark::kMillisecond);

}  // namespace
