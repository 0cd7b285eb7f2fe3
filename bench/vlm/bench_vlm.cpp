// Vortex-lattice benchmarks: the steady solution with every stability and control derivative
// (influence matrix, factorisation, unit solutions, differences) for the Ranger 2000 lattice of
// the default density (~2 000 vortices) and for AVL's b737 sample (1 505 vortices), both
// mirror-symmetric (two half systems), and the Ranger once more with its mirror plane moved by
// 1e-12 m so that the solver takes the whole system (the path of asymmetric lattices).
//
//   build/bench/vlm/bench_vlm --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//
// MANTA_VLM_KERNELS=baseline or =avx2 in the environment runs the baseline x86-64 or the AVX2
// kernels instead of the widest set the processor has (detail/kernels.hpp). The default path is
// single precision with iterative refinement (SteadyOptions::single_precision); the `_double`
// cases run the double-precision path. The project's target is under 50 ms per case on one core
// (issue 3). Also one step of the unsteady lattice of the Ranger with a 200-row wake, and one step
// as in the 60-second replay (vlm_replay_60s: time step c_ref / v0, 20-row wake, two threads).

#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include "manta/aircraft/aircraft.hpp"
#include "manta/core/memory.hpp"
#include "manta/vlm/avl_reader.hpp"
#include "manta/vlm/steady.hpp"
#include "manta/vlm/unsteady.hpp"

