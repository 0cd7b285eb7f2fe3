/// @file test_unsteady_source_deforming.cpp
/// The Euler source along a motion (`EulerSource::start_unsteady`, unsteady_source.cpp) in the
/// deforming mesh motion of the configuration (`unsteady: {mesh_motion: deforming, rigid_radius,
/// fixed_radius}`, docs/mesh-motion.md) on the meshmotion tests' flat-plate flap box, 6 x 4 x 8
/// cells (315 nodes): the flap (marker `flap`, a wall) pitches and deflects, the rest of the plane
/// z = 0 (marker `wall`, given the role symmetry, an inviscid wall too) slides, the far field
/// stays, the nodes between blend (rigid within 0.1 m of the flap, fixed from 0.2 m on):
/// - started from the free stream, its samples are `manta cfd --motion`'s coefficients.csv on the
///   same files, bit for bit once turned from rho v0^2 / 2 to rho airspeed^2 / 2, as in the
///   rigid mode (test_unsteady_source.cpp), and they differ from the rigid mode's;
/// - saved at a step and restored in a new run of a new source, it steps on bit for bit;
/// - a saved rigid run is refused by a deforming one, and the reverse, and a deforming run of
///   other radii: one-line InputErrors naming the mesh motions.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
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

/// theta = theta0 + pitch sin(50 t), elevator = flap sin(80 t), t = 0 ... 0.04 s in 8 steps of
/// 0.005 s, v0 170 m/s, Mach 0.5 (test_unsteady_source.cpp's motion).
aero::Motion plate_motion(double theta0, double pitch, double flap) {
    aero::Motion m;
    for (int i = 0; i <= 8; ++i) m.t.push_back(0.005 * i);
    for (auto& p : m.position) p.assign(m.t.size(), 0.0);
    for (auto& a : m.angles) a.assign(m.t.size(), 0.0);
    std::vector<double> e(m.t.size());
    for (std::size_t i = 0; i < m.t.size(); ++i) {
        m.angles[1][i] = theta0 + pitch * std::sin(50.0 * m.t[i]);
        e[i] = flap * std::sin(80.0 * m.t[i]);
    }
    m.add_mode("elevator", e);
    m.add_mode("aileron", std::vector<double>(m.t.size(), 0.0));
    m.add_mode("rudder", std::vector<double>(m.t.size(), 0.0));
    m.metadata.v0 = 170.0;
    m.metadata.mach = 0.5;
    return m;
}

