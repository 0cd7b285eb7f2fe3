// The Euler solver's point-wise flux kernels (manta/euler/flux.hpp) and the edge-based residual
// and Jacobian (manta/euler/spatial.hpp), static and with grid fluxes (arbitrary
// Lagrangian-Eulerian form, docs/euler.md).
//
//   build/bench/euler/bench_flux --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//
// Kernels: one call per state pair of 1024 random pairs and area vectors (ns per call is the
// reported time divided by 1024; the counter ns_per_call gives it). Residuals: a unit cube of
// 24^3 sub-cubes split into six tetrahedra each (Kuhn), all far field, a perturbed free stream;
// counter ns_per_edge.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <map>
#include <random>
#include <vector>

#include "manta/euler/flux.hpp"
#include "manta/euler/spatial.hpp"
#include "manta/mesh/dual.hpp"

namespace {

using namespace manta;
using euler::Mat5;
using euler::Vec3;
using euler::Vec5;

constexpr double gam = 1.4;
constexpr int n_pairs = 1024;

struct Pairs {
    std::vector<Vec5> L, R;
    std::vector<Vec3> n;
    std::vector<double> g;
};

const Pairs& pairs() {
    static const Pairs p = [] {
        Pairs q;
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        const auto state = [&] {
            Vec5 W;
            W << 1.0 + 0.3 * u(rng), 0.8 + 0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng),
                1.0 / gam + 0.2 * u(rng);
            return W;
        };
        for (int k = 0; k < n_pairs; ++k) {
            q.L.push_back(state());
            q.R.push_back(state());
            q.n.push_back(Vec3(u(rng), u(rng), u(rng)));
            q.g.push_back(0.3 * u(rng) * q.n.back().norm());
        }
        return q;
    }();
    return p;
}

template <class F>
void run_pairs(benchmark::State& state, F&& f) {
    const Pairs& p = pairs();
    for (auto _ : state)
        for (int k = 0; k < n_pairs; ++k) f(p, k);
    state.counters["ns_per_call"] = benchmark::Counter(
        static_cast<double>(state.iterations()) * n_pairs,
        benchmark::Counter::kIsRate | benchmark::Counter::kInvert, benchmark::Counter::kIs1000);
}

void BM_roe(benchmark::State& state) {
    euler::FluxOptions o;
    o.low_mach_fix = state.range(0) != 0;
    run_pairs(state, [&](const Pairs& p, int k) {
        benchmark::DoNotOptimize(euler::numerical_flux(p.L[k], p.R[k], p.n[k], gam, o));
    });
}
BENCHMARK(BM_roe)->Arg(0)->Arg(1);

void BM_hllc(benchmark::State& state) {
    euler::FluxOptions o;
    o.scheme = euler::FluxScheme::hllc;
    run_pairs(state, [&](const Pairs& p, int k) {
        benchmark::DoNotOptimize(euler::numerical_flux(p.L[k], p.R[k], p.n[k], gam, o));
    });
}
BENCHMARK(BM_hllc);

void BM_roe_jacobians(benchmark::State& state) {
    euler::FluxOptions o;
    Mat5 A, B;
    run_pairs(state, [&](const Pairs& p, int k) {
        euler::flux_jacobians(p.L[k], p.R[k], p.n[k], gam, o, A, B);
        benchmark::DoNotOptimize(A);
        benchmark::DoNotOptimize(B);
    });
}
BENCHMARK(BM_roe_jacobians);

void BM_farfield(benchmark::State& state) {
    Mat5 A;
    const Vec5 Winf = pairs().L[0];
    const bool jac = state.range(0) != 0;
    run_pairs(state, [&](const Pairs& p, int k) {
        benchmark::DoNotOptimize(
            euler::farfield_flux(p.L[k], Winf, p.n[k], gam, jac ? &A : nullptr));
        benchmark::DoNotOptimize(A);
    });
}
BENCHMARK(BM_farfield)->Arg(0)->Arg(1);

void BM_wall(benchmark::State& state) {
    run_pairs(state, [&](const Pairs& p, int k) {
        benchmark::DoNotOptimize(euler::wall_flux(p.L[k], p.n[k], gam));
        benchmark::DoNotOptimize(euler::wall_flux_jacobian(p.L[k], p.n[k], gam));
    });
}
BENCHMARK(BM_wall);

// ---------------------------------------------------------------------------------------------

struct Case {
    mesh::Mesh m{"bench box"};
    mesh::DualMetrics d;
    parallel::SerialHalo halo;
    euler::NodeStates U;
};

