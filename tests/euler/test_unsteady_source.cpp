/// @file test_unsteady_source.cpp
/// The Euler source along a motion (`EulerSource::start_unsteady`, unsteady_source.cpp) on the
/// meshmotion tests' flat-plate flap box (175 nodes, walls `flap` and `wall`), pitching and
/// deflecting its flap:
/// - started from the free stream, its samples are `manta cfd --motion`'s coefficients.csv on the
///   same files (the case driver, CfdCase), bit for bit once turned from rho v0^2 / 2 to
///   rho airspeed^2 / 2;
/// - started from the steady solution at a held attitude, the start sample is the steady source's
///   `evaluate` at that angle of attack (the same flow in a turned frame) and the history stays
///   there, where the free-stream start has a transient;
/// - saved at a step and restored in a new run of a new source, it steps on bit for bit;
/// - bad input (a mode with no control surface, a Mach mismatch, no v0, a time step that does not
///   divide the motion, a saved run of another motion) is a one-line InputError.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "flap_meshes.hpp"
#include "manta/aero/motion.hpp"
#include "manta/core/error.hpp"
#include "manta/euler/case.hpp"
#include "manta/euler/source.hpp"
#include "test_meshes.hpp"

namespace {

using namespace manta;
namespace fs = std::filesystem;
constexpr double deg = 3.14159265358979323846 / 180.0;

/// theta = theta0 + pitch sin(50 t), elevator = flap0 + flap sin(80 t), t = 0 ... 0.04 s in 8
/// steps of 0.005 s, v0 170 m/s, Mach 0.5 (one step is 0.85 plate chords of travel).
aero::Motion plate_motion(double theta0, double pitch, double flap0, double flap,
                          bool with_v0 = true, double mach = 0.5) {
    aero::Motion m;
    for (int i = 0; i <= 8; ++i) m.t.push_back(0.005 * i);
    for (auto& p : m.position) p.assign(m.t.size(), 0.0);
    for (auto& a : m.angles) a.assign(m.t.size(), 0.0);
    std::vector<double> e(m.t.size());
    for (std::size_t i = 0; i < m.t.size(); ++i) {
        m.angles[1][i] = theta0 + pitch * std::sin(50.0 * m.t[i]);
        e[i] = flap0 + flap * std::sin(80.0 * m.t[i]);
    }
    m.add_mode("elevator", e);
    m.add_mode("aileron", std::vector<double>(m.t.size(), 0.0));
    m.add_mode("rudder", std::vector<double>(m.t.size(), 0.0));
    if (with_v0) m.metadata.v0 = 170.0;
    m.metadata.mach = mach;
    return m;
}

/// A folder with the plate's SU2 file and its configuration (the flap hinged at x = 1 on the
/// plate as elevator unless `no_flap`; moment point at the hinge's middle; 5 inner iterations).
struct Folder {
    fs::path dir;
    Folder(const std::string& name, bool no_flap = false, const std::string& extra = {})
        : dir(fs::temp_directory_path() / name) {
        fs::remove_all(dir);
        fs::create_directories(dir);
        test::write_su2(test::flap_plate(6, 4, 4), dir / "plate.su2");
        std::ofstream(dir / "case.yaml")
            << "markers: {flap: wall, wall: wall, farfield: farfield}\n"
               "reference: {area: 1, chord: 1, span: 1, moment_point: [1, 0.5, 0]}\n"
               "unsteady: {max_inner: 5}\n"
               "output: {checkpoint_interval_s: 0, volume: false, surface: false}\n"
            << (no_flap ? ""
                        : "control_surfaces:\n  - {mode: elevator, marker: flap, hinge: [[1, "
                          "0.25, 0], [1, 0.75, 0]]}\n")
            << extra;
    }
    [[nodiscard]] fs::path mesh() const { return dir / "plate.su2"; }
    [[nodiscard]] fs::path config() const { return dir / "case.yaml"; }
    [[nodiscard]] aero::Motion motion(const aero::Motion& m, const std::string& name) const {
        aero::write_motion(dir / name, m);
        return aero::read_motion(dir / name);
    }
};

std::vector<aero::UnsteadySample> run_to_end(aero::UnsteadyRun& run) {
    std::vector<aero::UnsteadySample> out{run.current()};
    while (!run.finished()) out.push_back(run.step());
    return out;
}

void expect_same(const aero::UnsteadySample& a, const aero::UnsteadySample& b) {
    EXPECT_EQ(a.index, b.index);
    EXPECT_EQ(a.t, b.t);
    EXPECT_EQ(a.body.CX, b.body.CX);
    EXPECT_EQ(a.body.CY, b.body.CY);
    EXPECT_EQ(a.body.CZ, b.body.CZ);
    EXPECT_EQ(a.body.Cl, b.body.Cl);
    EXPECT_EQ(a.body.Cm, b.body.Cm);
    EXPECT_EQ(a.body.Cn, b.body.Cn);
    EXPECT_EQ(a.wind.CL, b.wind.CL);
    EXPECT_EQ(a.wind.CD, b.wind.CD);
    EXPECT_EQ(a.wind.CY, b.wind.CY);
    EXPECT_EQ(a.alpha, b.alpha);
    EXPECT_EQ(a.beta, b.beta);
    EXPECT_EQ(a.airspeed, b.airspeed);
}

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no InputError)";
}

