/// @file test_unsteady.cpp
/// Dual time stepping on a fixed mesh (unsteady.hpp): a uniform flow stays uniform to round-off;
/// a converged steady solution stays steady; an entropy wave convected through the channel
/// converges in time at first order with backward Euler and at second order with BDF2
/// (self-convergence against a solution at an eighth of the step, the spatial discretisation
/// the same for all); bad settings are one-line errors.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "manta/core/error.hpp"
#include "manta/euler/config.hpp"
#include "manta/euler/unsteady.hpp"
#include "manta/mesh/dual.hpp"
#include "test_meshes.hpp"

namespace {

using namespace manta;
using euler::BoundaryKind;

/// The subsonic bump channel at M 0.5, walls on the lower and upper boundaries.
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
        setup.reference.area = 0.1;
    }
    [[nodiscard]] euler::Domain domain() const { return {&mesh, &dual, mesh.n_nodes(), &halo}; }
};

TEST(UnsteadySolver, UniformFlowStaysUniform) {
    // Far field on every marker: the free stream is an exact solution of the discrete equations.
    Channel ch;
    for (auto& r : ch.setup.roles)
        if (r == BoundaryKind::wall) r = BoundaryKind::farfield;  // symmetry planes stay
    euler::UnsteadySettings t;
    t.dt = 0.05;
    euler::UnsteadySolver s(ch.domain(), ch.comm, ch.setup, t);
    const euler::NodeStates U0 = s.state();
    for (int n = 0; n < 5; ++n) {
        const euler::TimeStepRecord r = s.advance();
        EXPECT_TRUE(r.converged) << n;
        EXPECT_EQ(r.step, n + 1);
    }
    EXPECT_NEAR(s.time(), 0.25, 1e-15);
    const double dev = (s.state() - U0).cwiseAbs().maxCoeff();
    std::printf("uniform flow after 5 BDF2 steps: max |U - U_inf| %.2e\n", dev);
    EXPECT_LT(dev, 1e-13);
}

TEST(UnsteadySolver, SteadySolutionStaysSteady) {
    Channel ch;
    ch.setup.spatial.limiter = false;
    ch.setup.solver.residual_drop = 10;
    euler::SteadySolver steady(ch.domain(), ch.comm, ch.setup);
    const euler::SolveOutcome oc = steady.solve();
    ASSERT_TRUE(oc.converged) << oc.reason;
    euler::UnsteadySettings t;
    t.dt = 0.1;
    euler::UnsteadySolver s(ch.domain(), ch.comm, ch.setup, t);
    s.set_state(steady.state());
    for (int n = 0; n < 4; ++n) (void)s.advance();
    const double dev = (s.state() - steady.state()).cwiseAbs().maxCoeff();
    std::printf("steady solution after 4 BDF2 steps: max |U - U_steady| %.2e, CD %.9f -> %.9f\n",
                dev, oc.forces.CD, s.forces().CD);
    EXPECT_LT(dev, 1e-8);
    EXPECT_NEAR(s.forces().CL, oc.forces.CL, 1e-9);
    EXPECT_NEAR(s.forces().CD, oc.forces.CD, 1e-9);
}

/// The converged steady channel (second order, no limiter: a smooth residual, no limiter
/// switching in time).
struct SteadyChannel : Channel {
    euler::NodeStates U;
    SteadyChannel() {
        setup.spatial.limiter = false;
        setup.solver.residual_drop = 10;
        euler::SteadySolver s(domain(), comm, setup);
        const euler::SolveOutcome oc = s.solve();
        EXPECT_TRUE(oc.converged) << oc.reason;
        U = s.state();
    }
};

/// The steady channel flow with the entropy wave's density bump (amplitude 10 %, radius 0.2,
/// centred at x = -0.5, y = 0.4, at the local pressure and velocity).
euler::NodeStates with_density_bump(const SteadyChannel& ch) {
    euler::NodeStates U0 = ch.U;
    for (Eigen::Index i = 0; i < U0.cols(); ++i) {
        const Eigen::Vector3d x = ch.mesh.node(static_cast<mesh::Index>(i));
        const double r2 = (x.x() + 0.5) * (x.x() + 0.5) + (x.y() - 0.4) * (x.y() - 0.4);
        euler::Vec5 W = euler::primitive(U0.col(i), 1.4);
        W[0] *= 1.0 + 0.1 * std::exp(-r2 / 0.04);
        U0.col(i) = euler::conservative(W, 1.4);
    }
    return U0;
}

