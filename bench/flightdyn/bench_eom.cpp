// Equations of motion: right-hand-side evaluations per second and simulated seconds per wall
// second, for the Ranger 2000 (examples/ranger2000/aircraft.yaml; a Ranger-like model built in
// code from the same derivatives if the file is absent). Table look-ups are in the loop and the
// states vary (4096 states drawn once, cycled), so no cache or branch predictor sees one state.
//
//   build/bench/flightdyn/bench_flightdyn_eom --benchmark_repetitions=5
//       --benchmark_report_aggregates_only=true
//
// Figures to read: items_per_second of BM_euler_rhs (derivative evaluations per second, one
// state per call), of BM_euler_rhs_batch and BM_quaternion_rhs_batch (the same, batched: four
// states per AVX2 pass; the project target is >= 1e7 on one core) and sim_s_per_wall_s of
// BM_simulate_rk4_100Hz.
// BM_euler_rhs takes the fused kernels of the processor (AVX2 where it has it;
// MANTA_FLIGHTDYN_KERNELS=baseline or =reference chooses the baseline set or the templates);
// the *_kernels and *_templates variants fix the path.

#include <benchmark/benchmark.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "../../tests/flightdyn/test_sim_models.hpp"
#include "manta/aircraft/aircraft.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/eom.hpp"
#include "manta/flightdyn/simulate.hpp"