TEST(EulerUnsteadySource, FreeStreamStartGivesTheCaseDriversCoefficients) {
    const Folder f("manta_euler_unsteady_source_case");
    const aero::Motion motion = f.motion(plate_motion(1 * deg, 2 * deg, 2 * deg, 3 * deg), "m.csv");
    euler::CaseInputs in;
    in.mesh = f.mesh();
    in.config = f.config();
    in.motion = f.dir / "m.csv";
    in.out = f.dir / "case";
    {
        parallel::SerialCommunicator comm;
        euler::CfdCase c(in, comm);
        (void)c.run();
    }
    const auto source = euler::EulerSource::from_files(f.mesh(), f.config());
    source->set_unsteady_start(euler::UnsteadyStart::free_stream);
    ASSERT_TRUE(source->unsteady());
    const auto run = source->start_unsteady(motion, {});
    EXPECT_EQ(run->n_steps(), 8);
    EXPECT_DOUBLE_EQ(run->dt(), 0.005);
    const std::vector<aero::UnsteadySample> s = run_to_end(*run);

    std::ifstream csv(in.out / "coefficients.csv");
    std::string line;
    std::getline(csv, line);
    ASSERT_EQ(line, "t,CL,CD,CY,Cl,Cm,Cn,CX,CZ,alpha,beta,airspeed,inner_iterations,residual_drop");
    std::size_t k = 0;
    for (; std::getline(csv, line); ++k) {
        ASSERT_LT(k, s.size());
        std::vector<double> v;
        std::stringstream ls(line);
        for (std::string cell; std::getline(ls, cell, ',');) v.push_back(std::stod(cell));
        ASSERT_EQ(v.size(), 14u);
        // coefficients.csv is on rho v0^2 / 2, the samples on rho airspeed^2 / 2.
        const double q = (170.0 / v[11]) * (170.0 / v[11]);
        const aero::UnsteadySample& x = s[k];
        EXPECT_EQ(x.index, static_cast<int>(k));
        EXPECT_EQ(x.t, v[0]);
        EXPECT_EQ(x.wind.CL, v[1] * q) << "step " << k;
        EXPECT_EQ(x.wind.CD, v[2] * q);
        EXPECT_EQ(x.wind.CY, v[3] * q);
        EXPECT_EQ(x.body.Cl, v[4] * q);
        EXPECT_EQ(x.body.Cm, v[5] * q) << "step " << k;
        EXPECT_EQ(x.body.Cn, v[6] * q);
        EXPECT_EQ(x.body.CX, v[7] * q);
        EXPECT_EQ(x.body.CZ, v[8] * q);
        EXPECT_EQ(x.alpha, v[9]);
        EXPECT_EQ(x.beta, v[10]);
        EXPECT_EQ(x.airspeed, v[11]);
    }
    EXPECT_EQ(k, 9u);
    // The flap moves: the moment changes along the motion.
    EXPECT_GT(std::abs(s[8].body.Cm - s[4].body.Cm), 1e-4);
}

