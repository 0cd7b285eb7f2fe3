// AeroDatabase::evaluate on a Ranger-sized database: static 17 alpha x 6 Mach x 9 beta, three
// control tables 17 alpha x 6 Mach x 9 deflections, dynamic 17 alpha x 6 Mach (10 columns).
// Random in-table queries, drawn once; the time per call is the figure to read.
//
//   build-aero/bench/aero/bench_aero_database --benchmark_repetitions=5
//       --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "aero_test_util.hpp"
#include "manta/aero/database.hpp"
#include "manta/core/autodiff.hpp"

namespace {

using manta::aero::AeroDatabase;
using manta::aero::AeroQuery;
using manta::aero::Extrapolation;
using manta::aero::Interpolation;
namespace test = manta::aero::test;

constexpr std::size_t n_queries = 4096;  // power of two: cheap wrap-around

std::vector<AeroQuery<double>> random_queries(double out_of_range_fraction = 0.0) {
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<AeroQuery<double>> qs(n_queries);
    for (auto& q : qs) {
        q.alpha = (-8 + 32 * u(rng)) * test::deg;
        if (u(rng) < out_of_range_fraction) q.alpha = 30 * test::deg;
        q.mach = 0.1 + 0.5 * u(rng);
        q.beta = (-8 + 16 * u(rng)) * test::deg;
        q.elevator = (-20 + 40 * u(rng)) * test::deg;
        q.aileron = (-20 + 40 * u(rng)) * test::deg;
        q.rudder = (-20 + 40 * u(rng)) * test::deg;
        q.p_hat = 0.1 * (u(rng) - 0.5);
        q.q_hat = 0.1 * (u(rng) - 0.5);
        q.r_hat = 0.1 * (u(rng) - 0.5);
        q.alpha_dot_hat = 0.1 * (u(rng) - 0.5);
        q.beta_dot_hat = 0.1 * (u(rng) - 0.5);
    }
    return qs;
}

void run(benchmark::State& state, const AeroDatabase& db, Interpolation method,
         double out_fraction = 0.0) {
    const auto qs = random_queries(out_fraction);
    std::size_t i = 0;
    for (auto _ : state) {
        const auto c = db.evaluate(qs[i++ & (n_queries - 1)], method);
        benchmark::DoNotOptimize(c);
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_multilinear(benchmark::State& state) {
    const AeroDatabase db = test::ranger_like();
    run(state, db, Interpolation::multilinear);
}
BENCHMARK(BM_multilinear);

void BM_multilinear_nonuniform_alpha(benchmark::State& state) {
    const AeroDatabase db = test::ranger_like(Extrapolation::clamp, /*uniform_alpha=*/false);
    run(state, db, Interpolation::multilinear);
}
BENCHMARK(BM_multilinear_nonuniform_alpha);

void BM_multilinear_10pct_out_of_range(benchmark::State& state) {
    const AeroDatabase db = test::ranger_like();
    run(state, db, Interpolation::multilinear, 0.1);
}
BENCHMARK(BM_multilinear_10pct_out_of_range);

// The single pass of the equations of motion: coefficients and their alpha-dot/beta-dot partial
// derivatives together (AeroDatabase::evaluate_with_angle_rates).
void BM_multilinear_with_angle_rates(benchmark::State& state) {
    const AeroDatabase db = test::ranger_like();
    const auto qs = random_queries();
    std::size_t i = 0;
    for (auto _ : state) {
        const auto e =
            db.evaluate_with_angle_rates(qs[i++ & (n_queries - 1)], Interpolation::multilinear);
        benchmark::DoNotOptimize(e);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_multilinear_with_angle_rates);

void BM_c1(benchmark::State& state) {
    const AeroDatabase db = test::ranger_like();
    run(state, db, Interpolation::c1);
}
BENCHMARK(BM_c1);

// The same few queries over and over: table rows stay in L1, as along a simulated trajectory.
void BM_multilinear_hot_cache(benchmark::State& state) {
    const AeroDatabase db = test::ranger_like();
    const auto qs = random_queries();
    std::size_t i = 0;
    for (auto _ : state) {
        const auto c = db.evaluate(qs[i++ & 7], Interpolation::multilinear);
        benchmark::DoNotOptimize(c);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_multilinear_hot_cache);

// First-order AD with all eleven inputs seeded (core::Dual, dynamic derivative vector).
void dual_run(benchmark::State& state, Interpolation method) {
    const AeroDatabase db = test::ranger_like();
    auto qs = random_queries();
    std::vector<AeroQuery<manta::core::Dual>> qd(n_queries);
    for (std::size_t k = 0; k < n_queries; ++k) {
        auto in = test::fields(qs[k]);
        auto out = test::fields(qd[k]);
        for (std::size_t j = 0; j < in.size(); ++j)
            *out[j] = manta::core::make_dual(*in[j], 11, static_cast<Eigen::Index>(j));
    }
    std::size_t i = 0;
    for (auto _ : state) {
        const auto c = db.evaluate(qd[i++ & (n_queries - 1)], method);
        benchmark::DoNotOptimize(c);
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_dual_multilinear(benchmark::State& state) {
    dual_run(state, Interpolation::multilinear);
}
BENCHMARK(BM_dual_multilinear);

void BM_dual_c1(benchmark::State& state) {
    dual_run(state, Interpolation::c1);
}
BENCHMARK(BM_dual_c1);

}  // namespace
