// MANTA's side of bench/optimal/vs_psopt.sh: one problem solved once, on a fixed mesh or by the
// error-driven refinement, with the starting guesses of PSOPT's examples, and one result line.
//
//   build/bin/bench_optimal_vs_psopt PROBLEM MODE NODES
//     PROBLEM  brachistochrone | climb | schwartz
//     MODE     fixed (one segment of NODES LGL points per phase) | adaptive (solve_adaptive from
//              it, default RefinementOptions)
//
// Problems (each as PSOPT 5.0.2's example of the same name defines it):
//   brachistochrone  PSOPT examples/brac1: g = 9.8 m/s^2, rest at the origin to (2, 2), min t_f;
//                    guess x, y, v linear 0 -> 1 over [0, 2] s, theta = 1 rad.
//   climb            PSOPT examples/climb (MinTimeToClimb, 8-layer atmosphere); guess linear
//                    between the boundary values, w to 0.8 w0, alpha = 0, over [0, 500] s.
//   schwartz         PSOPT examples/twophase_schwartz: two phases on [0, 1] and [1, 2.9];
//                    guess x = (1, 1), u = 0.
// IPOPT: exact Hessian, tol 1e-8, MUMPS (SolverOptions defaults).
//
// Output, one line of key=value pairs:
//   manta problem=... mode=... status=... objective=... iterations=... passes=... nodes=...
//   solve_cpu_s=... solve_wall_s=... max_error=... (the last pass's error estimate, -1 on a fixed
//   mesh) node_list=a,b,... (final LGL points per segment, phases separated by '/')

#include <chrono>
#include <cstdio>
#include <ctime>
#include <exception>
#include <string>
#include <vector>

#include "manta/optimal/multiphase.hpp"
#include "manta/optimal/problems.hpp"
#include "manta/optimal/refine.hpp"