namespace {

namespace fd = manta::flightdyn;
using manta::core::deg;

constexpr std::size_t n_states = 4096;  // power of two: cheap wrap-around

/// The Ranger from its aircraft file, or the same derivatives built in code.
const fd::FlightModel& ranger() {
    static const fd::FlightModel model = [] {
        const std::filesystem::path file =
            std::filesystem::path(MANTA_SOURCE_DIR) / "examples" / "ranger2000" / "aircraft.yaml";
        if (std::filesystem::exists(file)) {
            fd::FlightModel m = manta::aircraft::load_aircraft(file).flight_model();
            fd::finalize(m);  // sets angle_rate_terms: the Ranger has alpha-dot derivatives
            return m;
        }
        return manta::test::ranger_like();
    }();
    return model;
}

struct Sample {
    fd::EulerState<double> state;
    fd::Controls<double> controls;
};

/// Flight states spread over the tables: V 80..220 m/s, altitude 500..8000 m, alpha -4..16 deg,
/// beta -8..8 deg, rates up to 0.5 rad/s, deflections over most of their travel.
std::vector<Sample> samples() {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    auto in = [&](double lo, double hi) { return lo + (hi - lo) * u(rng); };
    std::vector<Sample> out(n_states);
    for (auto& s : out) {
        s.state << in(-1e4, 1e4), in(-1e4, 1e4), -in(500, 8000), in(-1.0, 1.0), in(-0.5, 0.5),
            in(-3.0, 3.0), in(80, 220), deg(in(-4, 16)), deg(in(-8, 8)), in(-0.5, 0.5),
            in(-0.3, 0.3), in(-0.3, 0.3);
        s.controls.elevator = deg(in(-20, 10));
        s.controls.aileron = deg(in(-15, 10));
        s.controls.rudder = deg(in(-15, 15));
        s.controls.throttle = in(0.1, 1.0);
    }
    return out;
}

void BM_euler_rhs(benchmark::State& state) {
    const fd::FlightModel& m = ranger();
    const auto xs = samples();
    std::size_t i = 0;
    for (auto _ : state) {
        const Sample& s = xs[i++ & (n_states - 1)];
        const auto d = fd::euler_rhs(m, s.state, s.controls);
        benchmark::DoNotOptimize(d);
    }
    state.SetItemsProcessed(state.iterations());
    state.SetLabel(std::string(m.angle_rate_terms ? "alpha-dot terms (implicit solve)"
                                                  : "no alpha-dot terms") +
                   ", kernels: " + fd::detail::fast_rhs_kernel_name());
}
BENCHMARK(BM_euler_rhs);

/// BM_euler_rhs with the fused kernels of one instruction set (states the fused path refuses,
/// out-of-table queries, take the templates as in euler_rhs).
void fused_rhs(benchmark::State& state, fd::detail::FastKernelSet set) {
    const fd::FlightModel& m = ranger();
    const auto xs = samples();
    std::size_t i = 0;
    for (auto _ : state) {
        const Sample& s = xs[i++ & (n_states - 1)];
        fd::EulerState<double> d;
        if (!fd::detail::fast_euler_rhs(m, s.state, s.controls, d, set))
            d = fd::detail::euler_rhs_reference(m, s.state, s.controls);
        benchmark::DoNotOptimize(d);
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_euler_rhs_baseline_kernels(benchmark::State& state) {
    fused_rhs(state, fd::detail::FastKernelSet::baseline);
}
BENCHMARK(BM_euler_rhs_baseline_kernels);

void BM_euler_rhs_avx2_kernels(benchmark::State& state) {
    if (!fd::detail::has_avx2_rhs_kernels()) {
        state.SkipWithError("no AVX2 kernels on this processor or build");
        return;
    }
    fused_rhs(state, fd::detail::FastKernelSet::avx2);
}
BENCHMARK(BM_euler_rhs_avx2_kernels);

/// The same right-hand side by the templates alone (the reference of the fused kernels, and the
/// path of every non-double scalar).
void BM_euler_rhs_templates(benchmark::State& state) {
    const fd::FlightModel& m = ranger();
    const auto xs = samples();
    std::size_t i = 0;
    for (auto _ : state) {
        const Sample& s = xs[i++ & (n_states - 1)];
        const auto d = fd::detail::euler_rhs_reference(m, s.state, s.controls);
        benchmark::DoNotOptimize(d);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_euler_rhs_templates);

/// euler_rhs_batch over batches of `state.range(0)` states (the 4096 varied states in turn):
/// derivative evaluations per second, batched (AVX2: four states per pass).
void BM_euler_rhs_batch(benchmark::State& state) {
    const fd::FlightModel& m = ranger();
    const auto xs = samples();
    const auto batch = static_cast<std::size_t>(state.range(0));
    std::vector<fd::EulerState<double>> s;
    std::vector<fd::Controls<double>> u;
    for (const auto& x : xs) {
        s.push_back(x.state);
        u.push_back(x.controls);
    }
    std::vector<fd::EulerState<double>> d(batch);
    std::size_t i = 0;
    for (auto _ : state) {
        fd::euler_rhs_batch(m, std::span(s).subspan(i, batch), std::span(u).subspan(i, batch), d);
        benchmark::DoNotOptimize(d.data());
        benchmark::ClobberMemory();
        i = (i + batch) & (n_states - 1);
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(batch));
    state.SetLabel(std::string("kernels: ") + fd::detail::fast_rhs_kernel_name());
}
BENCHMARK(BM_euler_rhs_batch)->Arg(4)->Arg(64);

/// quaternion_rhs_batch, as BM_euler_rhs_batch.
void BM_quaternion_rhs_batch(benchmark::State& state) {
    const fd::FlightModel& m = ranger();
    const auto xs = samples();
    const auto batch = static_cast<std::size_t>(state.range(0));
    std::vector<fd::QuatState<double>> s;
    std::vector<fd::Controls<double>> u;
    for (const auto& x : xs) {
        s.push_back(fd::to_quaternion_state(x.state));
        u.push_back(x.controls);
    }
    std::vector<fd::QuatState<double>> d(batch);
    std::size_t i = 0;
    for (auto _ : state) {
        fd::quaternion_rhs_batch(m, std::span(s).subspan(i, batch), std::span(u).subspan(i, batch),
                                 d);
        benchmark::DoNotOptimize(d.data());
        benchmark::ClobberMemory();
        i = (i + batch) & (n_states - 1);
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(batch));
}
BENCHMARK(BM_quaternion_rhs_batch)->Arg(4)->Arg(64);

void BM_quaternion_rhs(benchmark::State& state) {
    const fd::FlightModel& m = ranger();
    const auto xs = samples();
    std::vector<fd::QuatState<double>> qs;
    for (const auto& s : xs) qs.push_back(fd::to_quaternion_state(s.state));
    std::size_t i = 0;
    for (auto _ : state) {
        const std::size_t k = i++ & (n_states - 1);
        const auto d = fd::quaternion_rhs(m, qs[k], xs[k].controls);
        benchmark::DoNotOptimize(d);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_quaternion_rhs);

/// The same tables without the implicit alpha-dot/beta-dot solve (as if they had no such
/// columns): a plain table evaluation instead of one with the angle-rate partial derivatives, and
/// no 2x2 solve.
void BM_euler_rhs_no_alphadot(benchmark::State& state) {
    fd::FlightModel m = ranger();
    m.angle_rate_terms = false;
    const auto xs = samples();
    std::size_t i = 0;
    for (auto _ : state) {
        const Sample& s = xs[i++ & (n_states - 1)];
        const auto d = fd::euler_rhs(m, s.state, s.controls);
        benchmark::DoNotOptimize(d);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_euler_rhs_no_alphadot);

/// The equations without the aero tables, to separate table cost from the rest.
void BM_euler_rhs_no_aero(benchmark::State& state) {
    fd::FlightModel m = ranger();
    m.aero.reset();
    fd::finalize(m);
    const auto xs = samples();
    std::size_t i = 0;
    for (auto _ : state) {
        const Sample& s = xs[i++ & (n_states - 1)];
        const auto d = fd::euler_rhs(m, s.state, s.controls);
        benchmark::DoNotOptimize(d);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_euler_rhs_no_aero);

/// 60 s of flight at 100 Hz RK4 (quaternion form, output every step) from a level state with a
/// doublet on the elevator and a roll input, as `manta simulate` runs it.
void BM_simulate_rk4_100Hz(benchmark::State& state) {
    const fd::FlightModel& m = ranger();
    fd::EulerState<double> s0 = fd::EulerState<double>::Zero();
    s0[fd::euler::z] = -3000.0;
    s0[fd::euler::V] = 150.0;
    s0[fd::euler::alpha] = deg(2.5);
    s0[fd::euler::theta] = deg(2.5);
    fd::Controls<double> u0;
    u0.throttle = 0.5;
    u0.elevator = deg(-2.0);
    const auto inputs = fd::InputHistory::parse(
        "t,elevator_deg,aileron_deg\n0,-2,0\n1,-5,0\n2,1,0\n3,-2,0\n10,-2,5\n12,-2,-5\n14,-2,0\n",
        "bench.csv", u0);
    fd::SimulationOptions opt;
    opt.duration = static_cast<double>(state.range(0));
    opt.dt = 0.01;
    opt.form = fd::StateForm::quaternion;
    double simulated = 0.0;
    for (auto _ : state) {
        const auto r = fd::simulate(m, s0, inputs, opt);
        simulated += r.final_time;
        benchmark::DoNotOptimize(r.rows.data());
    }
    state.counters["sim_s_per_wall_s"] = benchmark::Counter(simulated, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_simulate_rk4_100Hz)->Arg(60)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
