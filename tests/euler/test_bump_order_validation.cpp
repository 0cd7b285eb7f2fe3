/// @file test_bump_order_validation.cpp
/// Order of accuracy of the steady Euler solver on a smooth subsonic flow: the channel with a
/// Gaussian bump of the 1st International Workshop on High-Order CFD Methods (Wang et al.,
/// "High-order CFD methods: current status and perspective", Int. J. Numer. Meth. Fluids 72,
/// 2013, 811-845, "inviscid flow through a channel with a smooth bump"), M 0.5, on three nested
/// meshes (`test::bump_channel` levels 0, 1, 2: 24 x 8, 48 x 16 and 96 x 32 cells; the
/// first-order check uses levels 1, 2, 3, the last 192 x 64 cells).
///
/// The exact solution is isentropic, so the entropy error e = (p / rho^gamma) / s_inf - 1 is
/// the discretisation error alone. Its volume-weighted L2 norm, ||e|| = sqrt(sum V_i e_i^2 /
/// sum V_i) over the median-dual cells, falls as h^p for a scheme of order p; the observed order
/// between two levels is log2(||e||_coarse / ||e||_fine). The channel is short (x in [-1.5,
/// 1.5]), so the characteristic far field at the ends is not an exact free stream, but it
/// creates no entropy: the measure stays valid. The flow is converged to 10 orders (or
/// round-off) with tight linear solves, far below the discretisation error.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>

#include "manta/euler/config.hpp"
#include "manta/euler/solver.hpp"
#include "manta/mesh/dual.hpp"
#include "test_meshes.hpp"

namespace {

using namespace manta;

/// Volume-weighted L2 norm of the entropy error of the converged bump-channel flow at `level`,
/// with the scheme of order `order` (unlimited reconstruction at order 2: the flow is smooth).
double entropy_error(int level, int order) {
    const mesh::Mesh m = test::bump_channel(level, 0.1);
    const mesh::DualMetrics dual = mesh::compute_dual_metrics(m);
    parallel::SerialHalo halo;
    parallel::SerialCommunicator comm;
    euler::CaseSetup setup;
    euler::CfdConfig c;
    c.markers = {{"lower", euler::BoundaryKind::wall}, {"upper", euler::BoundaryKind::wall}};
    setup.roles = euler::resolve_roles(m, c);
    setup.flow.mach = 0.5;
    setup.reference.area = 0.1;
    setup.spatial.order = order;
    setup.spatial.limiter = false;
    setup.solver.residual_drop = 10.0;
    setup.solver.cfl_initial = 10.0;
    setup.solver.cfl_growth = 2.0;
    setup.solver.cfl_max = 1e8;
    setup.solver.max_iterations = 400;
    setup.solver.coefficient_tolerance = 1e-9;
    setup.solver.linear = {40, 40, 1e-6};
    euler::SteadySolver solver({&m, &dual, m.n_nodes(), &halo}, comm, setup);
    const euler::SolveOutcome oc = solver.solve();
    EXPECT_TRUE(oc.converged) << "level " << level << ": " << oc.reason;
    EXPECT_TRUE(oc.residual_drop >= 10.0 || oc.reason.find("round-off") != std::string::npos)
        << "level " << level << ": " << oc.residual_drop << " orders, " << oc.reason;
    const double gamma = setup.flow.gamma;
    const double s_inf = 1.0 / gamma;  // solver units: rho_inf = 1, p_inf = 1 / gamma
    const std::vector<double> W = solver.primitive_state();
    double sum = 0, vol = 0;
    for (mesh::Index i = 0; i < m.n_nodes(); ++i) {
        const double rho = W[5 * static_cast<std::size_t>(i)];
        const double p = W[5 * static_cast<std::size_t>(i) + 4];
        const double e = p / std::pow(rho, gamma) / s_inf - 1.0;
        const double v = dual.dual_volumes[static_cast<std::size_t>(i)];
        sum += v * e * e;
        vol += v;
    }
    const double err = std::sqrt(sum / vol);
    std::printf(
        "bump channel M 0.5, order %d, level %d (%d nodes): ||s/s_inf - 1|| = %.4e, "
        "%d iterations, %.2f orders, %.1f s\n",
        order, level, static_cast<int>(m.n_nodes()), err, oc.iterations, oc.residual_drop,
        oc.wall_s);
    return err;
}

/// Errors on three consecutive levels from `first` and the observed orders between the
/// coarser pair (order[0]) and the finer pair (order[1]).
struct Study {
    std::array<double, 3> error{};
    std::array<double, 2> order{};
};

Study study(int order, int first) {
    Study s;
    for (int l = 0; l < 3; ++l)
        s.error[static_cast<std::size_t>(l)] = entropy_error(first + l, order);
    for (std::size_t k = 0; k < 2; ++k) s.order[k] = std::log2(s.error[k] / s.error[k + 1]);
    std::printf("order %d scheme: observed orders %.3f (levels %d-%d), %.3f (levels %d-%d)\n",
                order, s.order[0], first, first + 1, s.order[1], first + 1, first + 2);
    return s;
}

TEST(BumpOrderValidation, SecondOrderSchemeConvergesAtSecondOrder) {
    const Study s = study(2, 0);
    RecordProperty("order_01", std::to_string(s.order[0]));
    RecordProperty("order_12", std::to_string(s.order[1]));
    // Measured 1.23 (levels 0-1, pre-asymptotic) and 2.29 (levels 1-2).
    EXPECT_GT(s.order[1], 1.8);
    EXPECT_LT(s.order[1], 2.6);
}

TEST(BumpOrderValidation, FirstOrderSchemeConvergesAtFirstOrder) {
    const Study s = study(1, 1);
    RecordProperty("order_01", std::to_string(s.order[0]));
    RecordProperty("order_12", std::to_string(s.order[1]));
    // Pre-asymptotic on these meshes (measured 0.54 on levels 1-2, 0.81 on levels 2-3): the
    // observed order rises toward 1 and stays well below the second-order scheme's.
    EXPECT_GT(s.order[1], s.order[0]);
    EXPECT_GT(s.order[1], 0.7);
    EXPECT_LT(s.order[1], 1.3);
}

}  // namespace