TEST(EulerUnsteadySource, SteadyStartIsTheSteadySolutionAtTheFirstInstant) {
    // A held attitude of 3 deg with the flap at 0: the start is the steady flow at alpha 3 deg
    // (the source's steady evaluation on the unturned mesh, which also fills the warm-start
    // cache) and stays there; from the free stream the same motion starts with a transient.
    const Folder f("manta_euler_unsteady_source_steady");
    const aero::Motion held = f.motion(plate_motion(3 * deg, 0.0, 0.0, 0.0), "held.csv");
    const auto source = euler::EulerSource::from_files(f.mesh(), f.config());
    aero::AeroQuery<double> q;
    q.mach = 0.5;
    q.alpha = 3 * deg;
    const aero::SourceResult steady = source->evaluate(q, {});
    const int cold_iterations = source->stats().iterations;
    const auto run = source->start_unsteady(held, {});
    const std::vector<aero::UnsteadySample> s = run_to_end(*run);
    std::printf("steady: CL %.8f Cm %.8f; start: dCL %.2e dCm %.2e dCD %.2e\n", steady.wind.CL,
                steady.body.Cm, s[0].wind.CL - steady.wind.CL, s[0].body.Cm - steady.body.Cm,
                s[0].wind.CD - steady.wind.CD);
    EXPECT_NEAR(s[0].alpha, 3 * deg, 1e-15);
    EXPECT_NEAR(s[0].airspeed, 170.0, 1e-12);
    // The same flow turned by 3 deg, both converged to the steady solver's residual drop
    // (measured: 4e-8 apart in CL, 7e-8 in Cm).
    EXPECT_NEAR(s[0].wind.CL, steady.wind.CL, 1e-6);
    EXPECT_NEAR(s[0].wind.CD, steady.wind.CD, 1e-6);
    EXPECT_NEAR(s[0].body.Cm, steady.body.Cm, 1e-6);
    EXPECT_GT(std::abs(steady.wind.CL), 0.01);
    double drift = 0.0;
    for (const auto& x : s) drift = std::max(drift, std::abs(x.wind.CL - s[0].wind.CL));
    const auto cold = euler::EulerSource::from_files(f.mesh(), f.config());
    cold->set_unsteady_start(euler::UnsteadyStart::free_stream);
    const auto fr = cold->start_unsteady(held, {});
    const std::vector<aero::UnsteadySample> c = run_to_end(*fr);
    // After the first step (the free stream's step 0 carries no load at all).
    double transient = 0.0;
    for (std::size_t k = 1; k < c.size(); ++k)
        transient = std::max(transient, std::abs(c[k].wind.CL - s[0].wind.CL));
    std::printf(
        "CL drift from the start over steps 1-8: steady start %.2e, free stream %.2e "
        "(cold steady solve %d iterations)\n",
        drift, transient, cold_iterations);
    EXPECT_LT(drift, 1e-6);
    EXPECT_GT(transient, 1e-2);
}

TEST(EulerUnsteadySource, SteadyStartInASteadyDescent) {
    // Level attitude, sinking at 5 m/s (z_ref = 5 t, z down): the air meets the plate at
    // alpha = atan(5 / 170) at the airspeed sqrt(170^2 + 5^2), so the start is the steady flow at
    // that Mach number and angle (the frame moving with the plate, shifted back into the
    // flow frame), on rho airspeed^2 / 2; the history stays there.
    const Folder f("manta_euler_unsteady_source_descent");
    aero::Motion m = plate_motion(0.0, 0.0, 0.0, 0.0);
    for (std::size_t i = 0; i < m.t.size(); ++i) m.position[2][i] = 5.0 * m.t[i];
    const aero::Motion sink = f.motion(m, "sink.csv");
    const auto source = euler::EulerSource::from_files(f.mesh(), f.config());
    aero::AeroQuery<double> q;
    q.alpha = std::atan2(5.0, 170.0);
    q.mach = 0.5 * std::hypot(170.0, 5.0) / 170.0;
    const aero::SourceResult steady = source->evaluate(q, {});
    const auto run = source->start_unsteady(sink, {});
    const std::vector<aero::UnsteadySample> s = run_to_end(*run);
    EXPECT_NEAR(s[0].alpha, q.alpha, 1e-14);
    EXPECT_NEAR(s[0].airspeed, std::hypot(170.0, 5.0), 1e-11);
    std::printf("descent: steady CL %.8f; start dCL %.2e dCm %.2e; end dCL %.2e\n", steady.wind.CL,
                s[0].wind.CL - steady.wind.CL, s[0].body.Cm - steady.body.Cm,
                s[8].wind.CL - steady.wind.CL);
    EXPECT_GT(steady.wind.CL, 0.05);
    EXPECT_NEAR(s[0].wind.CL, steady.wind.CL, 1e-6);
    EXPECT_NEAR(s[0].body.Cm, steady.body.Cm, 1e-6);
    for (const auto& x : s) EXPECT_NEAR(x.wind.CL, s[0].wind.CL, 1e-5) << "step " << x.index;
}

