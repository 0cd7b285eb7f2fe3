// Error-driven ph mesh refinement (refine.hpp) and hp refinement at control jumps: the LGL
// integration matrix, the error estimate, the ph rule of Patterson, Hager & Rao (Optim. Control
// Appl. Meth. 36, 2015), no coarsening over random meshes, junction re-indexing, and the
// refine_at_control_jumps defects of issue 20 (coarsening, clustered breaks).

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <span>
#include <vector>

#include "manta/core/error.hpp"
#include "manta/optimal/lgl.hpp"
#include "manta/optimal/problems.hpp"
#include "manta/optimal/refine.hpp"

namespace {

using namespace manta::optimal;

TEST(Refine, LglIntegrationMatrixIsExactForPolynomialsOfDegreeNMinus1) {
    for (const int n : {2, 3, 5, 9, 16}) {
        const LglRule r = lgl_rule(n);
        const Eigen::MatrixXd I = lgl_integration_matrix(n);
        for (int d = 0; d < n; ++d) {
            Eigen::VectorXd f(n), exact(n);
            for (int j = 0; j < n; ++j) {
                const double t = r.points(j);
                f(j) = std::pow(t, d);
                exact(j) = (std::pow(t, d + 1) - std::pow(-1.0, d + 1)) / (d + 1);
            }
            EXPECT_LT((I * f - exact).cwiseAbs().maxCoeff(), 1e-13) << n << " points, degree " << d;
        }
        // the last row integrates over [-1, 1]: the LGL weights
        EXPECT_LT((I.row(n - 1).transpose() - r.weights).cwiseAbs().maxCoeff(), 1e-13);
    }
    EXPECT_THROW((void)lgl_integration_matrix(1), manta::InputError);
}

TEST(Refine, ErrorEstimateIsSmallWhereResolvedAndLargeWhereNot) {
    const Brachistochrone b;
    const auto mb = make_model(b);
    const Solution sb = solve(*mb, Mesh::uniform(2, 12), b.guess());
    ASSERT_TRUE(sb.converged());
    const std::vector<double> eb = segment_errors(*mb, sb);
    ASSERT_EQ(eb.size(), 2U);
    for (const double e : eb) EXPECT_LT(e, 1e-7);
    // the bang-bang control on one 6-point segment: the switch is not resolved
    const DoubleIntegrator d;
    const auto md = make_model(d);
    const Solution sd = solve(*md, Mesh::uniform(1, 6), d.guess());
    ASSERT_TRUE(sd.converged());
    EXPECT_GT(segment_errors(*md, sd)[0], 1e-3);
    EXPECT_THROW((void)segment_errors(*md, sd, 0), manta::InputError);
}

/// A solution shell for refine_mesh: K segments over [0, 1], no controls (no jumps).
Solution shell(const Mesh& mesh) {
    Solution s;
    s.initial_time = 0.0;
    s.final_time = 1.0;
    s.breaks = mesh.breaks;
    s.segments.resize(mesh.nodes.size());
    return s;
}

TEST(Refine, PhRuleRaisesTheDegreeOrSplitsAndMapsThePhaseBreak) {
    Mesh mesh = Mesh::uniform(3, 5);
    mesh.free_breaks = true;
    mesh.phase_breaks = {2};
    RefinementOptions o;  // tolerance 1e-6, N_min 4, N_max 12
    std::vector<int> old;
    const Mesh r = refine_mesh(shell(mesh), mesh, {1e-1, 1e-3, 1e-8}, o, &old);
    // segment 0: P = ceil(log(1e5) / log 5) = 8, 5 + 8 > 12: B = max(ceil(13 / 4), 2) = 4 of 4;
    // segment 1: P = ceil(log(1e3) / log 5) = 5, 10 points; segment 2 below the tolerance: kept
    EXPECT_EQ(r.nodes, (std::vector<int>{4, 4, 4, 4, 10, 5}));
    EXPECT_EQ(old, (std::vector<int>{0, -1, -1, -1, 1, 2, 3}));
    EXPECT_NEAR(r.breaks[2], 2.0 / 12.0, 1e-15);
    EXPECT_TRUE(r.free_breaks);
    EXPECT_EQ(r.phase_breaks, (std::vector<int>{5}));  // the old break 2, only it free
    EXPECT_NEAR(r.breaks[5], 2.0 / 3.0, 1e-15);
    RefinementOptions bad;
    bad.max_nodes = 3;
    EXPECT_THROW((void)refine_mesh(shell(mesh), mesh, {1, 1, 1}, bad), manta::InputError);
    bad = {};
    bad.tolerance = 0.0;
    EXPECT_THROW(bad.validate(), manta::InputError);
}

TEST(Refine, NeverCoarserOverRandomMeshes) {
    std::mt19937 rng(20);
    std::uniform_int_distribution<int> nseg(1, 8), npts(2, 16);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (int trial = 0; trial < 500; ++trial) {
        Mesh mesh;
        const int K = nseg(rng);
        std::vector<double> cut{0.0, 1.0};
        while (static_cast<int>(cut.size()) < K + 1) cut.push_back(0.02 + 0.96 * uni(rng));
        std::sort(cut.begin(), cut.end());
        if (std::adjacent_find(cut.begin(), cut.end()) != cut.end()) continue;
        mesh.breaks = cut;
        std::vector<double> err;
        for (int k = 0; k < K; ++k) {
            mesh.nodes.push_back(npts(rng));
            err.push_back(std::pow(10.0, -10.0 * uni(rng)));
        }
        mesh.min_segment_fraction = 1e-4;
        RefinementOptions o;
        o.min_nodes = 2 + trial % 5;
        o.max_nodes = o.min_nodes + trial % 11;
        std::vector<int> old;
        const Mesh r = refine_mesh(shell(mesh), mesh, err, o, &old);
        // every new segment inside one old segment, at least as dense; old breaks kept in place
        int total_old = 0, total_new = 0;
        for (const int n : mesh.nodes) total_old += n;
        for (const int n : r.nodes) total_new += n;
        EXPECT_GE(total_new, total_old);
        for (int q = 0; q < r.n_segments(); ++q) {
            const double mid = 0.5 * (r.breaks[q] + r.breaks[q + 1]);
            int k = 0;
            while (k + 1 < K && mid >= mesh.breaks[k + 1]) ++k;
            EXPECT_GE(r.breaks[q], mesh.breaks[k] - 1e-15);
            EXPECT_LE(r.breaks[q + 1], mesh.breaks[k + 1] + 1e-15);
            EXPECT_GE(r.nodes[q] / (r.breaks[q + 1] - r.breaks[q]),
                      mesh.nodes[k] / (mesh.breaks[k + 1] - mesh.breaks[k]) * (1.0 - 1e-12))
                << "trial " << trial << " segment " << q;
            if (err[k] <= o.tolerance) {
                EXPECT_EQ(r.nodes[q], mesh.nodes[k]);
            }
        }
        for (std::size_t j = 0; j < old.size(); ++j) {
            if (old[j] >= 0) {
                EXPECT_EQ(r.breaks[j], mesh.breaks[old[j]]);
            }
        }
        EXPECT_FALSE(r.free_breaks);
    }
}

/// x'' = u, |u| <= 1, from rest at 0 through x = 1 (an interior event) back to rest at 0 in
/// least time: t_f = 4, the turn at 2 (Kirk, Optimal Control Theory, 1970, ch. 5, the
/// minimum-time double integrator per leg). The event is only right when called with the
/// junction index of the first mesh (1).
struct Turn {
    [[nodiscard]] ProblemInfo info() const {
        ProblemInfo p;
        p.name = "turn";
        p.states = {{"x", -10.0, 10.0, 1.0}, {"v", -10.0, 10.0, 1.0}};
        p.controls = {{"u", -1.0, 1.0, 1.0}};
        p.initial_states = {fixed(0.0), fixed(0.0)};
        p.final_states = {fixed(0.0), fixed(0.0)};
        p.final_time = {0.1, 20.0};
        p.interior_events = {{{"x at the turn", 1.0, 1.0, 1.0}, 1}};
        return p;
    }
    template <class T>
    void dynamics(std::span<const T> x, std::span<const T> u, std::span<const T> /*p*/,
                  const T& /*t*/, std::span<T> xdot) const {
        xdot[0] = x[1];
        xdot[1] = u[0];
    }
    template <class T>
    void interior(int junction, std::span<const T> x, std::span<const T> /*p*/, const T& /*t*/,
                  std::span<T> e) const {
        e[0] = junction == 1 ? x[0] : x[0] + 100.0;
    }
    template <class T>
    T mayer(std::span<const T> /*x0*/, std::span<const T> /*xf*/, std::span<const T> /*p*/,
            const T& /*t0*/, const T& tf) const {
        return tf;
    }
};

TEST(Refine, AdaptiveSolveKeepsTheInteriorEventAtItsJunction) {
    const auto m = make_model(Turn{});
    Mesh mesh = Mesh::uniform(2, 6);
    mesh.free_breaks = true;
    mesh.breaks = {0.0, 0.4, 1.0};
    Eigen::MatrixXd X(3, 2), U(3, 1);
    X << 0.0, 0.0, 1.0, 0.0, 0.0, 0.0;
    U.setZero();
    const Guess g = Guess::from_history({0.0, 2.5, 5.0}, X, U);
    const AdaptiveSolution r = solve_adaptive(*m, mesh, g);
    ASSERT_TRUE(r.solution.converged()) << r.status_text << "\n" << refinement_report(r);
    EXPECT_EQ(r.status, RefinementStatus::tolerance_met) << refinement_report(r);
    EXPECT_GT(r.passes.size(), 1U);
    EXPECT_GT(r.mesh.n_segments(), 2);
    ASSERT_EQ(r.interior_junctions.size(), 1U);
    const int j = r.interior_junctions[0];
    EXPECT_EQ(r.solution.info.interior_events[0].junction, j);
    EXPECT_NEAR(r.solution.final_time, 4.0, 1e-6);
    EXPECT_NEAR(r.solution.breaks[static_cast<std::size_t>(j)], 2.0, 1e-5);
    EXPECT_NEAR(r.solution.segments[static_cast<std::size_t>(j)].states(0, 0), 1.0, 1e-7);
}

/// A one-segment solution of N LGL points over [0, 10] s with control values u(t).
Solution one_segment(int n, const std::function<double(int, double)>& u) {
    Solution s;
    s.info.name = "synthetic";
    s.info.states = {{"x", -kInf, kInf, 1.0}};
    s.info.controls = {{"u", -1.0, 1.0, 1.0}};
    s.initial_time = 0.0;
    s.final_time = 10.0;
    s.breaks = {0.0, 10.0};
    SegmentSolution g;
    const LglRule r = lgl_rule(n);
    g.tau = r.points;
    g.weights = r.weights;
    g.bary = r.barycentric;
    g.time = 5.0 * (r.points.array() + 1.0);
    g.states = Eigen::MatrixXd::Zero(n, 1);
    g.controls.resize(n, 1);
    for (int i = 0; i < n; ++i) g.controls(i, 0) = u(i, g.time(i));
    s.segments.push_back(g);
    return s;
}

TEST(Refine, JumpRefinementNeverCoarsensTheSolutionsMesh) {
    // issue 20: no jump found gave one 12-point segment where the solution had 40
    const Solution s = one_segment(40, [](int, double t) { return 0.1 * std::sin(t); });
    const Mesh m = refine_at_control_jumps(s, 12);
    ASSERT_EQ(m.n_segments(), 1);
    EXPECT_GE(m.nodes[0], 40);
    // a jump at 3 s: two segments, each at least as dense as the 40 points on 10 s
    const Solution j = one_segment(40, [](int, double t) { return t < 3.0 ? -1.0 : 1.0; });
    const Mesh mj = refine_at_control_jumps(j, 12);
    ASSERT_EQ(mj.n_segments(), 2);
    EXPECT_NEAR(mj.breaks[1], 0.3, 0.02);
    for (int k = 0; k < 2; ++k) {
        EXPECT_GE(mj.nodes[k] / (mj.breaks[k + 1] - mj.breaks[k]), 40.0 * (1.0 - 1e-12));
        EXPECT_GE(mj.nodes[k], 12);
    }
    EXPECT_TRUE(mj.free_breaks);
}

TEST(Refine, JumpRefinementMergesAChatteringControl) {
    // issue 20: a control chattering between its bounds node by node (a singular arc) gave a
    // break at every node; now one break at each end of the run, apart by more than a spacing
    const Solution s = one_segment(40, [](int i, double) {
        return i < 15 ? 1.0 : (i > 29 ? -1.0 : (i % 2 == 0 ? 1.0 : -1.0));
    });
    const Mesh m = refine_at_control_jumps(s, 12);
    EXPECT_LE(m.n_segments(), 3);
    EXPECT_GE(m.n_segments(), 2);
    const SegmentSolution& g = s.segments[0];
    for (int k = 0; k < m.n_segments(); ++k) {
        EXPECT_GE((m.breaks[k + 1] - m.breaks[k]) * 10.0, g.time(20) - g.time(19));
        EXPECT_GE(m.nodes[k] / (m.breaks[k + 1] - m.breaks[k]), 40.0 * (1.0 - 1e-12));
    }
    // the breaks lie at the ends of the chattering run (nodes 14..30)
    EXPECT_GT(m.breaks[1] * 10.0, g.time(13));
    EXPECT_LT(m.breaks[m.n_segments() - 1] * 10.0, g.time(31));
}

}  // namespace