namespace {

namespace fs = std::filesystem;
using namespace manta;

vlm::Model ranger() {
    const auto def = aircraft::load_aircraft(fs::path(MANTA_SOURCE_DIR) / "examples" /
                                             "ranger2000" / "aircraft.yaml");
    vlm::Reference ref{def.reference.area, def.reference.span, def.reference.chord,
                       def.moment_reference_geom};
    return vlm::from_geometry(def.geometry, ref, {}, def.name);
}

void run(benchmark::State& state, const vlm::Model& m, double mach, double alpha,
         bool single = true, vlm::TrailingLegs legs = vlm::TrailingLegs::body_axis) {
    const vlm::Lattice lattice = vlm::build_lattice(m);
    vlm::FlowState s;
    s.alpha = alpha;
    vlm::SteadyOptions o;
    o.single_precision = single;
    o.trailing_legs = legs;
    for (auto _ : state) {
        const vlm::SteadySolver solver(m, lattice, mach, o);
        benchmark::DoNotOptimize(solver.derivatives(s));
    }
    state.counters["vortices"] = lattice.size();
}

void BM_ranger_steady_and_derivatives(benchmark::State& state) {
    run(state, ranger(), 0.3, 0.035);
}
BENCHMARK(BM_ranger_steady_and_derivatives)->Unit(benchmark::kMillisecond);

/// Trailing legs along the free stream (the aerodynamic source's, MANTA issue 16).
void BM_ranger_steady_and_derivatives_freestream_legs(benchmark::State& state) {
    run(state, ranger(), 0.3, 0.035, true, vlm::TrailingLegs::freestream);
}
BENCHMARK(BM_ranger_steady_and_derivatives_freestream_legs)->Unit(benchmark::kMillisecond);

/// One steady solution (no derivatives) with a solver built once, as the aerodynamic source
/// evaluates a table point: body-axis and free-stream legs.
void solve_only(benchmark::State& state, vlm::TrailingLegs legs) {
    const vlm::Model m = ranger();
    vlm::SteadyOptions o;
    o.trailing_legs = legs;
    const vlm::SteadySolver solver(m, vlm::build_lattice(m), 0.3, o);
    vlm::FlowState s;
    s.alpha = 0.035;
    for (auto _ : state) benchmark::DoNotOptimize(solver.solve(s));
}
void BM_ranger_steady_solve(benchmark::State& state) {
    solve_only(state, vlm::TrailingLegs::body_axis);
}
BENCHMARK(BM_ranger_steady_solve)->Unit(benchmark::kMillisecond);
void BM_ranger_steady_solve_freestream_legs(benchmark::State& state) {
    solve_only(state, vlm::TrailingLegs::freestream);
}
BENCHMARK(BM_ranger_steady_solve_freestream_legs)->Unit(benchmark::kMillisecond);

void BM_ranger_steady_and_derivatives_double(benchmark::State& state) {
    run(state, ranger(), 0.3, 0.035, false);
}
BENCHMARK(BM_ranger_steady_and_derivatives_double)->Unit(benchmark::kMillisecond);

/// The Ranger without exact mirror symmetry: the mirror copies' plane at y = 1e-12 m.
void BM_ranger_steady_and_derivatives_whole_system(benchmark::State& state) {
    vlm::Model m = ranger();
    for (auto& s : m.surfaces)
        if (s.y_duplicate) s.y_duplicate = 1e-12;
    run(state, m, 0.3, 0.035);
}
BENCHMARK(BM_ranger_steady_and_derivatives_whole_system)->Unit(benchmark::kMillisecond);

void BM_b737_steady_and_derivatives(benchmark::State& state) {
    const fs::path file = fs::path(MANTA_SHARED_DIR) / "reference" / "avl" / "samples" / "b737.avl";
    if (!fs::exists(file)) {
        state.SkipWithError("no AVL reference data");
        return;
    }
    run(state, vlm::read_avl(file), 0.7, 0.0335);
}
BENCHMARK(BM_b737_steady_and_derivatives)->Unit(benchmark::kMillisecond);

void BM_b737_steady_and_derivatives_double(benchmark::State& state) {
    const fs::path file = fs::path(MANTA_SHARED_DIR) / "reference" / "avl" / "samples" / "b737.avl";
    if (!fs::exists(file)) {
        state.SkipWithError("no AVL reference data");
        return;
    }
    run(state, vlm::read_avl(file), 0.7, 0.0335, false);
}
BENCHMARK(BM_b737_steady_and_derivatives_double)->Unit(benchmark::kMillisecond);

/// One unsteady step of the Ranger lattice (default density, ~2 000 panels) with a 200-row wake
/// (started from the steady solution, whose wake is already full), at constant attitude.
void BM_ranger_uvlm_step_200_wake_rows(benchmark::State& state) {
    const vlm::Model m = ranger();
    vlm::UnsteadyOptions o;
    o.wake_rows = 200;
    o.speed = 150.0;
    o.mach = 0.3;
    vlm::UnsteadySolver solver(m, vlm::build_lattice(m), o);
    aero::Motion motion;
    for (int i = 0; i <= 1; ++i) {
        motion.t.push_back(100.0 * i);
        for (auto& p : motion.position) p.push_back(0.0);
        motion.angles[0].push_back(0.0);
        motion.angles[1].push_back(0.035);
        motion.angles[2].push_back(0.0);
    }
    motion.add_mode("elevator", {0.0, 0.0});
    motion.add_mode("aileron", {0.0, 0.0});
    motion.add_mode("rudder", {0.0, 0.0});
    (void)solver.start(motion);
    for (auto _ : state) benchmark::DoNotOptimize(solver.step());
    state.counters["panels"] = solver.lattice().size();
    state.counters["wake_rows"] = solver.current().wake_rows;
}
BENCHMARK(BM_ranger_uvlm_step_200_wake_rows)->Unit(benchmark::kMillisecond)->Iterations(10);

/// One step of the 60-second replay's settings (bench/vlm/replay_60s.cpp): time step c_ref / v0,
/// 20-row wake, two worker threads, a rolling and pitching motion with control deflections.
void BM_ranger_uvlm_replay_step_20_wake_rows_2_threads(benchmark::State& state) {
    const vlm::Model m = ranger();
    vlm::UnsteadyOptions o;
    o.dt = m.reference.chord / 150.0;
    o.wake_length = 20.0;
    o.speed = 150.0;
    o.mach = 0.45;
    o.threads = 2;
    vlm::UnsteadySolver solver(m, vlm::build_lattice(m), o);
    aero::Motion motion;
    std::vector<double> de, da;
    for (int i = 0; i <= 100; ++i) {
        const double t = 0.05 * i;
        motion.t.push_back(t);
        for (auto& p : motion.position) p.push_back(0.0);
        motion.angles[0].push_back(0.3 * std::sin(0.5 * t));
        motion.angles[1].push_back(0.035 + 0.05 * std::sin(t));
        motion.angles[2].push_back(0.0);
        de.push_back(-0.05 * std::sin(t));
        da.push_back(0.05 * std::cos(0.5 * t));
    }
    motion.add_mode("elevator", de);
    motion.add_mode("aileron", da);
    motion.add_mode("rudder", std::vector<double>(de.size(), 0.0));
    (void)solver.start(motion);
    for (auto _ : state) {
        if (solver.finished()) (void)solver.start(motion);
        benchmark::DoNotOptimize(solver.step());
    }
    state.counters["panels"] = solver.lattice().size();
    state.counters["wake_rows"] = solver.max_wake_rows();
}
BENCHMARK(BM_ranger_uvlm_replay_step_20_wake_rows_2_threads)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);

}  // namespace

// The allocator settings of the `manta` program (core/memory.hpp), so the figures are those of
// `manta vlm` and of table campaigns.
int main(int argc, char** argv) {
    manta::core::keep_large_allocations();
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