/// A folder with the plate's SU2 file and its configuration: the flap a wall hinged at x = 1 as
/// elevator, the rest of the plate a symmetry plane, moment point at the hinge's middle, 5 inner
/// iterations, the mesh motion `mesh_motion` ("rigid", or "deforming" with `radii`).
struct Folder {
    fs::path dir;
    Folder(const std::string& name, const std::string& mesh_motion,
           const std::string& radii = ", rigid_radius: 0.1, fixed_radius: 0.2")
        : dir(fs::temp_directory_path() / name) {
        fs::remove_all(dir);
        fs::create_directories(dir);
        test::write_su2(test::flap_plate(6, 4, 8), dir / "plate.su2");
        std::ofstream(dir / "case.yaml")
            << "markers: {flap: wall, wall: symmetry, farfield: farfield}\n"
               "reference: {area: 1, chord: 1, span: 1, moment_point: [1, 0.5, 0]}\n"
               "unsteady: {max_inner: 5, mesh_motion: "
            << mesh_motion << (mesh_motion == "deforming" ? radii : std::string()) << "}\n"
            << "output: {checkpoint_interval_s: 0, volume: false, surface: false}\n"
               "control_surfaces:\n  - {mode: elevator, marker: flap, hinge: [[1, 0.25, 0], [1, "
               "0.75, 0]]}\n";
    }
    [[nodiscard]] fs::path mesh() const { return dir / "plate.su2"; }
    [[nodiscard]] fs::path config() const { return dir / "case.yaml"; }
    [[nodiscard]] aero::Motion motion(const aero::Motion& m, const std::string& name) const {
        aero::write_motion(dir / name, m);
        return aero::read_motion(dir / name);
    }
    [[nodiscard]] std::unique_ptr<euler::EulerSource> source(
        euler::UnsteadyStart start = euler::UnsteadyStart::steady) const {
        auto s = euler::EulerSource::from_files(mesh(), config());
        s->set_unsteady_start(start);
        return s;
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

TEST(EulerUnsteadySourceDeforming, FreeStreamStartGivesTheCaseDriversCoefficients) {
    const Folder f("manta_euler_unsteady_source_deforming_case", "deforming");
    const aero::Motion motion = f.motion(plate_motion(1 * deg, 2 * deg, 3 * deg), "m.csv");
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
    const auto source = f.source(euler::UnsteadyStart::free_stream);
    const auto run = source->start_unsteady(motion, {});
    EXPECT_EQ(run->n_steps(), 8);
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
        EXPECT_EQ(x.wind.CD, v[2] * q) << "step " << k;
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

    // The rigid mode on the same mesh, configuration and motion moves the far field with the
    // plate: another flow, other coefficients at every step after the first.
    const Folder r("manta_euler_unsteady_source_deforming_rigid", "rigid");
    const auto rigid_source = r.source(euler::UnsteadyStart::free_stream);
    const auto rigid = rigid_source->start_unsteady(motion, {});
    const std::vector<aero::UnsteadySample> g = run_to_end(*rigid);
    ASSERT_EQ(g.size(), s.size());
    double d_cl = 0.0, d_cm = 0.0, cl = 0.0;
    for (std::size_t j = 1; j < s.size(); ++j) {
        d_cl = std::max(d_cl, std::abs(s[j].wind.CL - g[j].wind.CL));
        d_cm = std::max(d_cm, std::abs(s[j].body.Cm - g[j].body.Cm));
        cl = std::max(cl, std::abs(s[j].wind.CL));
    }
    std::printf(
        "deforming vs rigid over steps 1-8: max |dCL| %.3e, max |dCm| %.3e (max |CL| %.4f)\n", d_cl,
        d_cm, cl);
    EXPECT_GT(d_cl, 1e-6);
    EXPECT_GT(d_cm, 1e-6);
    // The flap moves: the moment changes along the motion.
    EXPECT_GT(std::abs(s[8].body.Cm - s[4].body.Cm), 1e-4);
}

TEST(EulerUnsteadySourceDeforming, RestoredRunStepsOnBitForBit) {
    // The default start: the steady solution on the mesh as deformed at t0 (1 deg nose up).
    const Folder f("manta_euler_unsteady_source_deforming_restore", "deforming");
    const aero::Motion motion = f.motion(plate_motion(1 * deg, 2 * deg, 3 * deg), "m.csv");
    const auto source = f.source();
    const auto full = source->start_unsteady(motion, {});
    const std::vector<aero::UnsteadySample> ref = run_to_end(*full);

    const auto first = source->start_unsteady(motion, {});
    for (int k = 0; k < 3; ++k) (void)first->step();
    const fs::path file = f.dir / "state-3.bin";
    first->save(file);
    // A new source from the same files (an empty warm-start cache) and a new run.
    const auto other = f.source();
    const auto resumed = other->start_unsteady(motion, {});
    resumed->restore(file);
    expect_same(resumed->current(), ref[3]);
    std::vector<aero::UnsteadySample> tail;
    while (!resumed->finished()) tail.push_back(resumed->step());
    ASSERT_EQ(tail.size(), 5u);
    for (std::size_t k = 0; k < tail.size(); ++k) expect_same(tail[k], ref[4 + k]);
    EXPECT_NE(ref[8].body.Cm, ref[3].body.Cm);
    std::printf("deforming, steady start: CL %.6f Cm %.6f at t0, CL %.6f Cm %.6f at t = 0.04 s\n",
                ref[0].wind.CL, ref[0].body.Cm, ref[8].wind.CL, ref[8].body.Cm);
}

TEST(EulerUnsteadySourceDeforming, SavedRunOfAnotherMeshMotionIsOneLineInputError) {
    const Folder d("manta_euler_unsteady_source_deforming_fp", "deforming");
    const Folder r("manta_euler_unsteady_source_deforming_fp_rigid", "rigid");
    const Folder o("manta_euler_unsteady_source_deforming_fp_radii", "deforming",
                   ", fixed_radius: 0.24");
    const aero::Motion motion = d.motion(plate_motion(1 * deg, 2 * deg, 3 * deg), "m.csv");
    const auto ds = d.source(euler::UnsteadyStart::free_stream);
    const auto rs = r.source(euler::UnsteadyStart::free_stream);
    const auto os = o.source(euler::UnsteadyStart::free_stream);
    const auto dr = ds->start_unsteady(motion, {});
    const auto rr = rs->start_unsteady(motion, {});
    const auto orun = os->start_unsteady(motion, {});
    dr->save(d.dir / "deforming.bin");
    rr->save(r.dir / "rigid.bin");
    auto one_line = [](const std::string& e, const std::vector<std::string>& parts) {
        for (const auto& p : parts) EXPECT_NE(e.find(p), std::string::npos) << e;
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    };
    const std::string deforming_words = "deforming (rigid_radius 0.1 m, fixed_radius 0.2 m)";
    // A saved rigid run in a deforming one.
    one_line(error_of([&] { dr->restore(r.dir / "rigid.bin"); }),
             {(r.dir / "rigid.bin").string(), "a run of unsteady.mesh_motion rigid",
              "this run's configuration has " + deforming_words});
    // A saved deforming run in a rigid one.
    one_line(
        error_of([&] { rr->restore(d.dir / "deforming.bin"); }),
        {(d.dir / "deforming.bin").string(), "a run of unsteady.mesh_motion " + deforming_words,
         "this run's configuration has rigid"});
    // A deforming run of other radii (rigid_radius the default).
    one_line(
        error_of([&] { orun->restore(d.dir / "deforming.bin"); }),
        {"a run of unsteady.mesh_motion " + deforming_words,
         "this run's configuration has deforming (rigid_radius default, fixed_radius 0.24 m)"});
    // Each restores its own.
    EXPECT_NO_THROW(dr->restore(d.dir / "deforming.bin"));
    EXPECT_NO_THROW(rr->restore(r.dir / "rigid.bin"));
}

}  // namespace
