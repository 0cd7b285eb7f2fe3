// VlmSource: the vortex lattice behind aero::AeroSource (steady evaluation, viscous drag,
// fingerprint, replay along a motion).

#include <gtest/gtest.h>

#include <cmath>

#include "manta/aero/motion.hpp"
#include "manta/core/error.hpp"
#include "manta/vlm/source.hpp"

namespace {

using namespace manta;
using Eigen::Vector3d;

vlm::Model wing_and_tail(double tail_incidence = 0.0) {
    vlm::Model m;
    m.name = "wing-tail";
    m.reference = {6.0, 6.0, 1.0, Vector3d(0.25, 0, 0)};
    vlm::Surface w;
    w.name = "wing";
    w.n_chord = 4;
    w.n_span = 8;
    w.y_duplicate = 0.0;
    w.component = 1;
    vlm::Section r, t;
    r.chord = 1.0;
    t.chord = 1.0;
    t.leading_edge = Vector3d(0, 3, 0);
    w.sections = {r, t};
    vlm::Surface h;
    h.name = "tail";
    h.n_chord = 3;
    h.n_span = 4;
    h.y_duplicate = 0.0;
    h.component = 2;
    vlm::Section hr, ht;
    hr.leading_edge = Vector3d(4, 0, 0.3);
    hr.chord = 0.5;
    hr.incidence = tail_incidence;
    ht.leading_edge = Vector3d(4, 1, 0.3);
    ht.chord = 0.5;
    ht.incidence = tail_incidence;
    vlm::SectionControl e;
    e.name = "elevator";
    e.hinge_chord_fraction = 0.7;
    hr.controls = {e};
    ht.controls = {e};
    h.sections = {hr, ht};
    m.surfaces = {w, h};
    return m;
}

TEST(VlmSource, SteadyEvaluationMatchesSolver) {
    const vlm::VlmSource src(wing_and_tail());
    aero::AeroQuery<double> q;
    q.alpha = 0.05;
    q.mach = 0.3;
    q.elevator = 0.1;
    const auto r = src.evaluate(q, {});
    vlm::FlowState s;
    s.alpha = 0.05;
    s.deflection = Eigen::VectorXd::Constant(1, 0.1);
    const auto ref = src.solver(0.3)->solve(s);
    EXPECT_DOUBLE_EQ(r.wind.CL, ref.CL);
    EXPECT_DOUBLE_EQ(r.body.Cm, ref.body.Cm);
    EXPECT_EQ(r.CD_profile, 0.0);  // no geometry: no viscous estimate
    // The elevator of the query reaches the lattice: trailing edge down, nose down.
    aero::AeroQuery<double> q0 = q;
    q0.elevator = 0.0;
    EXPECT_LT(r.body.Cm, src.evaluate(q0, {}).body.Cm);
}

TEST(VlmSource, FingerprintFollowsTheModel) {
    const vlm::VlmSource a(wing_and_tail()), b(wing_and_tail()), c(wing_and_tail(0.01));
    EXPECT_EQ(a.fingerprint(), b.fingerprint());
    EXPECT_NE(a.fingerprint(), c.fingerprint());
    EXPECT_EQ(a.name(), "vlm");
}

// A motion at constant attitude: the replay (default wake, convected with the free stream)
// settles on the source's steady coefficients, whose trailing legs follow the free stream too
// (MANTA issue 16: with the steady legs along body x, Cm differed by 4 % on this model).
TEST(VlmSource, ReplayOfASteadyMotionGivesTheSteadyLoads) {
    for (const vlm::TrailingLegs legs :
         {vlm::TrailingLegs::freestream, vlm::TrailingLegs::body_axis}) {
        SCOPED_TRACE(legs == vlm::TrailingLegs::freestream ? "freestream legs" : "body-axis legs");
        vlm::VlmSource src(wing_and_tail(), std::nullopt, {}, legs);
        aero::Motion m;
        for (int i = 0; i <= 20; ++i) {
            m.t.push_back(0.01 * i);
            for (auto& p : m.position) p.push_back(0.0);
            m.angles[0].push_back(0.0);
            m.angles[1].push_back(0.05);
            m.angles[2].push_back(0.0);
        }
        m.add_mode("elevator", std::vector<double>(21, 0.0));
        m.add_mode("aileron", std::vector<double>(21, 0.0));
        m.add_mode("rudder", std::vector<double>(21, 0.0));
        m.metadata.v0 = 50.0;
        double last = -1.0;
        const auto h = src.replay(m, [&](double f) { last = f; });
        ASSERT_GE(h.t.size(), 2u);
        EXPECT_NEAR(last, 1.0, 1e-12);
        aero::AeroQuery<double> q;
        q.alpha = 0.05;
        const auto st = src.evaluate(q, {});
        EXPECT_NEAR(h.wind.back().CL, st.wind.CL, 0.01 * st.wind.CL);
        EXPECT_NEAR(h.body.back().Cm, st.body.Cm, 0.02 * std::abs(st.body.Cm) + 1e-4);
    }
}

// Which legs a source takes unless told (vlm::default_trailing_legs): free stream with a MANTA
// geometry, body x without one (AVL files, AVL's convention), with the matching unsteady wake;
// the choice changes the results, so it is part of the fingerprint (a table store keyed by it
// never mixes the two).
TEST(VlmSource, TrailingLegsByDefaultAndInTheFingerprint) {
    EXPECT_EQ(vlm::default_trailing_legs(true), vlm::TrailingLegs::freestream);
    EXPECT_EQ(vlm::default_trailing_legs(false), vlm::TrailingLegs::body_axis);
    const vlm::VlmSource plain(wing_and_tail());
    EXPECT_EQ(plain.trailing_legs(), vlm::TrailingLegs::body_axis);
    EXPECT_EQ(plain.unsteady_options().wake, vlm::WakeModel::planar);
    const vlm::VlmSource bent(wing_and_tail(), std::nullopt, {}, vlm::TrailingLegs::freestream);
    EXPECT_EQ(bent.trailing_legs(), vlm::TrailingLegs::freestream);
    EXPECT_EQ(bent.unsteady_options().wake, vlm::WakeModel::prescribed);
    EXPECT_NE(plain.fingerprint(), bent.fingerprint());
    aero::AeroQuery<double> q;
    q.alpha = 0.17;
    q.mach = 0.3;
    // At 10 deg the two legs give different moments on a wing with a tail behind it.
    EXPECT_GT(std::abs(plain.evaluate(q, {}).body.Cm - bent.evaluate(q, {}).body.Cm), 1e-4);
}

}  // namespace
