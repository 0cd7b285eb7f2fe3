/// @file test_pseudo_step.cpp
/// The implicit pseudo-time step shared by the steady and the dual-time solvers (solver.hpp,
/// `PseudoTimeStep`): the steady solve through it gives the values recorded from the solver
/// before the step was taken out of `SteadySolver::solve`, bit for bit; extra terms that are
/// all zero change nothing, bit for bit; with an extra diagonal d V and source d V U0 the
/// converged state solves R(U) + d V (U - U0) = 0; a stopping rule that stops leaves the state
/// and the iteration state as they were; grid fluxes and geometry updates reach both operators.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "manta/core/error.hpp"
#include "manta/euler/config.hpp"
#include "manta/euler/solver.hpp"
#include "manta/mesh/dual.hpp"
#include "test_meshes.hpp"

namespace {

using namespace manta;
using euler::BoundaryKind;

/// The subsonic bump channel, walls on the lower and upper boundaries, M 0.5, alpha 0.01 rad.
struct Channel {
    mesh::Mesh mesh = test::bump_channel(0, 0.1);
    mesh::DualMetrics dual = mesh::compute_dual_metrics(mesh);
    parallel::SerialHalo halo;
    parallel::SerialCommunicator comm;
    euler::CaseSetup setup;
    Channel() {
        euler::CfdConfig c;
        c.markers = {{"lower", BoundaryKind::wall}, {"upper", BoundaryKind::wall}};
        setup.roles = euler::resolve_roles(mesh, c);
        setup.flow.mach = 0.5;
        setup.flow.alpha = 0.01;
        setup.reference.area = 0.1;
    }
    [[nodiscard]] euler::Domain domain() const { return {&mesh, &dual, mesh.n_nodes(), &halo}; }
};

/// FNV-1a of the state's bytes.
std::uint64_t hash(const euler::NodeStates& U) {
    std::uint64_t h = 1469598103934665603ull;
    const auto* b = reinterpret_cast<const unsigned char*>(U.data());
    for (std::size_t k = 0; k < sizeof(double) * static_cast<std::size_t>(U.size()); ++k) {
        h ^= b[k];
        h *= 1099511628211ull;
    }
    return h;
}

struct Recorded {
    int iterations;
    double CL, CD, CMy, drop;
    std::uint64_t state;
};

TEST(PseudoTimeStep, SteadySolveGivesTheValuesRecordedBeforeTheStepWasTakenOut) {
    // Recorded with main at a34b63e (SteadySolver::solve with the step inside; GCC 12.2,
    // -O3, x86-64): the default Roe MUSCL scheme, JST with strong tangency, and four
    // first-order start iterations with block ILU(0). Iterations, coefficients and the whole
    // state must be the same bit for bit.
    const Recorded recorded[3] = {
        {55, -0x1.7d89720d0461ep-14, 0x1.2a10d5f10b6d2p-7, 0x1.dd32328081818p-12,
         0x1.801a8aee73298p+2, 0x17d6e123f01bb61aull},
        {74, -0x1.039c7a0a4865ap-14, 0x1.95a1088acb426p-8, 0x1.4485629e82607p-12,
         0x1.82c01fdb20c1p+2, 0x59777a69c0101f76ull},
        {143, -0x1.7d8b591a188d9p-14, 0x1.2a12527003f2p-7, 0x1.dd34764b1fe54p-12,
         0x1.8084cc8fa50a2p+2, 0xbc410a9ddb0dc737ull},
    };
    for (int variant = 0; variant < 3; ++variant) {
        Channel ch;
        if (variant == 1) ch.setup.spatial.flux.scheme = euler::FluxScheme::jst;
        if (variant == 2) {
            ch.setup.solver.first_order_iterations = 4;
            ch.setup.solver.preconditioner = euler::PreconditionerKind::ilu0;
        }
        euler::SteadySolver s(ch.domain(), ch.comm, ch.setup);
        const euler::SolveOutcome oc = s.solve();
        const Recorded& r = recorded[variant];
        EXPECT_TRUE(oc.converged) << variant << ": " << oc.reason;
        EXPECT_EQ(oc.backoffs, 0) << variant;
        EXPECT_EQ(oc.iterations, r.iterations) << variant;
        EXPECT_EQ(oc.forces.CL, r.CL) << variant;
        EXPECT_EQ(oc.forces.CD, r.CD) << variant;
        EXPECT_EQ(oc.forces.CMy, r.CMy) << variant;
        EXPECT_EQ(oc.residual_drop, r.drop) << variant;
        EXPECT_EQ(hash(s.state()), r.state) << variant;
    }
}

/// Run the step from the free stream until `rule` stops it; returns the stop decision.
euler::StopDecision run(euler::PseudoTimeStep& step, euler::NodeStates& U,
                        const euler::StopRule& rule, const euler::StepTerms& terms,
                        int* iterations = nullptr) {
    const euler::CaseSetup& s = step.setup();
    U.resize(5, step.domain().mesh->n_nodes());
    const euler::Vec5 U_inf = euler::conservative(step.free_stream_primitive(), s.flow.gamma);
    for (Eigen::Index i = 0; i < U.cols(); ++i) U.col(i) = U_inf;
    step.set_backoff_state(U);
    euler::IterationState it = step.initial_state();
    step.begin(it);
    while (true) {
        const euler::StepOutcome o = step.step(U, it, rule, terms);
        if (o.result == euler::StepResult::stopped) {
            if (iterations) *iterations = it.iteration;
            return o.decision;
        }
    }
}

TEST(PseudoTimeStep, ZeroExtraTermsChangeNothingBitForBit) {
    // The hooks' code path (diagonal added to the residual and to the matrix, source
    // subtracted) with zeros gives the steady solve exactly.
    Channel ch;
    euler::SteadySolver steady(ch.domain(), ch.comm, ch.setup);
    const euler::SolveOutcome oc = steady.solve();
    ASSERT_TRUE(oc.converged) << oc.reason;

    euler::PseudoTimeStep step(ch.domain(), ch.comm, ch.setup);
    const std::vector<double> zeros(static_cast<std::size_t>(ch.mesh.n_nodes()), 0.0);
    const euler::NodeStates S = euler::NodeStates::Zero(5, ch.mesh.n_nodes());
    const euler::SolverSettings& set = ch.setup.solver;
    euler::NodeStates U;
    int iterations = 0;
    const euler::StopDecision d = run(
        step, U, [&](const euler::StepStatus& st) { return euler::steady_stop(set, st); },
        {zeros, &S}, &iterations);
    EXPECT_TRUE(d.converged) << d.reason;
    EXPECT_EQ(d.reason, oc.reason);
    EXPECT_EQ(iterations, oc.iterations);
    EXPECT_EQ(step.forces(U).CL, oc.forces.CL);
    EXPECT_TRUE((U.array() == steady.state().array()).all()) << "zero terms changed the state";
}

TEST(PseudoTimeStep, ExtraDiagonalAndSourceSolveTheModifiedSystem) {
    // With D = d V and S = d V U0 the step drives R(U) + d V (U - U0) to zero: the implicit
    // equation of one backward-Euler physical step of length 1/d from U0. U0 is a uniform flow
    // at M 0.4; d = 2 (the flow crosses the 3-unit channel in 6 time units, so neither term is
    // small). Second order, no limiter (a smooth residual to converge to round-off), weak walls.
    Channel ch;
    ch.setup.spatial.limiter = false;
    const double d = 2.0;
    const euler::Vec5 U0 =
        euler::conservative(euler::free_stream(0.4, 0.0, 0.0, ch.setup.flow.gamma), 1.4);
    const auto n = static_cast<std::size_t>(ch.mesh.n_nodes());
    std::vector<double> D(n);
    euler::NodeStates S(5, ch.mesh.n_nodes());
    for (std::size_t i = 0; i < n; ++i) {
        D[i] = d * ch.dual.dual_volumes[i];
        S.col(static_cast<Eigen::Index>(i)) = D[i] * U0;
    }
    euler::PseudoTimeStep step(ch.domain(), ch.comm, ch.setup);
    euler::NodeStates U;
    int calls = 0;
    const euler::StopDecision dec = run(step, U,
                                        [&](const euler::StepStatus& st) {
                                            ++calls;
                                            euler::StopDecision r;
                                            if (st.drop >= 10.0 || st.at_roundoff)
                                                r = {true, true, "converged"};
                                            if (st.iteration >= 200)
                                                r = {true, false, "iteration limit"};
                                            return r;
                                        },
                                        {D, &S});
    ASSERT_TRUE(dec.converged) << dec.reason;
    EXPECT_GT(calls, 1);

    // The residual of a fresh operator at the converged state, plus the extra terms.
    const euler::Vec5 W_inf = step.free_stream_primitive();
    euler::SpatialOperator op(ch.domain(), ch.setup.roles, W_inf, 1.4, ch.setup.spatial);
    euler::NodeStates R;
    op.residual(U, R);
    double r_norm = 0, term_norm = 0, total = 0, away0 = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const auto c = static_cast<Eigen::Index>(i);
        const euler::Vec5 t = D[i] * (U.col(c) - U0);
        r_norm = std::max(r_norm, R.col(c).cwiseAbs().maxCoeff());
        term_norm = std::max(term_norm, t.cwiseAbs().maxCoeff());
        total = std::max(total, (R.col(c) + t).cwiseAbs().maxCoeff());
        away0 = std::max(away0, (U.col(c) - U0).cwiseAbs().maxCoeff());
    }
    std::printf("max |R| %.3e, max |dV(U - U0)| %.3e, max |R + dV(U - U0)| %.3e\n", r_norm,
                term_norm, total);
    // Both terms matter (the state is neither U0 nor the steady solution) and cancel.
    EXPECT_GT(away0, 1e-3);
    EXPECT_GT(r_norm, 1e-4);
    EXPECT_GT(term_norm, 1e-4);
    EXPECT_LT(total, 1e-7 * term_norm);  // 10 orders of residual drop
    // Without the terms the same iteration goes to the steady solution, not to this state.
    euler::PseudoTimeStep plain(ch.domain(), ch.comm, ch.setup);
    euler::NodeStates Us;
    const euler::SolverSettings& set = ch.setup.solver;
    (void)run(plain, Us, [&](const euler::StepStatus& st) { return euler::steady_stop(set, st); },
              {});
    EXPECT_GT((Us - U).cwiseAbs().maxCoeff(), 1e-3);
}