/// An entropy wave: the steady channel flow with a Gaussian density bump (amplitude 10 %,
/// radius 0.2, at the local pressure and velocity) centred at x = -0.5, y = 0.4, advanced to
/// t = 0.2 (the bump moves by about 0.1) with step dt; returns the state. `base`: settings of
/// the inner iterations besides dt, order, inner_drop and max_inner; `inner`: the inner
/// iterations of all steps.
euler::NodeStates entropy_wave(const SteadyChannel& ch, int order, double dt,
                               const euler::UnsteadySettings& base = {}, int* inner = nullptr) {
    euler::UnsteadySettings t = base;
    t.dt = dt;
    t.order = order;
    t.inner_drop = 8;  // inner iterations converged far below the time error
    t.max_inner = 100;
    euler::UnsteadySolver s(ch.domain(), ch.comm, ch.setup, t);
    s.set_state(with_density_bump(ch));
    const int steps = static_cast<int>(std::lround(0.2 / dt));
    if (inner) *inner = 0;
    for (int n = 0; n < steps; ++n) {
        const euler::TimeStepRecord r = s.advance();
        if (inner) *inner += r.inner_iterations;
        EXPECT_TRUE(r.converged) << "order " << order << " dt " << dt << " step " << r.step
                                 << " inner " << r.inner_iterations << " drop " << r.residual_drop;
    }
    EXPECT_NEAR(s.time(), 0.2, 1e-12);
    return s.state();
}

TEST(UnsteadySolver, BackwardDifferencesConvergeAtTheirOrder) {
    const SteadyChannel ch;
    for (const int order : {1, 2}) {
        const double dt0 = 0.05;
        const euler::NodeStates ref = entropy_wave(ch, order, dt0 / 8);
        double e[3];
        for (int k = 0; k < 3; ++k)
            e[k] = (entropy_wave(ch, order, dt0 / (1 << k)) - ref).cwiseAbs().maxCoeff();
        // With the reference at dt0/8, e(dt) ~ C (dt^p - (dt0/8)^p): the ratios of the
        // differences of successive errors are free of the reference's own error.
        const double p1 = std::log2(e[0] / e[1]), p2 = std::log2(e[1] / e[2]);
        const double p = std::log2((e[0] - e[1]) / (e[1] - e[2]));
        std::printf(
            "BDF%d: max error %.3e %.3e %.3e at dt %.4g, /2, /4; orders %.2f %.2f, "
            "from differences %.2f\n",
            order, e[0], e[1], e[2], dt0, p1, p2, p);
        EXPECT_NEAR(p, order, 0.2) << "BDF" << order;
        EXPECT_GT(e[0], e[1]);
        EXPECT_GT(e[1], e[2]);
    }
}

TEST(UnsteadySolver, ExtrapolatedStartAndReusedJacobianKeepTheSolution) {
    // The entropy wave with BDF2 at dt = 0.025 (time error 3.5e-4 against dt/8, above), inner
    // iterations to 8 orders: started from the extrapolation 2 U^n - U^(n-1), with the Jacobian
    // assembled every third inner iteration, and both (the defaults), the states at t = 0.2 are
    // those of the plain iteration (from U^n, a Jacobian every inner iteration) to far below the
    // time error; the extrapolated start needs fewer inner iterations (the drop counts from
    // R*(U^n) in all four runs).
    const SteadyChannel ch;
    int n_plain = 0, n_extra = 0, n_reuse = 0, n_both = 0;
    euler::UnsteadySettings p;
    p.extrapolate = false;
    p.jacobian_interval = 1;
    const euler::NodeStates plain = entropy_wave(ch, 2, 0.025, p, &n_plain);
    euler::UnsteadySettings e = p;
    e.extrapolate = true;
    const euler::NodeStates extra = entropy_wave(ch, 2, 0.025, e, &n_extra);
    euler::UnsteadySettings j = p;
    j.jacobian_interval = 3;
    const euler::NodeStates reuse = entropy_wave(ch, 2, 0.025, j, &n_reuse);
    const euler::NodeStates both = entropy_wave(ch, 2, 0.025, {}, &n_both);  // the defaults
    const double d_extra = (extra - plain).cwiseAbs().maxCoeff();
    const double d_reuse = (reuse - plain).cwiseAbs().maxCoeff();
    const double d_both = (both - plain).cwiseAbs().maxCoeff();
    std::printf(
        "entropy wave, 8 BDF2 steps: inner iterations %d (U^n), %d (extrapolated), %d (Jacobian "
        "every 3rd), %d (both); max |dU| %.2e, %.2e, %.2e\n",
        n_plain, n_extra, n_reuse, n_both, d_extra, d_reuse, d_both);
    EXPECT_LT(d_extra, 1e-8);
    EXPECT_LT(d_reuse, 1e-8);
    EXPECT_LT(d_both, 1e-8);
    EXPECT_LT(n_extra, n_plain);
    EXPECT_GT(d_extra, 0.0);  // a different iteration, not the same one
}