TEST(EulerUnsteadySource, RestoredRunStepsOnBitForBit) {
    const Folder f("manta_euler_unsteady_source_restore");
    const aero::Motion motion = f.motion(plate_motion(1 * deg, 2 * deg, 2 * deg, 3 * deg), "m.csv");
    const auto source = euler::EulerSource::from_files(f.mesh(), f.config());
    const auto full = source->start_unsteady(motion, {});
    const std::vector<aero::UnsteadySample> ref = run_to_end(*full);

    const auto first = source->start_unsteady(motion, {});
    for (int k = 0; k < 3; ++k) (void)first->step();
    const fs::path file = f.dir / "state-3.bin";
    first->save(file);
    EXPECT_TRUE(fs::exists(file));
    // A new source from the same files (an empty warm-start cache) and a new run.
    const auto other = euler::EulerSource::from_files(f.mesh(), f.config());
    const auto resumed = other->start_unsteady(motion, {});
    resumed->restore(file);
    expect_same(resumed->current(), ref[3]);
    std::vector<aero::UnsteadySample> tail;
    while (!resumed->finished()) tail.push_back(resumed->step());
    ASSERT_EQ(tail.size(), 5u);
    for (std::size_t k = 0; k < tail.size(); ++k) expect_same(tail[k], ref[4 + k]);
    EXPECT_NE(ref[8].body.Cm, ref[3].body.Cm);
    // Saved at the start (before any step) and restored: the same again.
    const auto at0 = source->start_unsteady(motion, {});
    at0->save(f.dir / "state-0.bin");
    const auto r0 = other->start_unsteady(motion, {});
    r0->restore(f.dir / "state-0.bin");
    expect_same(r0->current(), ref[0]);
    expect_same(r0->step(), ref[1]);
    // Past the end: an InputError.
    EXPECT_NE(error_of([&] { (void)full->step(); }).find("past the motion's end"),
              std::string::npos);

    // A saved run of another motion, a truncated file, not a saved run: one line naming it.
    const aero::Motion other_motion =
        f.motion(plate_motion(1 * deg, 2.5 * deg, 2 * deg, 3 * deg), "m2.csv");
    const auto foreign = source->start_unsteady(other_motion, {});
    std::string e = error_of([&] { foreign->restore(file); });
    EXPECT_NE(e.find(file.string()), std::string::npos) << e;
    EXPECT_NE(e.find("another mesh, configuration, motion or time step"), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos);
    {
        std::ifstream in(file, std::ios::binary);
        const std::string all((std::istreambuf_iterator<char>(in)), {});
        std::ofstream(f.dir / "cut.bin", std::ios::binary) << all.substr(0, all.size() / 2);
        std::ofstream(f.dir / "junk.bin", std::ios::binary) << "junk";
    }
    e = error_of([&] { resumed->restore(f.dir / "cut.bin"); });
    EXPECT_NE(e.find("cut.bin: truncated"), std::string::npos) << e;
    e = error_of([&] { resumed->restore(f.dir / "junk.bin"); });
    EXPECT_NE(e.find("junk.bin: not a saved Euler-source run"), std::string::npos) << e;
}

TEST(EulerUnsteadySource, BadInputIsOneLineInputError) {
    auto one_line = [](const std::string& e, const std::string& part) {
        EXPECT_NE(e.find(part), std::string::npos) << e;
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    };
    const Folder plain("manta_euler_unsteady_source_bad", true);
    const auto source = euler::EulerSource::from_files(plain.mesh(), plain.config());
    // The elevator deflects, the configuration has no control surface for it.
    one_line(
        error_of([&] { (void)source->start_unsteady(plate_motion(0, 1 * deg, 2 * deg, 0), {}); }),
        "elevator");
    // Mach 0.6 in the motion, 0.5 in the configuration.
    const Folder mach("manta_euler_unsteady_source_mach", false, "flow: {mach: 0.5}\n");
    const auto ms = euler::EulerSource::from_files(mach.mesh(), mach.config());
    one_line(
        error_of([&] { (void)ms->start_unsteady(plate_motion(0, 1 * deg, 0, 0, true, 0.6), {}); }),
        "differs from the flow's Mach number 0.5");
    // No v0.
    one_line(
        error_of([&] { (void)source->start_unsteady(plate_motion(0, 1 * deg, 0, 0, false), {}); }),
        "no '# v0:' line");
    // A time step that does not divide the 0.04 s.
    aero::UnsteadySettings s;
    s.dt = 0.003;
    const std::string m =
        error_of([&] { (void)source->start_unsteady(plate_motion(0, 1 * deg, 0, 0), s); });
    one_line(m, "time step 0.003 s does not divide the duration 0.04 s");
    // The time step it suggests is one to use as written (all its digits): 13 steps.
    const std::size_t at = m.find("such as ");
    ASSERT_NE(at, std::string::npos) << m;
    s.dt = std::stod(m.substr(at + 8));
    EXPECT_NE(m.find("N = 13"), std::string::npos) << m;
    EXPECT_EQ(source->start_unsteady(plate_motion(0, 1 * deg, 0, 0), s)->n_steps(), 13);
    // A given time step that divides it: 16 steps.
    s.dt = 0.0025;
    EXPECT_EQ(source->start_unsteady(plate_motion(0, 1 * deg, 0, 0), s)->n_steps(), 16);
}

}  // namespace