Case& box() {
    static Case* c = [] {
        auto* b = new Case;
        constexpr int n = 24;
        const auto id = [](int i, int j, int k) { return i + (n + 1) * (j + (n + 1) * k); };
        for (int k = 0; k <= n; ++k)
            for (int j = 0; j <= n; ++j)
                for (int i = 0; i <= n; ++i)
                    b->m.add_node(Eigen::Vector3d(i, j, k) / static_cast<double>(n));
        std::map<std::array<mesh::Index, 3>, std::array<mesh::Index, 3>> open;
        for (int k = 0; k < n; ++k)
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    std::array<int, 3> axes{0, 1, 2};
                    do {
                        std::array<int, 3> p{0, 0, 0};
                        std::vector<mesh::Index> t{id(i, j, k)};
                        for (int s = 0; s < 2; ++s) {
                            p[axes[s]] = 1;
                            t.push_back(id(i + p[0], j + p[1], k + p[2]));
                        }
                        t.push_back(id(i + 1, j + 1, k + 1));
                        const auto x = [&](int q) { return b->m.node(t[q]); };
                        if ((x(1) - x(0)).cross(x(2) - x(0)).dot(x(3) - x(0)) < 0.0)
                            std::swap(t[1], t[2]);
                        b->m.add_cell(mesh::CellType::tetra, t);
                        for (const auto& f : mesh::cell_faces(mesh::CellType::tetra)) {
                            std::array<mesh::Index, 3> fn{t[f[0]], t[f[1]], t[f[2]]}, key = fn;
                            std::sort(key.begin(), key.end());
                            if (!open.erase(key)) open[key] = fn;
                        }
                    } while (std::next_permutation(axes.begin(), axes.end()));
                }
        const int far = b->m.add_marker("farfield");
        for (const auto& [key, fn] : open) b->m.add_face(mesh::FaceType::triangle, fn, far);
        b->m.finalize();
        b->d = mesh::compute_dual_metrics(b->m);
        b->U.resize(5, b->m.n_nodes());
        std::mt19937 rng(3);
        std::uniform_real_distribution<double> u(-0.02, 0.02);
        for (mesh::Index i = 0; i < b->m.n_nodes(); ++i) {
            Vec5 W;
            W << 1.0 + u(rng), 0.5 + u(rng), u(rng), u(rng), 1.0 / gam + u(rng);
            b->U.col(i) = euler::conservative(W, gam);
        }
        return b;
    }();
    return *c;
}

void BM_residual(benchmark::State& state) {
    Case& c = box();
    euler::SpatialOptions o;
    o.order = static_cast<int>(state.range(0) % 10);
    if (state.range(0) >= 10) o.flux.scheme = euler::FluxScheme::jst;
    Vec5 Winf;
    Winf << 1.0, 0.5, 0.0, 0.0, 1.0 / gam;
    euler::SpatialOperator op({&c.m, &c.d, c.m.n_nodes(), &c.halo}, {euler::BoundaryKind::farfield},
                              Winf, gam, o);
    euler::NodeStates R;
    op.residual(c.U, R);
    for (auto _ : state) {
        op.residual(c.U, R);
        benchmark::DoNotOptimize(R.data());
    }
    state.counters["ns_per_edge"] = benchmark::Counter(
        static_cast<double>(state.iterations()) * c.d.n_edges(),
        benchmark::Counter::kIsRate | benchmark::Counter::kInvert, benchmark::Counter::kIs1000);
}
// 1, 2: Roe order 1 and 2; 12: JST.
BENCHMARK(BM_residual)->Arg(1)->Arg(2)->Arg(12)->Unit(benchmark::kMillisecond);

void BM_jacobian(benchmark::State& state) {
    Case& c = box();
    euler::SpatialOptions o;
    Vec5 Winf;
    Winf << 1.0, 0.5, 0.0, 0.0, 1.0 / gam;
    euler::SpatialOperator op({&c.m, &c.d, c.m.n_nodes(), &c.halo}, {euler::BoundaryKind::farfield},
                              Winf, gam, o);
    euler::BlockMatrix J = op.make_jacobian_matrix();
    for (auto _ : state) {
        op.jacobian(c.U, J);
        benchmark::ClobberMemory();
    }
    state.counters["ns_per_edge"] = benchmark::Counter(
        static_cast<double>(state.iterations()) * c.d.n_edges(),
        benchmark::Counter::kIsRate | benchmark::Counter::kInvert, benchmark::Counter::kIs1000);
}
BENCHMARK(BM_jacobian)->Unit(benchmark::kMillisecond);

// The per-step geometry of a moving mesh: the dual metrics recomputed from moved coordinates
// and the volumes the dual faces sweep between two coordinate levels (a rigid rotation).
void BM_moving_geometry(benchmark::State& state) {
    Case& c = box();
    const auto n = static_cast<std::size_t>(c.m.n_nodes());
    std::vector<double> x0(3 * n), x1(3 * n);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitY()).toRotationMatrix();
    for (std::size_t i = 0; i < n; ++i) {
        const Eigen::Vector3d p = c.m.node(static_cast<mesh::Index>(i));
        const Eigen::Vector3d q = R * p;
        for (int k = 0; k < 3; ++k) {
            x0[3 * i + k] = p[k];
            x1[3 * i + k] = q[k];
        }
    }
    mesh::DualFaceValues swept;
    swept.resize_for(c.d);
    for (auto _ : state) {
        if (state.range(0) == 0)
            mesh::update_dual_metrics(c.m, c.d);
        else
            mesh::swept_volumes(c.m, c.d, x0, x1, swept);
        benchmark::ClobberMemory();
    }
    state.counters["ns_per_cell"] = benchmark::Counter(
        static_cast<double>(state.iterations()) * c.m.n_cells(),
        benchmark::Counter::kIsRate | benchmark::Counter::kInvert, benchmark::Counter::kIs1000);
}
// 0: update_dual_metrics; 1: swept_volumes.
BENCHMARK(BM_moving_geometry)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