TEST(PseudoTimeStep, AReusedMatrixConvergesToTheSameState) {
    // The system of ExtraDiagonalAndSourceSolveTheModifiedSystem (D = d V, S = d V U0, d = 2)
    // solved with the matrix and preconditioner assembled at every third step only (a chord
    // iteration, the dual-time solver's jacobian_interval 3): the same state to the tolerance of
    // 10 orders of residual drop, while the iteration without the terms' reuse flag is the
    // plain one bit for bit. `log10_density_residual` is the residual the next step records.
    Channel ch;
    ch.setup.spatial.limiter = false;
    const double d = 2.0;
    const euler::Vec5 U0 =
        euler::conservative(euler::free_stream(0.4, 0.0, 0.0, ch.setup.flow.gamma), 1.4);
    const auto n = static_cast<std::size_t>(ch.mesh.n_nodes());
    std::vector<double> D(n);
    euler::NodeStates S(5, ch.mesh.n_nodes());
    for (std::size_t i = 0; i < n; ++i) {
        D[i] = d * ch.dual.dual_volumes[i];
        S.col(static_cast<Eigen::Index>(i)) = D[i] * U0;
    }
    const auto solve = [&](int interval, int& iterations, bool& residual_matches) {
        euler::PseudoTimeStep step(ch.domain(), ch.comm, ch.setup);
        euler::NodeStates U(5, ch.mesh.n_nodes());
        const euler::Vec5 U_inf = euler::conservative(step.free_stream_primitive(), 1.4);
        for (Eigen::Index i = 0; i < U.cols(); ++i) U.col(i) = U_inf;
        step.set_backoff_state(U);
        euler::IterationState it = step.initial_state();
        step.begin(it);
        const euler::StopRule rule = [](const euler::StepStatus& st) {
            euler::StopDecision r;
            if (st.drop >= 10.0 || st.at_roundoff) r = {true, true, "converged"};
            if (st.iteration >= 300) r = {true, false, "iteration limit"};
            return r;
        };
        residual_matches = true;
        while (true) {
            euler::StepTerms terms{D, &S};
            terms.reuse_matrix = interval > 1 && it.iteration % interval != 0;
            const double before = step.log10_density_residual(U, terms);
            const euler::StepOutcome o = step.step(U, it, rule, terms);
            if (o.result != euler::StepResult::backed_off)
                residual_matches = residual_matches && o.record.log10_residual[0] == before;
            if (o.result == euler::StepResult::stopped) {
                EXPECT_TRUE(o.decision.converged) << interval << ": " << o.decision.reason;
                iterations = it.iteration;
                return U;
            }
        }
    };
    int it1 = 0, it3 = 0;
    bool m1 = false, m3 = false;
    const euler::NodeStates U1 = solve(1, it1, m1), U3 = solve(3, it3, m3);
    EXPECT_TRUE(m1);
    EXPECT_TRUE(m3);
    const double diff = (U3 - U1).cwiseAbs().maxCoeff();
    std::printf("matrix every step: %d iterations; every third step: %d; max |dU| %.2e\n", it1, it3,
                diff);
    EXPECT_LT(diff, 1e-8);
    // The plain iteration is the one of ExtraDiagonalAndSourceSolveTheModifiedSystem.
    euler::PseudoTimeStep plain(ch.domain(), ch.comm, ch.setup);
    euler::NodeStates Up;
    int itp = 0;
    (void)run(
        plain, Up,
        [](const euler::StepStatus& st) {
            euler::StopDecision r;
            if (st.drop >= 10.0 || st.at_roundoff) r = {true, true, "converged"};
            if (st.iteration >= 300) r = {true, false, "iteration limit"};
            return r;
        },
        {D, &S}, &itp);
    EXPECT_EQ(itp, it1);
    EXPECT_EQ(hash(Up), hash(U1));
}

