// A partial replay (docs/replay.md, `--until`): the trajectory cut after its first seconds as if
// the file ended there (replay::first_seconds), and run_replay on it.
//  - the rows before the cut are the file's; the last row lies at exactly t0 + S and carries the
//    C1 cubic interpolant of the trajectory there (the motion the replay follows);
//  - a cut on a row keeps that row as it is; a duration beyond the end keeps the trajectory;
//  - a duration that is not positive is a one-line InputError;
//  - run_replay with `until` takes S / dt steps and reports `until` in its summary.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <sstream>

#include "manta/core/error.hpp"
#include "manta/replay/motion_builder.hpp"
#include "manta/replay/replay.hpp"
#include "manta/vlm/source.hpp"

namespace {

using namespace manta;
namespace fs = std::filesystem;
constexpr double deg = std::numbers::pi / 180.0;

/// A banked, pitching, accelerating flight sampled every 0.05 s, with a throttle and a phase
/// column (phase 1 from t = 1 s), starting at t0 = 0.5 s; with `elevator_only` the aileron and
/// rudder stay at 0.
replay::Trajectory turning_flight(bool elevator_only = false) {
    std::ostringstream s;
    s.precision(17);
    s << "# manoeuvre: test\n# phases: a,b\n"
         "t,x,y,z,phi,theta,psi,V,alpha,beta,p,q,r,elevator,aileron,rudder,throttle,mach,phase\n";
    for (int i = 0; i <= 60; ++i) {
        const double t = 0.5 + 0.05 * i;
        const double V = 60.0 + 2.0 * t;
        s << t << ',' << 60.0 * t + t * t << ',' << 0.3 * t * t << ",-1000," << 0.4 * std::sin(t)
          << ',' << 2 * deg + 1 * deg * std::sin(2 * t) << ',' << 0.1 * t * t << ',' << V << ','
          << 3 * deg + 0.5 * deg * std::cos(t) << ',' << 0.2 * deg * t << ',' << 0.4 * std::cos(t)
          << ',' << 2 * deg * std::cos(2 * t) << ',' << 0.2 * t << ',' << -2 * deg + 1 * deg * t
          << ',' << (elevator_only ? 0.0 : 1 * deg * std::sin(3 * t)) << ','
          << (elevator_only ? 0.0 : 0.1 * deg * t) << ',' << 0.5 + 0.1 * t << ',' << V / 340.0
          << ',' << (t >= 1.0 ? 1 : 0) << '\n';
    }
    return replay::parse_trajectory(s.str(), "turn.csv");
}

TEST(FirstSecondsTest, LastRowAtTheCutFromTheInterpolant) {
    const replay::Trajectory tr = turning_flight();
    const replay::Trajectory cut = replay::first_seconds(tr, 1.23);
    ASSERT_EQ(cut.size(), 26u);  // rows 0.50 ... 1.70 and the cut at 1.73
    EXPECT_DOUBLE_EQ(cut.t.back(), 0.5 + 1.23);
    for (std::size_t i = 0; i + 1 < cut.size(); ++i) {
        EXPECT_EQ(cut.t[i], tr.t[i]);
        EXPECT_EQ(cut.V[i], tr.V[i]);
        EXPECT_EQ(cut.euler[0][i], tr.euler[0][i]);
        EXPECT_EQ(cut.controls[0][i], tr.controls[0][i]);
    }
    const aero::MotionState s = replay::trajectory_interpolant(tr).at(cut.t.back());
    const std::size_t n = cut.size() - 1;
    for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_DOUBLE_EQ(cut.position[k][n], s.position[k]);
        EXPECT_NEAR(cut.euler[k][n], s.euler[k], 1e-12);
        EXPECT_DOUBLE_EQ(cut.controls[k][n], s.modes[k]);
        EXPECT_DOUBLE_EQ(cut.rates[k][n], s.modes[7 + k]);
    }
    EXPECT_DOUBLE_EQ(cut.V[n], s.modes[3]);
    EXPECT_DOUBLE_EQ(cut.alpha[n], s.modes[4]);
    EXPECT_DOUBLE_EQ(cut.beta[n], s.modes[5]);
    EXPECT_DOUBLE_EQ(cut.mach[n], s.modes[6]);
    // Smooth columns: the cubic is close to the exact history.
    EXPECT_NEAR(cut.V[n], 60.0 + 2.0 * 1.73, 1e-9);
    EXPECT_NEAR(cut.euler[0][n], 0.4 * std::sin(1.73), 1e-6);
    EXPECT_NEAR(cut.throttle[n], 0.5 + 0.1 * 1.73, 1e-12);  // linear between its rows
    EXPECT_EQ(cut.phase[n], 1);
    EXPECT_EQ(cut.phase_names, tr.phase_names);
    EXPECT_EQ(cut.meta("manoeuvre"), "test");
}

