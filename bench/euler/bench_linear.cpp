// The implicit Euler solver's linear algebra (manta/euler/block_matrix.hpp): block ILU(0)
// factorisation, its application, block symmetric Gauss-Seidel's set-up (inverted diagonal
// blocks) and application, the block matrix-vector product and one 20-iteration FGMRES
// solve, on the edge graph of a tetrahedral grid of 47^3 = 103 823 nodes (the Freudenthal
// split of each cube into six tetrahedra: 14 neighbours per interior node, as in a typical
// tetrahedral mesh) with random diagonally dominant 5x5 blocks.
//
//   build/bench/euler/bench_linear --benchmark_repetitions=5
//   --benchmark_report_aggregates_only=true
//
// Argument 0: nodes in grid order (lexicographic, a banded order like reverse Cuthill-McKee's);
// argument 1: nodes in a random order, as from a mesh generator that orders nothing. Counters:
// s_per_node (seconds per call per node), bytes_per_node (memory of the object benchmarked),
// iterations_to_1e-6 (FGMRES(20) iterations for a 1e-6 residual drop, to compare the ILU(0)'s
// quality in the two orders).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <memory>
#include <numeric>
#include <random>
#include <vector>

#include "manta/euler/block_matrix.hpp"

namespace {

using namespace manta;
using euler::Index;
using Edge = std::array<Index, 2>;

constexpr int grid_n = 47;

struct System {
    Index n = 0;
    std::vector<Edge> edges;
    euler::BlockMatrix A;
    euler::BlockIlu0 M;
    std::vector<double> x, b;
};

/// The Freudenthal grid's edges in node order `order` (node id -> position), (i, j) with i < j.
std::vector<Edge> tet_grid_edges(int n, const std::vector<Index>& order) {
    static constexpr int offsets[7][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0},
                                          {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
    const auto id = [&](int i, int j, int k) { return order[(k * n + j) * n + i]; };
    std::vector<Edge> edges;
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                for (const auto& o : offsets) {
                    const int a = i + o[0], b = j + o[1], c = k + o[2];
                    if (a < n && b < n && c < n) {
                        const Index p = id(i, j, k), q = id(a, b, c);
                        edges.push_back({std::min(p, q), std::max(p, q)});
                    }
                }
    // Edges sorted by their first node, as the mesh module produces them.
    std::sort(edges.begin(), edges.end());
    return edges;
}

std::unique_ptr<System> make_system(bool shuffled) {
    auto s = std::make_unique<System>();
    s->n = grid_n * grid_n * grid_n;
    std::vector<Index> order(s->n);
    std::iota(order.begin(), order.end(), 0);
    std::mt19937_64 rng(42);
    if (shuffled) std::shuffle(order.begin(), order.end(), rng);
    s->edges = tet_grid_edges(grid_n, order);
    s->A = euler::BlockMatrix(s->n, s->n, s->edges);
    // Random blocks, off-diagonal ones like a convective Jacobian's (a negative multiple of the
    // identity plus a random part), diagonal blocks made dominant.
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const auto random_block = [&](double scale) {
        euler::Mat5 m;
        for (int r = 0; r < 5; ++r)
            for (int c = 0; c < 5; ++c) m(r, c) = scale * u(rng);
        return m;
    };
    for (Index e = 0; e < Index(s->edges.size()); ++e) {
        s->A.add(s->A.edge_ij(e), -euler::Mat5::Identity() + random_block(0.2));
        s->A.add(s->A.edge_ji(e), -euler::Mat5::Identity() + random_block(0.2));
    }
    for (Index r = 0; r < s->n; ++r) {
        s->A.add(s->A.diagonal(r), random_block(0.2));
        const auto rows = s->A.row_offsets();
        s->A.add_to_diagonal(r, 2.0 * double(rows[r + 1] - rows[r] - 1) + 1.0);
    }
    s->M.factorize(s->A);
    s->x.resize(5 * std::size_t(s->n));
    s->b.resize(5 * std::size_t(s->n));
    for (auto& v : s->b) v = u(rng);
    return s;
}

System& system(bool shuffled) {
    static std::array<std::unique_ptr<System>, 2> systems;
    auto& s = systems[shuffled ? 1 : 0];
    if (!s) s = make_system(shuffled);
    return *s;
}

void per_node(benchmark::State& state, const System& s, std::size_t bytes) {
    state.counters["s_per_node"] = benchmark::Counter(
        double(s.n), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
    state.counters["bytes_per_node"] = double(bytes) / double(s.n);
}

void BM_factorize(benchmark::State& state) {
    System& s = system(state.range(0) != 0);
    euler::BlockIlu0 M;
    M.factorize(s.A);  // symbolic part and first touch: the solver refactorises in place
    for (auto _ : state) M.factorize(s.A);
    per_node(state, s, M.memory_bytes());
}
BENCHMARK(BM_factorize)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_apply(benchmark::State& state) {
    System& s = system(state.range(0) != 0);
    for (auto _ : state) {
        s.M.apply(s.b, s.x);
        benchmark::ClobberMemory();
    }
    per_node(state, s, s.M.memory_bytes());
}
BENCHMARK(BM_apply)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_multiply(benchmark::State& state) {
    System& s = system(state.range(0) != 0);
    for (auto _ : state) {
        s.A.multiply(s.b, s.x);
        benchmark::ClobberMemory();
    }
    per_node(state, s, s.A.memory_bytes());
}
BENCHMARK(BM_multiply)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_sgs_factorize(benchmark::State& state) {
    System& s = system(state.range(0) != 0);
    euler::BlockSgs M;
    for (auto _ : state) M.factorize(s.A);
    per_node(state, s, M.memory_bytes());
}
BENCHMARK(BM_sgs_factorize)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_sgs_apply(benchmark::State& state) {
    System& s = system(state.range(0) != 0);
    euler::BlockSgs M;
    M.factorize(s.A);
    for (auto _ : state) {
        M.apply(s.b, s.x);
        benchmark::ClobberMemory();
    }
    per_node(state, s, M.memory_bytes());
}
BENCHMARK(BM_sgs_apply)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_fgmres_20(benchmark::State& state) {
    System& s = system(state.range(0) != 0);
    const parallel::SerialCommunicator comm;
    const parallel::SerialHalo halo;
    euler::Fgmres solver;
    euler::KrylovOptions o;
    o.restart = 20;
    o.max_iterations = 20;
    o.relative_tolerance = 0.0;  // always 20 iterations
    double residual = solver.solve(s.A, s.M, s.b, s.x, comm, halo, o).relative_residual;  // warm
    for (auto _ : state)
        residual = solver.solve(s.A, s.M, s.b, s.x, comm, halo, o).relative_residual;
    per_node(state, s, solver.memory_bytes());
    state.counters["residual_after_20"] = residual;
    o.max_iterations = 200;
    o.relative_tolerance = 1e-6;
    state.counters["iterations_to_1e-6"] =
        solver.solve(s.A, s.M, s.b, s.x, comm, halo, o).iterations;
}
BENCHMARK(BM_fgmres_20)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
