// The replay against the tables (docs/replay.md) on a small wing + tail vortex lattice whose
// tables are made from the same lattice's steady solutions, so that differences are the
// unsteady physics and the method, not two different aerodynamic models:
//  - steady trimmed flight: replay = table to the source's own precision (the unsteady lattice
//    in steady flight against the steady lattice: near-field against Trefftz-plane drag, ring
//    wake of finite length against horseshoes; Katz & Plotkin, Low-Speed Aerodynamics, 2nd ed.
//    2001, sec. 13.x: the unsteady method tends to the steady one as the wake grows);
//  - slow pitch oscillation (reduced frequency k = omega c / 2V = 0.02): replay = table plus
//    dynamic derivatives (quasi-steady theory holds for k << 0.1, e.g. Etkin & Reid, Dynamics of
//    Flight, 3rd ed. 1996, sec. 5.9), and the dynamic derivatives bring the table closer;
//  - a synthetic error planted in the table is flagged where the manoeuvre crosses it;
//  - a replay stopped after k steps and run again continues from its checkpoint and writes the
//    same comparison.csv byte for byte;
//  - a source that cannot move: one-line InputError, nothing written.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <thread>
#include <vector>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/replay/replay.hpp"
#include "manta/vlm/source.hpp"

namespace {

using namespace manta;
using Eigen::Vector3d;
namespace fs = std::filesystem;
constexpr double deg = std::numbers::pi / 180.0;
constexpr double mach = 0.1;

vlm::Model wing_and_tail() {
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
    ht.leading_edge = Vector3d(4, 1, 0.3);
    ht.chord = 0.5;
    vlm::SectionControl e;
    e.name = "elevator";
    e.hinge_chord_fraction = 0.7;
    hr.controls = {e};
    ht.controls = {e};
    h.sections = {hr, ht};
    m.surfaces = {w, h};
    return m;
}

const vlm::VlmSource& source() {
    static const vlm::VlmSource s(wing_and_tail());
    return s;
}

/// Tables of the steady lattice: static over alpha -6..10 deg (1 deg), elevator increments,
/// and (with `dynamic`) CL_q, Cm_q by central differences in q_hat. `planted` is added to Cm at
/// alpha = 3 and 4 deg.
aero::AeroDatabase tables(bool dynamic, double planted = 0.0) {
    std::vector<double> alpha;
    for (int a = -6; a <= 10; ++a) alpha.push_back(a * deg);
    auto eval = [](double a, double de, double qh) {
        aero::AeroQuery<double> q;
        q.alpha = a;
        q.mach = mach;
        q.elevator = de;
        q.q_hat = qh;
        const aero::SourceResult r = source().evaluate(q, {});
        return std::array<double, 6>{r.wind.CL, r.wind.CD, r.wind.CY,
                                     r.body.Cl, r.body.Cm, r.body.Cn};
    };
    std::vector<aero::Table> ts;
    aero::Table st;
    st.name = "static";
    st.kind = aero::TableKind::static_table;
    st.axes = {{aero::Axis::alpha, alpha}};
    st.columns = {"CL", "CD", "CY", "Cl", "Cm", "Cn"};
    for (const double a : alpha) {
        auto c = eval(a, 0.0, 0.0);
        if (std::abs(a - 3 * deg) < 1e-9 || std::abs(a - 4 * deg) < 1e-9) c[4] += planted;
        st.values.insert(st.values.end(), c.begin(), c.end());
    }
    ts.push_back(st);
    aero::Table ct;
    ct.name = "elevator";
    ct.kind = aero::TableKind::control;
    const std::vector<double> de{-10 * deg, -5 * deg, 0.0, 5 * deg, 10 * deg};
    ct.axes = {{aero::Axis::alpha, {-6 * deg, 2 * deg, 10 * deg}}, {aero::Axis::elevator, de}};
    ct.columns = {"CL", "CD", "Cm"};
    for (const double a : ct.axes[0].breakpoints)
        for (const double d : de) {
            const auto c = eval(a, d, 0.0), c0 = eval(a, 0.0, 0.0);
            ct.values.insert(ct.values.end(), {c[0] - c0[0], c[1] - c0[1], c[4] - c0[4]});
        }
    ts.push_back(ct);
    if (dynamic) {
        aero::Table dt;
        dt.name = "dynamic";
        dt.kind = aero::TableKind::dynamic;
        dt.axes = {{aero::Axis::alpha, {-6 * deg, 2 * deg, 10 * deg}}};
        dt.columns = {"CL_q", "Cm_q"};
        const double h = 0.01;
        for (const double a : dt.axes[0].breakpoints) {
            const auto p = eval(a, 0.0, h), m = eval(a, 0.0, -h);
            dt.values.insert(dt.values.end(), {(p[0] - m[0]) / (2 * h), (p[4] - m[4]) / (2 * h)});
        }
        ts.push_back(dt);
    }
    return {{"lattice tables", "", "vlm"},
            aero::ForceAxes::wind,
            aero::Extrapolation::linear,
            std::move(ts)};
}

/// Level flight at 30 m/s with theta = alpha = a(t), q = a'(t), elevator de.
replay::Trajectory level_flight(double duration, double dt_rows, double (*a)(double),
                                double (*a_dot)(double), double de) {
    std::ostringstream s;
    s.precision(17);
    s << "# manoeuvre: test\nt,x,y,z,phi,theta,psi,V,alpha,beta,p,q,r,elevator,aileron,rudder,"
         "mach\n";
    const int n = static_cast<int>(std::lround(duration / dt_rows));
    for (int i = 0; i <= n; ++i) {
        const double t = i * dt_rows;
        s << t << ',' << 30.0 * t << ",0,-1000,0," << a(t) << ",0,30," << a(t) << ",0,0,"
          << a_dot(t) << ",0," << de << ",0,0," << mach << '\n';
    }
    return replay::parse_trajectory(s.str(), "test.csv");
}

double steady_alpha(double) {
    return 3 * deg;
}
double zero(double) {
    return 0.0;
}
constexpr double omega = 0.04 * 30.0;  // k = omega c / 2V = 0.02
double pitch(double t) {
    return 2 * deg + 2 * deg * std::sin(omega * t);
}
double pitch_rate(double t) {
    return 2 * deg * omega * std::cos(omega * t);
}

replay::ReplaySettings settings(double dt) {
    replay::ReplaySettings s;
    s.dt = dt;
    s.span = 6.0;
    s.chord = 1.0;
    s.viscous = false;
    s.checkpoint_seconds = 0.0;
    return s;
}

fs::path fresh(const std::string& name) {
    const fs::path p = fs::temp_directory_path() / ("manta_replay_test_" + name);
    fs::remove_all(p);
    return p;
}

TEST(Replay, SteadyTrimmedFlightEqualsTheTable) {
    const replay::Trajectory tr = level_flight(1.0, 0.05, steady_alpha, zero, -2 * deg);
    const fs::path out = fresh("steady");
    const replay::ReplayOutcome oc =
        replay::run_replay(source(), tables(true), tr, settings(0.02), out);
    ASSERT_TRUE(oc.completed);
    EXPECT_EQ(oc.steps, 50);
    const auto& c = oc.summary["coefficients"];
    // Measured (docs/replay.md, "Validation"): CL 8.0e-4 (0.35 % of CL), CD 1.2e-4, Cm 3.4e-3,
    // constant in time: the steady bias of rings shed 0.6 c per step against horseshoes.
    EXPECT_LT(c["CL"]["max_abs"].get<double>(), 2e-3) << c.dump();
    EXPECT_LT(c["CD"]["max_abs"].get<double>(), 2e-3) << c.dump();
    EXPECT_LT(c["Cm"]["max_abs"].get<double>(), 5e-3) << c.dump();
    for (const char* k : {"CY", "Cl", "Cn"}) EXPECT_LT(c[k]["max_abs"].get<double>(), 1e-9) << k;
    EXPECT_GT(c["CL"]["mean_table"].get<double>(), 0.1);  // a real lift, not zeros
    EXPECT_EQ(oc.summary["flags"].size(), 0u);
    EXPECT_TRUE(fs::exists(out / "motion.csv"));
    EXPECT_TRUE(fs::exists(out / "comparison.csv"));
    EXPECT_FALSE(fs::exists(out / "checkpoint"));
    std::cout << "steady: " << c.dump() << "\n";
}

TEST(Replay, SlowPitchOscillationMatchesTablePlusDynamicDerivatives) {
    const replay::Trajectory tr = level_flight(6.0, 0.05, pitch, pitch_rate, 0.0);
    const replay::ReplayOutcome with =
        replay::run_replay(source(), tables(true), tr, settings(0.04), fresh("pitch_dyn"));
    const replay::ReplayOutcome without =
        replay::run_replay(source(), tables(false), tr, settings(0.04), fresh("pitch_static"));
    const auto& a = with.summary["coefficients"];
    const auto& b = without.summary["coefficients"];
    std::cout << "pitch with dynamic: " << a.dump() << "\nwithout: " << b.dump() << "\n";
    // CL swings by about 0.3 (4 deg); agreement within a few per cent of the swing.
    EXPECT_LT(a["CL"]["rms"].get<double>(), 0.01);
    EXPECT_LT(a["Cm"]["rms"].get<double>(), 0.01);
    // Pitch damping: the dynamic derivatives bring Cm closer to the replay.
    EXPECT_LT(a["Cm"]["rms"].get<double>(), 0.7 * b["Cm"]["rms"].get<double>());
}

TEST(Replay, PlantedTableErrorIsFlagged) {
    const replay::Trajectory tr = level_flight(6.0, 0.05, pitch, pitch_rate, 0.0);
    replay::ReplaySettings s = settings(0.04);
    const replay::ReplayOutcome clean =
        replay::run_replay(source(), tables(true), tr, s, fresh("clean"));
    for (const auto& f : clean.summary["flags"])
        for (const auto& c : f["coefficients"]) EXPECT_NE(c.get<std::string>(), "Cm") << f.dump();
    const replay::ReplayOutcome bad =
        replay::run_replay(source(), tables(true, 0.05), tr, s, fresh("planted"));
    const auto& flags = bad.summary["flags"];
    ASSERT_GE(flags.size(), 1u) << bad.summary.dump();
    for (const auto& f : flags) {
        bool cm = false;
        for (const auto& c : f["coefficients"]) cm = cm || c.get<std::string>() == "Cm";
        EXPECT_TRUE(cm) << f.dump();
        // The error lives at alpha 3 to 4 deg (+- one grid cell of interpolation).
        EXPECT_GT(f["state"]["alpha_max"].get<double>(), 2 * deg) << f.dump();
        EXPECT_LT(std::abs(f["max_diff"]["Cm"].get<double>() + 0.05), 0.02) << f.dump();
        EXPECT_FALSE(f["reasons"].empty());
    }
    EXPECT_GT(bad.summary["flagged_steps"].get<int>(), 10);
}

TEST(Replay, StoppedReplayResumesToTheSameResultBitForBit) {
    const replay::Trajectory tr = level_flight(3.0, 0.05, pitch, pitch_rate, 0.0);
    const aero::AeroDatabase db = tables(true);
    const fs::path ref = fresh("uninterrupted"), out = fresh("resumed");
    const replay::ReplayOutcome full = replay::run_replay(source(), db, tr, settings(0.04), ref);
    ASSERT_TRUE(full.completed);
    replay::ReplaySettings s = settings(0.04);
    s.stop_after_steps = 29;
    const replay::ReplayOutcome first = replay::run_replay(source(), db, tr, s, out);
    EXPECT_FALSE(first.completed);
    EXPECT_TRUE(fs::exists(out / "checkpoint" / "checkpoint.json"));
    EXPECT_FALSE(fs::exists(out / "comparison.csv"));  // never a half-written output
    // Another time step: the checkpoint is not this replay's.
    try {
        (void)replay::run_replay(source(), db, tr, settings(0.05), out);
        ADD_FAILURE() << "mismatched checkpoint accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("--restart"), std::string::npos) << e.what();
    }
    s.stop_after_steps = -1;
    const replay::ReplayOutcome second = replay::run_replay(source(), db, tr, s, out);
    ASSERT_TRUE(second.completed);
    EXPECT_EQ(second.resumed_from, 29);
    EXPECT_EQ(second.summary["resumed_from_step"].get<int>(), 29);
    EXPECT_EQ(core::read_file(out / "comparison.csv"), core::read_file(ref / "comparison.csv"));
    EXPECT_EQ(core::read_file(out / "motion.csv"), core::read_file(ref / "motion.csv"));
    EXPECT_EQ(second.summary["coefficients"].dump(), full.summary["coefficients"].dump());
    EXPECT_EQ(second.summary["flags"].dump(), full.summary["flags"].dump());
    EXPECT_FALSE(fs::exists(out / "checkpoint"));
    // --restart discards a checkpoint.
    s.stop_after_steps = 5;
    (void)replay::run_replay(source(), db, tr, s, out);
    s.stop_after_steps = -1;
    s.restart = true;
    EXPECT_EQ(replay::run_replay(source(), db, tr, s, out).resumed_from, -1);
}

/// A source with only steady evaluations (like the Euler solver today).
class SteadyOnly : public aero::AeroSource {
public:
    [[nodiscard]] std::string name() const override { return "euler"; }
    [[nodiscard]] std::string fingerprint() const override { return "x"; }
    [[nodiscard]] aero::SourceResult evaluate(const aero::AeroQuery<double>&,
                                              const aero::FlowConditions&) const override {
        return {};
    }
};

/// The lattice whose unsteady run spends `start_s` of wall time on its start (as the Euler
/// source's steady solution does, lazily at the first `current()`), its steps as the lattice's.
class SlowStart : public aero::AeroSource {
public:
    explicit SlowStart(double start_s) : start_s_(start_s) {}
    std::string name() const override { return "slow-start"; }
    std::string fingerprint() const override { return source().fingerprint(); }
    aero::SourceResult evaluate(const aero::AeroQuery<double>& q,
                                const aero::FlowConditions& c) const override {
        return source().evaluate(q, c);
    }
    bool unsteady() const override { return true; }
    std::unique_ptr<aero::UnsteadyRun> start_unsteady(
        const aero::Motion& m, const aero::UnsteadySettings& s) const override {
        return std::make_unique<Run>(source().start_unsteady(m, s), start_s_);
    }

private:
    struct Run : aero::UnsteadyRun {
        Run(std::unique_ptr<aero::UnsteadyRun> r, double s) : run(std::move(r)), start_s(s) {}
        const aero::UnsteadySample& current() const override {
            if (!started) {
                std::this_thread::sleep_for(std::chrono::duration<double>(start_s));
                started = true;
            }
            return run->current();
        }
        const aero::UnsteadySample& step() override {
            (void)current();
            return run->step();
        }
        bool finished() const override { return run->finished(); }
        int n_steps() const override { return run->n_steps(); }
        double dt() const override { return run->dt(); }
        void save(const fs::path& f) const override { run->save(f); }
        void restore(const fs::path& f) override {
            run->restore(f);
            started = true;
        }
        std::unique_ptr<aero::UnsteadyRun> run;
        double start_s;
        mutable bool started = false;
    };
    double start_s_;
};

TEST(Replay, TimeLeftCountsTheStepsNotTheSourcesStart) {
    // A start of 2 s before 50 steps of a few milliseconds: the time left after the first step
    // is the steps' (under a second), not the start's share spread over them (2 s x 49 = 98 s).
    const replay::Trajectory tr = level_flight(1.0, 0.05, steady_alpha, zero, 0.0);
    replay::ReplaySettings s = settings(0.02);
    std::vector<replay::ReplayProgress> seen;
    s.progress = [&](const replay::ReplayProgress& p) { seen.push_back(p); };
    const replay::ReplayOutcome oc =
        replay::run_replay(SlowStart(2.0), tables(false), tr, s, fresh("slow_start"));
    ASSERT_TRUE(oc.completed);
    ASSERT_EQ(seen.size(), 50u);
    EXPECT_EQ(seen.front().step, 1);
    EXPECT_GE(seen.front().elapsed_s, 2.0);
    EXPECT_LT(seen.front().remaining_s, 10.0) << "the start counted as a step's cost";
    EXPECT_EQ(seen.back().remaining_s, 0.0);
}

TEST(Replay, SourceThatCannotMoveIsAOneLineErrorAndWritesNothing) {
    const replay::Trajectory tr = level_flight(1.0, 0.05, steady_alpha, zero, 0.0);
    const fs::path out = fresh("cannot_move");
    try {
        (void)replay::run_replay(SteadyOnly(), tables(false), tr, settings(0.02), out);
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("'euler' cannot move"), std::string::npos) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos);
    }
    EXPECT_FALSE(fs::exists(out));
    // The interface's own default says the same.
    EXPECT_THROW((void)SteadyOnly().start_unsteady(aero::Motion{}, {}), InputError);
}