TEST(FirstSecondsTest, OnARowBeyondTheEndAndBadDurations) {
    const replay::Trajectory tr = turning_flight();
    const replay::Trajectory on_row = replay::first_seconds(tr, 1.0);
    ASSERT_EQ(on_row.size(), 21u);
    EXPECT_EQ(on_row.t.back(), tr.t[20]);
    EXPECT_EQ(on_row.V.back(), tr.V[20]);
    EXPECT_EQ(replay::first_seconds(tr, 3.0).size(), tr.size());
    EXPECT_EQ(replay::first_seconds(tr, 100.0).size(), tr.size());
    for (const double bad : {0.0, -1.0, std::nan("")}) {
        try {
            (void)replay::first_seconds(tr, bad);
            ADD_FAILURE() << bad << " accepted";
        } catch (const InputError& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find("turn.csv"), std::string::npos) << m;
            EXPECT_EQ(m.find('\n'), std::string::npos) << m;
        }
    }
}

/// A rectangular wing with an elevator-driven flap (a lattice that moves).
const vlm::VlmSource& wing() {
    static const vlm::VlmSource src = [] {
        vlm::Model m;
        m.name = "wing";
        m.reference = {6.0, 6.0, 1.0, Eigen::Vector3d(0.25, 0, 0)};
        vlm::Surface w;
        w.name = "wing";
        w.n_chord = 3;
        w.n_span = 6;
        w.y_duplicate = 0.0;
        vlm::Section r, t;
        r.chord = 1.0;
        t.chord = 1.0;
        t.leading_edge = Eigen::Vector3d(0, 3, 0);
        vlm::SectionControl e;
        e.name = "elevator";
        e.hinge_chord_fraction = 0.7;
        r.controls = {e};
        t.controls = {e};
        w.sections = {r, t};
        m.surfaces = {w};
        return vlm::VlmSource(m);
    }();
    return src;
}

TEST(FirstSecondsTest, ReplayOfTheFirstSecondsOnly) {
    const replay::Trajectory tr = turning_flight(true);
    aero::Table st;
    st.name = "static";
    st.kind = aero::TableKind::static_table;
    st.axes = {{aero::Axis::alpha, {-10 * deg, 10 * deg}}};
    st.columns = {"CL", "CD", "CY", "Cl", "Cm", "Cn"};
    st.values = {-0.8, 0.02, 0, 0, 0.1, 0, 0.8, 0.02, 0, 0, -0.1, 0};
    const aero::AeroDatabase db({"linear", "", "test"}, aero::ForceAxes::wind,
                                aero::Extrapolation::linear, {st});
    replay::ReplaySettings s;
    s.dt = 0.04;
    s.until = 0.6;
    s.span = 6.0;
    s.chord = 1.0;
    s.viscous = false;
    s.checkpoint_seconds = 0.0;
    const fs::path out = fs::temp_directory_path() / "manta_replay_test_first_seconds";
    fs::remove_all(out);
    const replay::ReplayOutcome oc = replay::run_replay(wing(), db, tr, s, out);
    ASSERT_TRUE(oc.completed);
    EXPECT_EQ(oc.steps, 15);  // 0.6 s / 0.04 s
    EXPECT_DOUBLE_EQ(oc.summary["until"].get<double>(), 0.6);
    EXPECT_NEAR(oc.summary["duration"].get<double>(), 0.6, 1e-12);
    // The same as the replay of the cut trajectory.
    replay::ReplaySettings whole = s;
    whole.until = 0.0;
    const fs::path ref = fs::temp_directory_path() / "manta_replay_test_first_seconds_ref";
    fs::remove_all(ref);
    const replay::ReplayOutcome rc =
        replay::run_replay(wing(), db, replay::first_seconds(tr, 0.6), whole, ref);
    EXPECT_EQ(oc.summary["coefficients"].dump(), rc.summary["coefficients"].dump());
    EXPECT_TRUE(rc.summary["until"].is_null());
}

}  // namespace
