// Surface snapshots of a replay (docs/replay.md, "Surface snapshots"): the steps they are taken
// at (replay::snapshot_steps), the files run_replay has its writer write into out/surface/ with
// the index at the end, a fresh start removing an earlier surface/, a stopped and resumed replay
// leaving the same files byte for byte, a writer that has nothing to write, and a bad interval.
// The source is the lattice with a stand-in writer (the Euler source's own writer is checked by
// tests/cli/replay_report_cp_test.sh).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
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

aero::AeroDatabase linear_tables() {
    aero::Table st;
    st.name = "static";
    st.kind = aero::TableKind::static_table;
    st.axes = {{aero::Axis::alpha, {-10 * deg, 10 * deg}}};
    st.columns = {"CL", "CD", "CY", "Cl", "Cm", "Cn"};
    st.values = {-0.8, 0.02, 0, 0, 0.1, 0, 0.8, 0.02, 0, 0, -0.1, 0};
    return aero::AeroDatabase({"linear", "", "test"}, aero::ForceAxes::wind,
                              aero::Extrapolation::linear, {st});
}

/// The files of a folder and their contents.
std::map<std::string, std::string> files(const fs::path& dir) {
    std::map<std::string, std::string> out;
    for (const auto& e : fs::directory_iterator(dir))
        out[e.path().filename().string()] = core::read_file(e.path());
    return out;
}

/// A stand-in snapshot: the run's step, time and lift, exactly.
bool stand_in(const aero::UnsteadyRun& run, const fs::path& file) {
    const aero::UnsteadySample& s = run.current();
    core::write_file_atomic(file, std::to_string(s.index) + "," + core::format_exact(s.t) + "," +
                                      core::format_exact(s.wind.CL) + "\n");
    return true;
}

replay::ReplaySettings settings() {
    replay::ReplaySettings s;
    s.dt = 0.05;
    s.span = 6.0;
    s.chord = 1.0;
    s.viscous = false;
    s.checkpoint_seconds = 0.0;
    s.snapshot_every = 0.4;
    s.write_snapshot = stand_in;
    return s;
}

}  // namespace

TEST(SnapshotsTest, Steps) {
    using V = std::vector<int>;
    EXPECT_EQ(replay::snapshot_steps(200, 0.01, 0.25), (V{0, 25, 50, 75, 100, 125, 150, 175, 200}));
    // 0.3 s steps, every second: the first step at or past 1, 2 and 3 s (t = 1.2, 2.1, 3.0).
    EXPECT_EQ(replay::snapshot_steps(10, 0.3, 1.0), (V{0, 4, 7, 10}));
    // The last step always; an interval longer than the replay: the first and the last.
    EXPECT_EQ(replay::snapshot_steps(7, 0.3, 1.0), (V{0, 4, 7}));
    EXPECT_EQ(replay::snapshot_steps(5, 0.1, 10.0), (V{0, 5}));
    EXPECT_TRUE(replay::snapshot_steps(5, 0.1, 0.0).empty());
}

TEST(SnapshotsTest, WrittenIndexedAndTheSameAfterAResume) {
    const replay::Trajectory tr = turning_flight(true);  // 3 s: 60 steps of 0.05 s
    const aero::AeroDatabase db = linear_tables();
    const fs::path base = fs::temp_directory_path() / "manta_replay_test_snapshots";
    fs::remove_all(base);
    // Uninterrupted, into a folder with a snapshot of an earlier replay (removed).
    fs::create_directories(base / "full" / "surface");
    core::write_file_atomic(base / "full" / "surface" / "step-999999.csv", "stale\n");
    const replay::ReplayOutcome full =
        replay::run_replay(wing(), db, tr, settings(), base / "full");
    ASSERT_TRUE(full.completed);
    ASSERT_EQ(full.steps, 60);
    const auto want = files(base / "full" / "surface");
    // Steps 0, 8 (0.4 s), 16, 24, 32, 40, 48, 56 and the last, 60; and the index.
    EXPECT_EQ(want.size(), 10u);
    EXPECT_EQ(want.count("step-999999.csv"), 0u);
    EXPECT_EQ(want.at("step-000008.csv").substr(0, 5), "8,0.9");  // t0 = 0.5 s
    EXPECT_EQ(want.at("index.csv").substr(0, want.at("index.csv").find('\n')), "step,t,file");
    EXPECT_NE(want.at("index.csv").find("\n60,3.5"), std::string::npos);
    EXPECT_NE(want.at("index.csv").find(",step-000060.csv\n"), std::string::npos);
    EXPECT_EQ(full.snapshots, 9);
    EXPECT_EQ(full.summary["snapshots"]["count"], 9);
    EXPECT_EQ(full.summary["snapshots"]["written_here"], 9);
    // Stopped after 21 steps (checkpoint at step 21), then resumed: the same files.
    replay::ReplaySettings s = settings();
    s.stop_after_steps = 21;
    const replay::ReplayOutcome stopped = replay::run_replay(wing(), db, tr, s, base / "resumed");
    ASSERT_FALSE(stopped.completed);
    EXPECT_EQ(files(base / "resumed" / "surface").size(), 3u);  // steps 0, 8, 16
    const replay::ReplayOutcome resumed =
        replay::run_replay(wing(), db, tr, settings(), base / "resumed");
    ASSERT_TRUE(resumed.completed);
    EXPECT_EQ(resumed.resumed_from, 21);
    EXPECT_EQ(resumed.summary["snapshots"]["written_here"], 6);
    EXPECT_EQ(files(base / "resumed" / "surface"), want);
    EXPECT_EQ(core::read_file(base / "resumed" / "comparison.csv"),
              core::read_file(base / "full" / "comparison.csv"));
    // Another interval is another replay: its checkpoint is refused.
    s.stop_after_steps = 5;
    (void)replay::run_replay(wing(), db, tr, s, base / "other");
    replay::ReplaySettings other = settings();
    other.snapshot_every = 0.5;
    EXPECT_THROW((void)replay::run_replay(wing(), db, tr, other, base / "other"), InputError);
}

TEST(SnapshotsTest, NoneWithoutASurfaceOrAWriterAndABadIntervalRefused) {
    const replay::Trajectory tr = turning_flight(true);
    const aero::AeroDatabase db = linear_tables();
    const fs::path base = fs::temp_directory_path() / "manta_replay_test_snapshots_none";
    fs::remove_all(base);
    replay::ReplaySettings s = settings();
    s.write_snapshot = [](const aero::UnsteadyRun&, const fs::path&) { return false; };
    const replay::ReplayOutcome a = replay::run_replay(wing(), db, tr, s, base / "a");
    EXPECT_FALSE(fs::exists(base / "a" / "surface" / "index.csv"));
    EXPECT_TRUE(a.summary["snapshots"].is_null());
    s.write_snapshot = nullptr;
    const replay::ReplayOutcome b = replay::run_replay(wing(), db, tr, s, base / "b");
    EXPECT_FALSE(fs::exists(base / "b" / "surface"));
    EXPECT_EQ(b.snapshots, 0);
    s = settings();
    s.snapshot_every = -1.0;
    try {
        (void)replay::run_replay(wing(), db, tr, s, base / "c");
        FAIL() << "a negative interval was taken";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("snapshot every -1 s; expected a time > 0 s"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_FALSE(fs::exists(base / "c"));
}