TEST(PseudoTimeStep, AStopLeavesStateAndIterationStateUnchanged) {
    Channel ch;
    euler::PseudoTimeStep step(ch.domain(), ch.comm, ch.setup);
    euler::NodeStates U(5, ch.mesh.n_nodes());
    const euler::Vec5 U_inf = euler::conservative(step.free_stream_primitive(), 1.4);
    for (Eigen::Index i = 0; i < U.cols(); ++i) U.col(i) = U_inf;
    euler::IterationState it = step.initial_state();
    step.begin(it);
    const auto go = [](const euler::StepStatus&) { return euler::StopDecision{}; };
    for (int k = 0; k < 3; ++k) ASSERT_EQ(step.step(U, it, go).result, euler::StepResult::updated);
    EXPECT_EQ(it.iteration, 3);
    const euler::NodeStates before = U;
    const euler::IterationState it_before = it;
    const euler::StepOutcome o = step.step(U, it, [](const euler::StepStatus& st) {
        return euler::StopDecision{st.iteration == 3, false, "asked"};
    });
    EXPECT_EQ(o.result, euler::StepResult::stopped);
    EXPECT_EQ(o.decision.reason, "asked");
    EXPECT_EQ(o.status.iteration, 3);
    EXPECT_TRUE((U.array() == before.array()).all());
    EXPECT_EQ(it.iteration, it_before.iteration);
    EXPECT_EQ(it.cfl, it_before.cfl);
    EXPECT_EQ(it.window, it_before.window);
    // Terms of the wrong size are an InputError naming what was expected.
    const std::vector<double> short_d(3, 0.0);
    try {
        (void)step.step(U, it, go, {short_d, nullptr});
        ADD_FAILURE() << "no error for a short diagonal";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("one per node"), std::string::npos) << e.what();
    }
}