namespace {

using namespace manta::optimal;

/// The two-phase Schwartz problem (A. L. Schwartz, PhD thesis, U. C. Berkeley, 1996; PSOPT's
/// examples/twophase_schwartz): x1' = x2, x2' = u - 0.1 (1 + 2 x1^2) x2 from (1, 1); phase 1 on
/// [0, 1], |u| <= 1, x2 >= -0.8, outside the ellipse 9 (x1 - 1)^2 + ((x2 - 0.4)/0.3)^2 = 1;
/// phase 2 on [1, 2.9], |u| <= 50, x2 >= -10; min 5 (x1^2 + x2^2) at 2.9.
struct Schwartz {
    int phase = 1;
    [[nodiscard]] ProblemInfo info() const {
        ProblemInfo p;
        p.name = phase == 1 ? "Schwartz phase 1" : "Schwartz phase 2";
        p.states = {{"x1", -20.0, 10.0, 1.0}, {"x2", phase == 1 ? -0.8 : -10.0, 10.0, 1.0}};
        p.controls = {{"u", phase == 1 ? -1.0 : -50.0, phase == 1 ? 1.0 : 50.0, 1.0}};
        if (phase == 1) {
            p.path = {{"ellipse", -100.0, 0.0, 1.0}};
            p.initial_time = fixed(0.0);
            p.final_time = fixed(1.0);
            p.set_initial("x1", 1.0);
            p.set_initial("x2", 1.0);
        } else {
            p.initial_time = fixed(1.0);
            p.final_time = fixed(2.9);
            p.objective_scale = 1.0;
        }
        return p;
    }
    template <class T>
    void dynamics(std::span<const T> x, std::span<const T> u, std::span<const T> /*p*/,
                  const T& /*t*/, std::span<T> xdot) const {
        xdot[0] = x[1];
        xdot[1] = u[0] - 0.1 * (1.0 + 2.0 * x[0] * x[0]) * x[1];
    }
    template <class T>
    void path(std::span<const T> x, std::span<const T> /*u*/, std::span<const T> /*p*/,
              const T& /*t*/, std::span<T> g) const {
        const T a = x[0] - 1.0;
        const T b = (x[1] - 0.4) / 0.3;
        g[0] = 1.0 - 9.0 * a * a - b * b;
    }
};
struct SchwartzEnd : Schwartz {
    template <class T>
    T mayer(std::span<const T> /*x0*/, std::span<const T> xf, std::span<const T> /*p*/,
            const T& /*t0*/, const T& /*tf*/) const {
        return 5.0 * (xf[0] * xf[0] + xf[1] * xf[1]);
    }
};

std::string node_list(const Mesh& m) {
    std::string s;
    for (std::size_t k = 0; k < m.nodes.size(); ++k) {
        if (k > 0) s += ',';
        s += std::to_string(m.nodes[k]);
    }
    return s;
}

int total(const Mesh& m) {
    int n = 0;
    for (const int k : m.nodes) n += k;
    return n;
}

struct Result {
    std::string status;
    double objective = 0.0;
    int iterations = 0;
    int passes = 1;
    int nodes = 0;
    double cpu = 0.0;
    std::string nodes_text;
    double max_error = -1.0;  ///< the refinement's last error estimate (-1: fixed mesh)
};

Result single(const Model& model, const Guess& guess, bool adaptive, int n) {
    SolverOptions o;
    o.resimulate = false;
    const Mesh mesh = Mesh::uniform(1, n);
    Result r;
    if (!adaptive) {
        const Solution s = solve(model, mesh, guess, o);
        r = {to_string(s.status), s.objective, s.iterations,   1,
             total(mesh),         s.cpu_time,  node_list(mesh)};
        return r;
    }
    // the refinement's error estimate needs no re-simulation; its stop is the estimate
    const AdaptiveSolution a = solve_adaptive(model, mesh, guess, o, RefinementOptions{});
    r.status = to_string(a.status);
    r.objective = a.solution.objective;
    r.passes = static_cast<int>(a.passes.size());
    for (const RefinementPass& p : a.passes) {
        r.iterations += p.iterations;
        r.cpu += p.cpu_s;
    }
    r.nodes = total(a.mesh);
    r.nodes_text = node_list(a.mesh);
    r.max_error = a.passes.empty() ? -1.0 : a.passes.back().max_error;
    return r;
}

Result schwartz(bool adaptive, int n) {
    Schwartz one;
    SchwartzEnd two;
    two.phase = 2;
    Eigen::VectorXd x(2), u(1);
    x << 1.0, 1.0;
    u << 0.0;
    MultiPhaseProblem mp;
    mp.name = "two-phase Schwartz";
    mp.phases = {{make_model(one), Mesh::uniform(1, n), Guess::linear(0.0, 1.0, x, x, u, u)},
                 {make_model(two), Mesh::uniform(1, n), Guess::linear(1.0, 2.9, x, x, u, u)}};
    SolverOptions o;
    o.resimulate = false;
    Result r;
    if (!adaptive) {
        const MultiPhaseSolution s = solve(mp, o);
        r = {to_string(s.status),
             s.objective,
             s.iterations,
             1,
             2 * n,
             s.cpu_time,
             node_list(mp.phases[0].mesh) + "/" + node_list(mp.phases[1].mesh)};
        return r;
    }
    const MultiPhaseAdaptiveSolution a = solve_adaptive(mp, o, RefinementOptions{});
    r.status = to_string(a.status);
    r.objective = a.solution.objective;
    r.passes = static_cast<int>(a.passes.size());
    for (const MultiPhasePass& p : a.passes) {
        r.iterations += p.iterations;
        r.cpu += p.cpu_s;
    }
    r.nodes = 0;
    for (std::size_t k = 0; k < a.meshes.size(); ++k) {
        r.nodes += total(a.meshes[k]);
        r.nodes_text += (k > 0 ? "/" : "") + node_list(a.meshes[k]);
    }
    r.max_error = a.passes.empty() ? -1.0 : a.passes.back().max_error;
    return r;
}

int run(const std::string& problem, const std::string& mode, int n) {
    const bool adaptive = mode == "adaptive";
    const auto w0 = std::chrono::steady_clock::now();
    Result r;
    if (problem == "brachistochrone") {
        Brachistochrone b;
        b.gravity = 9.8;
        b.x_final = 2.0;
        b.y_final = 2.0;
        const auto model = make_model(b);
        const Guess g =
            Guess::linear(0.0, 2.0, Eigen::Vector3d(0.0, 0.0, 0.0), Eigen::Vector3d(1.0, 1.0, 1.0),
                          Eigen::VectorXd::Ones(1), Eigen::VectorXd::Ones(1));
        r = single(*model, g, adaptive, n);
    } else if (problem == "climb") {
        const MinTimeToClimb c;
        const auto model = make_model(c);
        const Guess g = Guess::linear(0.0, 500.0, Eigen::Vector4d(0.0, 424.26, 0.0, 42000.0),
                                      Eigen::Vector4d(65600.0, 968.148, 0.0, 0.8 * 42000.0),
                                      Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1));
        r = single(*model, g, adaptive, n);
    } else if (problem == "schwartz") {
        r = schwartz(adaptive, n);
    } else {
        std::fprintf(stderr,
                     "bench_optimal_vs_psopt: problem '%s', expected brachistochrone, climb or "
                     "schwartz\n",
                     problem.c_str());
        return 2;
    }
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    std::printf(
        "manta problem=%s mode=%s status=%s objective=%.12g iterations=%d passes=%d nodes=%d "
        "solve_cpu_s=%.4f solve_wall_s=%.4f max_error=%.3e node_list=%s\n",
        problem.c_str(), mode.c_str(), r.status.c_str(), r.objective, r.iterations, r.passes,
        r.nodes, r.cpu, wall, r.max_error, r.nodes_text.c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr,
                     "usage: bench_optimal_vs_psopt brachistochrone|climb|schwartz "
                     "fixed|adaptive NODES\n");
        return 2;
    }
    const std::string mode = argv[2];
    if (mode != "fixed" && mode != "adaptive") {
        std::fprintf(stderr, "bench_optimal_vs_psopt: mode '%s', expected fixed or adaptive\n",
                     argv[2]);
        return 2;
    }
    int n = 0;
    try {
        n = std::stoi(argv[3]);
    } catch (const std::exception&) {
        n = 0;
    }
    if (n < 2) {
        std::fprintf(stderr, "bench_optimal_vs_psopt: NODES '%s', expected an integer >= 2\n",
                     argv[3]);
        return 2;
    }
    try {
        return run(argv[1], mode, n);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_optimal_vs_psopt: %s\n", e.what());
        return 1;
    }
}