TEST(Replay, AutomaticPhasesOfAManoeuvre) {
    // Steady 2 s, pull-up (q = 0.2 rad/s) 3 s, roll (p = 1 rad/s) 2 s, steady 2 s.
    std::ostringstream s;
    s << "t,x,y,z,phi,theta,psi,V,alpha,beta,p,q,r,elevator,aileron,rudder\n";
    for (int i = 0; i <= 90; ++i) {
        const double t = 0.1 * i;
        const double q = t >= 2 && t < 5 ? 0.2 : 0.0, p = t >= 5 && t < 7 ? 1.0 : 0.0;
        s << t << ",0,0,-1000,0,0,0,100,0.05,0," << p << ',' << q << ",0,0,0,0\n";
    }
    const replay::Trajectory tr = replay::parse_trajectory(s.str(), "auto.csv");
    const auto phases = replay::trajectory_phases(tr);
    ASSERT_EQ(phases.size(), 4u);
    EXPECT_EQ(phases[0].name, "steady");
    EXPECT_EQ(phases[1].name, "pull-up");
    EXPECT_EQ(phases[2].name, "roll");
    EXPECT_EQ(phases[3].name, "steady");
    EXPECT_NEAR(phases[1].t_start, 2.0, 1e-9);
    EXPECT_NEAR(phases[2].t_start, 5.0, 1e-9);
}

}  // namespace
