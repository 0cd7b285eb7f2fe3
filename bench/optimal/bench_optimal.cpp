// Optimal-control benchmarks: Bryson's minimum time to climb (PSOPT's data, US 1976 atmosphere)
// solved from PSOPT's linear guess at 40 and 80 LGL points in one segment, exact Hessian; and the
// per-node AD kernels the NLP callbacks are made of.
//
//   build/bench/optimal/bench_optimal --benchmark_repetitions=5
//   (add --benchmark_report_aggregates_only=true for the medians only)
//
// Counters: ipopt_iterations, solver_cpu_s (process CPU time of the solve as measured by the
// library). The project's target is under 0.5 s CPU at 40 nodes (issue 5; PSOPT with CppAD
// and an exact Hessian needs about 2.8 s CPU and 19 iterations on the same machine).

#include <benchmark/benchmark.h>

#include "manta/optimal/problems.hpp"

namespace {

using namespace manta::optimal;

void BM_min_time_to_climb(benchmark::State& state) {
    const MinTimeToClimb p;
    const auto model = make_model(p);
    const Mesh mesh = Mesh::uniform(1, static_cast<int>(state.range(0)));
    SolverOptions o;
    o.resimulate = false;
    Solution s;
    for (auto _ : state) {
        s = solve(*model, mesh, p.guess(), o);
        benchmark::DoNotOptimize(s.final_time);
    }
    if (!s.converged()) state.SkipWithError(s.status_text.c_str());
    state.counters["ipopt_iterations"] = s.iterations;
    state.counters["solver_cpu_s"] = s.cpu_time;
}
BENCHMARK(BM_min_time_to_climb)->Arg(40)->Arg(80)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_min_time_to_climb_limited_memory(benchmark::State& state) {
    const MinTimeToClimb p;
    const auto model = make_model(p);
    const Mesh mesh = Mesh::uniform(1, static_cast<int>(state.range(0)));
    SolverOptions o;
    o.resimulate = false;
    o.hessian = HessianMode::limited_memory;
    Solution s;
    for (auto _ : state) {
        s = solve(*model, mesh, p.guess(), o);
        benchmark::DoNotOptimize(s.final_time);
    }
    state.counters["ipopt_iterations"] = s.iterations;
    state.counters["solver_cpu_s"] = s.cpu_time;
}
BENCHMARK(BM_min_time_to_climb_limited_memory)
    ->Arg(40)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

/// One collocation node of the climb: outputs and their 4x7 Jacobian by first-order AD.
void BM_climb_node_jacobian(benchmark::State& state) {
    const auto model = make_model(MinTimeToClimb{});
    const std::vector<double> v{30000.0, 900.0, 0.1, 40000.0, 0.05, 0.0, 320.0};
    NodePlacement at;
    at.a = 0.4;
    at.weight = 0.05;
    std::vector<double> out(4), jac(4 * 7);
    for (auto _ : state) {
        model->node_jacobian(v, at, out, jac);
        benchmark::DoNotOptimize(jac.data());
    }
}
BENCHMARK(BM_climb_node_jacobian);

/// One collocation node of the climb: 7x7 Hessian of the weighted outputs (forward over forward).
void BM_climb_node_hessian(benchmark::State& state) {
    const auto model = make_model(MinTimeToClimb{});
    const std::vector<double> v{30000.0, 900.0, 0.1, 40000.0, 0.05, 0.0, 320.0};
    NodePlacement at;
    at.a = 0.4;
    at.weight = 0.05;
    const std::vector<double> w{1e-3, -2e-2, 0.5, 1e-4};
    std::vector<double> hess(7 * 7);
    for (auto _ : state) {
        model->node_hessian(v, at, w, hess);
        benchmark::DoNotOptimize(hess.data());
    }
}
BENCHMARK(BM_climb_node_hessian);

}  // namespace
