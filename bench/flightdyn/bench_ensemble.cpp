// Ensembles: 64 cases of the Ranger 2000 (examples/ranger2000/aircraft.yaml), each trimmed in
// level flight on an 8 x 8 grid of speed (110..215 m/s) and altitude (1..8 km) and flown for 10 s
// of RK4 at 100 Hz (dt 0.01 s, rows every 0.1 s) through an elevator doublet and an aileron pulse:
// simulate_ensemble (lock-step, one batched right-hand side per RK4 stage) against the same cases
// one after another with simulate.
//
//   build/bench/flightdyn/bench_flightdyn_ensemble --benchmark_repetitions=5
//       --benchmark_report_aggregates_only=true
//
// Figure to read: case_s_per_wall_s (simulated case-seconds per wall second) of
// BM_ensemble_rk4 against BM_one_by_one_rk4; the argument is the state form (0 quaternion,
// 1 Euler angles).

#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "manta/aircraft/aircraft.hpp"
#include "manta/core/memory.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/simulate.hpp"
#include "manta/flightdyn/trim.hpp"

namespace {

namespace fd = manta::flightdyn;
using manta::core::deg;

constexpr int n_side = 8;          // speeds x altitudes
constexpr double duration = 10.0;  // [s] per case

/// The Ranger of examples/ranger2000/aircraft.yaml (alpha-dot terms on: finalize).
const fd::FlightModel& ranger() {
    static const fd::FlightModel model = [] {
        fd::FlightModel m = manta::aircraft::load_aircraft(std::string(MANTA_SOURCE_DIR) +
                                                           "/examples/ranger2000/aircraft.yaml")
                                .flight_model();
        fd::finalize(m);
        return m;
    }();
    return model;
}

/// The 64 cases, trimmed once.
const std::vector<fd::EnsembleCase>& cases() {
    static const std::vector<fd::EnsembleCase> all = [] {
        std::vector<fd::EnsembleCase> out;
        for (int i = 0; i < n_side; ++i) {
            for (int k = 0; k < n_side; ++k) {
                fd::TrimTarget target;
                target.airspeed = 110.0 + 15.0 * i;
                target.altitude = 1000.0 + 1000.0 * k;
                const fd::TrimResult trim = fd::trim(ranger(), target);
                const double de = trim.controls.elevator / deg(1.0);
                // Doublet of +-2 deg about trim at 1-3 s, then a 5 deg aileron pulse at 5-6 s.
                std::string csv = "t,elevator_deg,aileron_deg\n";
                const auto row = [&csv](double t, double e, double a) {
                    csv.append(std::to_string(t)).append(",").append(std::to_string(e));
                    csv.append(",").append(std::to_string(a)).append("\n");
                };
                row(0.0, de, 0);
                row(1.0, de, 0);
                row(1.1, de - 2, 0);
                row(2.0, de - 2, 0);
                row(2.1, de + 2, 0);
                row(3.0, de + 2, 0);
                row(3.1, de, 0);
                row(5.0, de, 0);
                row(5.1, de, 5);
                row(6.0, de, 5);
                row(6.1, de, 0);
                std::string name = "V";
                name.append(std::to_string(i)).append("_h").append(std::to_string(k));
                out.push_back(
                    {name, trim.state, fd::InputHistory::parse(csv, "doublet.csv", trim.controls)});
            }
        }
        return out;
    }();
    return all;
}

fd::SimulationOptions options(const benchmark::State& state) {
    fd::SimulationOptions opt;
    opt.duration = duration;
    opt.dt = 0.01;
    opt.output_interval = 0.1;
    opt.form = state.range(0) == 0 ? fd::StateForm::quaternion : fd::StateForm::euler;
    return opt;
}

void BM_ensemble_rk4(benchmark::State& state) {
    const auto& cs = cases();
    const fd::SimulationOptions opt = options(state);
    double simulated = 0.0;
    for (auto _ : state) {
        const auto results = fd::simulate_ensemble(ranger(), cs, opt);
        for (const auto& r : results) simulated += r.final_time;
        benchmark::DoNotOptimize(results.data());
    }
    state.counters["case_s_per_wall_s"] =
        benchmark::Counter(simulated, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ensemble_rk4)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_one_by_one_rk4(benchmark::State& state) {
    const auto& cs = cases();
    const fd::SimulationOptions opt = options(state);
    double simulated = 0.0;
    for (auto _ : state) {
        for (const auto& c : cs) {
            const auto r = fd::simulate(ranger(), c.initial, c.inputs, opt);
            simulated += r.final_time;
            benchmark::DoNotOptimize(r.rows.data());
        }
    }
    state.counters["case_s_per_wall_s"] =
        benchmark::Counter(simulated, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_one_by_one_rk4)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

// As `manta` does (src/cli/main.cpp): freed memory stays in the heap, so the results' rows, all
// alive at once in an ensemble, do not pay fresh page faults on every iteration.
int main(int argc, char** argv) {
    manta::core::keep_large_allocations();
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