/// Largest change of the limiter between two sets of its values.
double limiter_change(const std::vector<double>& a, const std::vector<double>& b) {
    double m = 0.0;
    for (std::size_t k = 0; k < a.size(); ++k) m = std::max(m, std::abs(a[k] - b[k]));
    return m;
}

TEST(UnsteadySolver, LimiterFrozenAfterTheSetInnerIterationsOfEachStep) {
    // The entropy wave on the limited channel: with freeze_limiter_inner = 3 the limiter of
    // every inner iteration after the third of a step is the third's, and the next step
    // evaluates it afresh (it differs from the last step's frozen one); without the setting it
    // changes from one inner iteration to the next.
    SteadyChannel ch;
    ch.setup.spatial.limiter = true;
    for (const int freeze : {0, 3}) {
        euler::UnsteadySettings t;
        t.dt = 0.025;
        t.inner_drop = 8;
        t.max_inner = 30;
        t.freeze_limiter_inner = freeze;
        euler::UnsteadySolver s(ch.domain(), ch.comm, ch.setup, t);
        s.set_state(with_density_bump(ch));
        std::vector<double> at_freeze, previous_step;
        for (int n = 0; n < 3; ++n) {
            std::vector<double> last;
            double after_freeze = 0.0, before_freeze = 0.0;
            int count = 0;
            const euler::TimeStepRecord r = s.advance([&](const euler::IterationRecord&) {
                ++count;
                std::vector<double> phi = s.limiter_values();
                EXPECT_FALSE(phi.empty());
                if (!last.empty() && (freeze == 0 || count <= freeze))
                    before_freeze = std::max(before_freeze, limiter_change(phi, last));
                if (freeze > 0 && count == freeze) at_freeze = phi;
                if (freeze > 0 && count > freeze)
                    after_freeze = std::max(after_freeze, limiter_change(phi, at_freeze));
                last = std::move(phi);
                return true;
            });
            ASSERT_GT(r.inner_iterations, 4) << "step " << n + 1;
            EXPECT_GT(before_freeze, 0.0) << "freeze " << freeze << " step " << n + 1;
            EXPECT_EQ(after_freeze, 0.0) << "step " << n + 1;
            if (freeze > 0) {
                if (!previous_step.empty()) {
                    EXPECT_GT(limiter_change(at_freeze, previous_step), 0.0) << "step " << n + 1;
                }
                previous_step = at_freeze;
            }
        }
    }
}

TEST(UnsteadySolver, BadSettingsAreOneLineErrors) {
    Channel ch;
    euler::UnsteadySettings t;
    for (const auto& [bad, key] : {std::pair{[] {
                                                 euler::UnsteadySettings s;
                                                 s.dt = 0;
                                                 return s;
                                             }(),
                                             "dt"},
                                   std::pair{[] {
                                                 euler::UnsteadySettings s;
                                                 s.dt = 1;
                                                 s.order = 3;
                                                 return s;
                                             }(),
                                             "order"},
                                   std::pair{[] {
                                                 euler::UnsteadySettings s;
                                                 s.dt = 1;
                                                 s.jacobian_interval = 0;
                                                 return s;
                                             }(),
                                             "jacobian_interval"},
                                   std::pair{[] {
                                                 euler::UnsteadySettings s;
                                                 s.dt = 1;
                                                 s.freeze_limiter_inner = -1;
                                                 return s;
                                             }(),
                                             "freeze_limiter_inner"}}) {
        try {
            euler::UnsteadySolver s(ch.domain(), ch.comm, ch.setup, bad);
            ADD_FAILURE() << key;
        } catch (const InputError& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find(key), std::string::npos) << m;
            EXPECT_EQ(m.find('\n'), std::string::npos) << m;
        }
    }
    t.dt = 0.1;
    euler::UnsteadySolver s(ch.domain(), ch.comm, ch.setup, t);
    euler::NodeStates U = s.state();
    U(4, 7) = -1.0;
    try {
        s.set_state(U);
        ADD_FAILURE() << "negative energy accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("node 7"), std::string::npos) << e.what();
    }
}

}  // namespace