TEST(PseudoTimeStep, RecordsTheLargestDensityResidualAndWhereItIs) {
    // The converged channel flow with the state of one interior node raised by 30 %: the
    // record's largest |R_rho| is the residual's own largest, at that node's coordinates, and
    // that node is the perturbed one or one of its edge neighbours.
    Channel ch;
    ch.setup.spatial.limiter = false;
    ch.setup.solver.residual_drop = 8;
    euler::SteadySolver steady(ch.domain(), ch.comm, ch.setup);
    ASSERT_TRUE(steady.solve().converged);
    euler::NodeStates U = steady.state();
    euler::PseudoTimeStep step(ch.domain(), ch.comm, ch.setup);
    const mesh::Index k = ch.mesh.n_nodes() / 2;
    U.col(k) *= 1.3;
    euler::IterationState it = step.initial_state();
    step.begin(it);
    const auto go = [](const euler::StepStatus&) { return euler::StopDecision{}; };
    const euler::StepOutcome o = step.step(U, it, go);
    ASSERT_EQ(o.result, euler::StepResult::updated);
    const euler::NodeStates& R = step.residual();
    mesh::Index at = 0;
    for (mesh::Index i = 0; i < ch.mesh.n_nodes(); ++i)
        if (std::abs(R(0, i)) > std::abs(R(0, at))) at = i;
    EXPECT_EQ(o.record.max_residual, std::abs(R(0, at)));
    for (int c = 0; c < 3; ++c)
        EXPECT_EQ(o.record.max_residual_at[static_cast<std::size_t>(c)], ch.mesh.node(at)[c]);
    bool near = at == k;
    for (const auto& e : ch.dual.edges)
        near = near || (e[0] == k && e[1] == at) || (e[1] == k && e[0] == at);
    EXPECT_TRUE(near) << "largest residual at node " << at << ", perturbed node " << k;
    EXPECT_GT(o.record.max_residual, 0.0);
}

