/// @file test_source.cpp
/// The Euler solver behind aero::AeroSource (source.hpp): a warm-started evaluation gives the
/// cold-started result in fewer iterations, body and wind axes are consistent, and queries the
/// channel cannot answer are input errors: a pitch rate about y turns the slab through its
/// symmetry planes z = 0 and z = 0.1, and the channel has no control surfaces
/// (test_source_campaign.cpp and test_wing_rates_slow.cpp solve rates and deflections).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>

#include "manta/core/error.hpp"
#include "manta/euler/config.hpp"
#include "manta/euler/source.hpp"
#include "test_meshes.hpp"

namespace {

using namespace manta;

euler::CaseSetup channel_setup(const mesh::Mesh& m) {
    euler::CfdConfig c;
    c.markers = {{"lower", euler::BoundaryKind::wall}, {"upper", euler::BoundaryKind::wall}};
    euler::CaseSetup s;
    s.roles = euler::resolve_roles(m, c);
    s.reference.area = 0.1;
    return s;
}

TEST(EulerSource, WarmStartGivesTheColdResultInFewerIterations) {
    const mesh::Mesh m = test::bump_channel(0, 0.1);
    euler::EulerSource warm(m, channel_setup(m), "bump level 0");
    euler::EulerSource cold(m, channel_setup(m), "bump level 0");
    EXPECT_EQ(warm.name(), "euler");
    EXPECT_EQ(warm.fingerprint(), cold.fingerprint());
    aero::AeroQuery<double> q;
    q.mach = 0.5;
    q.alpha = 0.0;
    (void)warm.evaluate(q, {});
    q.alpha = 0.5 * M_PI / 180.0;
    const aero::SourceResult a = warm.evaluate(q, {});
    const aero::SourceResult b = cold.evaluate(q, {});
    const euler::EulerSourceStats ws = warm.stats(), cs = cold.stats();
    EXPECT_EQ(ws.evaluations, 2);
    EXPECT_EQ(ws.warm_starts, 1);
    EXPECT_EQ(cs.warm_starts, 0);
    // The second warm evaluation's iterations: total minus the first (cold) one at alpha 0.
    euler::EulerSource first(m, channel_setup(m), "bump level 0");
    q.alpha = 0.0;
    (void)first.evaluate(q, {});
    const int second_warm = ws.iterations - first.stats().iterations;
    std::printf("iterations: cold %d, warm %d\n", cs.iterations, second_warm);
    EXPECT_LT(second_warm, cs.iterations);
    EXPECT_NEAR(a.wind.CL, b.wind.CL, 1e-4);
    EXPECT_NEAR(a.wind.CD, b.wind.CD, 1e-4);
    EXPECT_NEAR(a.body.Cm, b.body.Cm, 1e-4);
    // Body and wind axes: CL = -CZ cos a + CX sin a at zero sideslip.
    const double al = 0.5 * M_PI / 180.0;
    EXPECT_NEAR(a.wind.CL, -a.body.CZ * std::cos(al) + a.body.CX * std::sin(al), 1e-12);
}

// A warm start that fails is solved again from the free stream. The warm start's residual target
// counts from the peak of the run that began the chain, so a start from M 0.1 (small residuals)
// must reach a lower residual at M 0.6 than a cold run there: with the iteration limit of the
// cold runs, the warm-started run stops short, and the source then solves from the free stream,
// which gives the cold source's result bit for bit.
TEST(EulerSource, AWarmStartThatFailsIsSolvedAgainFromTheFreeStream) {
    const mesh::Mesh m = test::bump_channel(0, 0.1);
    aero::AeroQuery<double> low, high;
    low.mach = 0.1;
    high.mach = 0.6;
    auto iterations = [&](const euler::CaseSetup& s,
                          std::initializer_list<aero::AeroQuery<double>> qs) {
        euler::EulerSource src(m, s, "bump level 0");
        for (const auto& q : qs) (void)src.evaluate(q, {});
        return src.stats().iterations;
    };
    const euler::CaseSetup plain = channel_setup(m);
    const int n_low = iterations(plain, {low}), n_high = iterations(plain, {high});
    const int n_warm = iterations(plain, {low, high}) - n_low;
    std::printf("iterations: M 0.1 %d, M 0.6 %d, M 0.6 from M 0.1 %d\n", n_low, n_high, n_warm);
    const int limit = std::max(n_low, n_high);
    ASSERT_GT(n_warm, limit) << "the premise: the warm start needs more than the cold runs";

    euler::CaseSetup limited = plain;
    limited.solver.max_iterations = limit;
    euler::EulerSource src(m, limited, "bump level 0");
    euler::EulerSource cold(m, limited, "bump level 0");
    (void)src.evaluate(low, {});
    const aero::SourceResult r = src.evaluate(high, {});
    const aero::SourceResult c = cold.evaluate(high, {});
    const euler::EulerSourceStats st = src.stats();
    EXPECT_EQ(st.cold_retries, 1);
    EXPECT_EQ(st.warm_starts, 0);  // both solutions in the end from the free stream
    EXPECT_EQ(st.evaluations, 2);
    EXPECT_EQ(r.wind.CL, c.wind.CL);
    EXPECT_EQ(r.wind.CD, c.wind.CD);
    EXPECT_EQ(r.body.Cm, c.body.Cm);
}

TEST(EulerSource, RatesAndControlsAreInputErrors) {
    const mesh::Mesh m = test::bump_channel(0, 0.1);
    euler::EulerSource src(m, channel_setup(m), "bump level 0");
    aero::AeroQuery<double> q;
    q.mach = 0.5;
    q.q_hat = 0.01;
    EXPECT_THROW((void)src.evaluate(q, {}), InputError);
    q.q_hat = 0.0;
    q.elevator = 0.1;
    EXPECT_THROW((void)src.evaluate(q, {}), InputError);
}

}  // namespace