TEST(PseudoTimeStep, DivergenceNamesWhereTheLargestResidualIs) {
    // A NaN state at one node, no back-off allowed: the ConvergenceError says where the largest
    // (finite) density residual was, in the mesh's coordinates, on one line.
    Channel ch;
    ch.setup.solver.max_backoffs = 0;
    euler::PseudoTimeStep step(ch.domain(), ch.comm, ch.setup);
    euler::NodeStates U(5, ch.mesh.n_nodes());
    const euler::Vec5 U_inf = euler::conservative(step.free_stream_primitive(), 1.4);
    for (Eigen::Index i = 0; i < U.cols(); ++i) U.col(i) = U_inf;
    U(0, ch.mesh.n_nodes() / 2) = std::numeric_limits<double>::quiet_NaN();
    euler::IterationState it = step.initial_state();
    step.begin(it);
    try {
        (void)step.step(U, it, [](const euler::StepStatus&) { return euler::StopDecision{}; });
        ADD_FAILURE() << "a NaN state did not stop the iteration";
    } catch (const ConvergenceError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("NaN in the residual"), std::string::npos) << m;
        EXPECT_NE(m.find("the largest density residual at ("), std::string::npos) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
}

/// Take `n` steps from the free stream with no stopping rule; returns the state.
euler::NodeStates steps(euler::PseudoTimeStep& step, int n) {
    euler::NodeStates U(5, step.domain().mesh->n_nodes());
    const euler::Vec5 U_inf = euler::conservative(step.free_stream_primitive(), 1.4);
    for (Eigen::Index i = 0; i < U.cols(); ++i) U.col(i) = U_inf;
    euler::IterationState it = step.initial_state();
    step.begin(it);
    for (int k = 0; k < n; ++k) EXPECT_EQ(step.step(U, it, {}).result, euler::StepResult::updated);
    return U;
}

TEST(PseudoTimeStep, GridFluxesAndGeometryReachBothOperators) {
    // With first-order start iterations the step holds two operators; the moving-mesh hooks
    // must reach both. Zero grid fluxes change nothing bit for bit; non-zero ones change the
    // first (first-order) step and the second-order steps.
    Channel ch;
    ch.setup.solver.first_order_iterations = 1;
    euler::PseudoTimeStep plain(ch.domain(), ch.comm, ch.setup);
    const euler::NodeStates U1 = steps(plain, 1);
    euler::PseudoTimeStep plain3(ch.domain(), ch.comm, ch.setup);
    const euler::NodeStates U3 = steps(plain3, 3);
    mesh::DualFaceValues zero;
    zero.resize_for(ch.dual);
    euler::PseudoTimeStep z(ch.domain(), ch.comm, ch.setup);
    z.set_grid_fluxes(&zero);
    EXPECT_TRUE((steps(z, 3).array() == U3.array()).all());
    mesh::DualFaceValues g = zero;
    for (double& v : g.edges) v = 1e-4;
    euler::PseudoTimeStep a(ch.domain(), ch.comm, ch.setup);
    a.set_grid_fluxes(&g);
    EXPECT_GT((steps(a, 1) - U1).cwiseAbs().maxCoeff(), 1e-9);  // the first-order operator
    euler::CaseSetup second = ch.setup;
    second.solver.first_order_iterations = 0;
    euler::PseudoTimeStep b0(ch.domain(), ch.comm, second), b(ch.domain(), ch.comm, second);
    b.set_grid_fluxes(&g);
    EXPECT_GT((steps(b, 1) - steps(b0, 1)).cwiseAbs().maxCoeff(), 1e-9);  // the second-order
    b.set_grid_fluxes(nullptr);
    EXPECT_TRUE((steps(b, 3).array() == steps(b0, 3).array()).all());

    // Geometry: a step set up on the channel, the mesh then stretched by 1.5 along x and the
    // metrics and the step's geometry updated, steps as one set up on the stretched mesh (one
    // not updated does not: its least-squares matrices are the old mesh's).
    Channel big;
    euler::PseudoTimeStep moved(big.domain(), big.comm, second);
    euler::PseudoTimeStep stale(big.domain(), big.comm, second);
    std::vector<double> x(big.mesh.coordinates().begin(), big.mesh.coordinates().end());
    for (std::size_t k = 0; k < x.size(); k += 3) x[k] *= 1.5;
    big.mesh.set_coordinates(x);
    mesh::update_dual_metrics(big.mesh, big.dual);
    moved.update_geometry();
    euler::PseudoTimeStep fresh(big.domain(), big.comm, second);
    const euler::NodeStates U_fresh = steps(fresh, 3);
    const double d = (steps(moved, 3) - U_fresh).cwiseAbs().maxCoeff();
    const double d_stale = (steps(stale, 3) - U_fresh).cwiseAbs().maxCoeff();
    std::printf("stretched mesh, against a step set up on it: max |dU| %.2e updated, %.2e not\n", d,
                d_stale);
    EXPECT_GT(d_stale, 1e-9);
    EXPECT_LT(d, 1e-12);
}

}  // namespace
